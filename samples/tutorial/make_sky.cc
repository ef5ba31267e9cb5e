// tessera-tutorial-sky FILE: writes the environment map of the tutorial's steps 5 to 11
// (tutorial/sky.h) to an HDR file. The OptiX SDK ships a photograph (CedarCity.hdr); Tessera makes
// its own at build time so that the repository carries no image, and the tutorial loads it
// through OpenImageIO like any file.
#include <OpenImageIO/imageio.h>

#include <cstdio>
#include <vector>

#include "tutorial/sky.h"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: tessera-tutorial-sky FILE.hdr\n");
    return 2;
  }
  using tessera::tutorial::kSkyHeight;
  using tessera::tutorial::kSkyWidth;
  const std::vector<float> pixels = tessera::tutorial::SkyPixels();
  auto out = OIIO::ImageOutput::create(argv[1]);
  if (!out ||
      !out->open(argv[1], OIIO::ImageSpec(kSkyWidth, kSkyHeight, 3, OIIO::TypeDesc::FLOAT)) ||
      !out->write_image(OIIO::TypeDesc::FLOAT, pixels.data()) || !out->close()) {
    std::fprintf(stderr, "tessera-tutorial-sky: cannot write %s: %s\n", argv[1],
                 out ? out->geterror().c_str() : OIIO::geterror().c_str());
    return 1;
  }
  return 0;
}

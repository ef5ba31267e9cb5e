#include "tutorial/image_io.h"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cctype>
#include <memory>

#include "tutorial/rt_check.h"

namespace tessera::tutorial {

ImageFormat FormatForPath(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  const size_t dot = path.find_last_of('.');
  std::string ext;
  if (dot != std::string::npos && (slash == std::string::npos || dot > slash)) {
    ext = path.substr(dot);
  }
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext == ".png") return ImageFormat::kPng;
  if (ext == ".exr") return ImageFormat::kExr;
  throw TutorialError("cannot write '" + path + "': unsupported extension '" + ext +
                      "' (use .png or .exr)");
}

void WriteImage(const std::string& path, const Image& image) {
  const ImageFormat format = FormatForPath(path);
  std::unique_ptr<OIIO::ImageOutput> out = OIIO::ImageOutput::create(path);
  if (!out) {
    throw TutorialError("cannot write '" + path + "': " + OIIO::geterror());
  }
  OIIO::ImageSpec spec(image.width, image.height, 4,
                       format == ImageFormat::kPng ? OIIO::TypeDesc::UINT8 : OIIO::TypeDesc::FLOAT);
  spec.attribute("Software", "tessera-tutorial");
  // OIIO converts the float pixels, clamping to [0, 1] for 8-bit PNG.
  if (!out->open(path, spec) || !out->write_image(OIIO::TypeDesc::FLOAT, image.rgba.data()) ||
      !out->close()) {
    throw TutorialError("cannot write '" + path + "': " + out->geterror());
  }
}

}  // namespace tessera::tutorial

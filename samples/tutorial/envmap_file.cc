// The environment map read from an image file (tutorial/envmap.h).
#include "tessera/image.h"
#include "tutorial/envmap.h"
#include "tutorial/rt_check.h"

#ifndef TESSERA_TUTORIAL_ENVMAP
#error "TESSERA_TUTORIAL_ENVMAP must name the environment map the build made"
#endif

namespace tessera::tutorial {

RTbuffer LoadEnvmapFile(RTcontext context, const std::string& path) {
  const std::string file = path.empty() ? TESSERA_TUTORIAL_ENVMAP : path;
  RTbuffer image = nullptr;
  if (tesseraBufferCreateFromImage(context, file.c_str(), 0, &image) != RT_SUCCESS) {
    throw TutorialError(std::string("environment map: ") + tesseraImageGetErrorString());
  }
  return image;
}

}  // namespace tessera::tutorial

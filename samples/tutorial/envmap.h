// Where the tutorial's environment map comes from (RenderOptions::load_envmap): the image file the
// build writes (or one the user names), read through libtessera_image, for the tessera-tutorial
// tool and the tests; or, by default, the same sky computed in memory, which needs no image
// library, so that the benchmarks link none and can be carried to machines without OpenImageIO's
// dependencies.
#ifndef TESSERA_SAMPLES_TUTORIAL_ENVMAP_H_
#define TESSERA_SAMPLES_TUTORIAL_ENVMAP_H_

#include <string>

#include "tessera/rt.h"

namespace tessera::tutorial {

// Makes a new 2D INPUT buffer of `context` with the environment map's texels, row 0 the bottom
// row as the SDK's loaders store images. Throws TutorialError naming what went wrong.
using EnvmapLoader = RTbuffer (*)(RTcontext context, const std::string& path);

// The build's sky (tutorial/sky.h) computed in memory, float4 texels; `path` must be empty.
RTbuffer ComputedSky(RTcontext context, const std::string& path);

// The image at `path`, or the build's HDR file when `path` is empty: float4 texels for an HDR
// image, bytes for an 8-bit one (the sampler reads them as normalized floats). In
// tessera_tutorial_lib, which links libtessera_image.
RTbuffer LoadEnvmapFile(RTcontext context, const std::string& path);

}  // namespace tessera::tutorial

#endif  // TESSERA_SAMPLES_TUTORIAL_ENVMAP_H_

// The environment map of the tutorial's steps 5 to 11, computed: a latitude-longitude image of a
// clear sky with a sun, a bright horizon and a darker ground. The build writes it to an HDR file
// (make_sky.cc) that the tutorial loads like any image; the benchmarks take it from here directly,
// so that they need no image library (bench/common/tutorial_sky.cc).
//
// Layout, as the SDK's envmap_miss reads it: u = (atan2(x, z) + pi) / (2 pi) across, v = (1 + y)
// / 2 from the bottom row up (the top row is the zenith).
#ifndef TESSERA_SAMPLES_TUTORIAL_SKY_H_
#define TESSERA_SAMPLES_TUTORIAL_SKY_H_

#include <vector>

namespace tessera::tutorial {

inline constexpr int kSkyWidth = 1024;
inline constexpr int kSkyHeight = 512;

// RGB radiance, kSkyWidth x kSkyHeight, top row (the zenith) first.
std::vector<float> SkyPixels();

}  // namespace tessera::tutorial

#endif  // TESSERA_SAMPLES_TUTORIAL_SKY_H_

// What --check verifies about a rendered eyelight image, and PNG output for people to look at.
#ifndef TESSERA_BENCH_EYELIGHT_IMAGE_CHECK_H_
#define TESSERA_BENCH_EYELIGHT_IMAGE_CHECK_H_

#include <string>

#include "mesh.h"
#include "scene.h"

namespace tessera::bench {

struct CheckReport {
  double hit_fraction = 0;       // pixels with alpha 255
  int grey_levels = 0;           // distinct grey values over the image
  double mismatch_fraction = 0;  // pixels that differ from the brute-force reference
  bool ok = false;
  std::string summary;
};

// The image must hit the scene in at least half its pixels, must not be uniform (fewer than 16
// grey levels), and must agree with a brute-force host rendering of the same camera: same
// hit/miss and grey within 2 levels, except in at most 1% of pixels (edges, where Embree's and
// the host's triangle tests may round differently).
CheckReport CheckImage(const Image& image, const Mesh& mesh, const Camera& camera);

// Writes the RGB channels of `image` as a binary PPM (P6), which image viewers and oiiotool
// read. No image library: the benchmark then packs small enough for the 16-core machine
// (tools/bundle-for-device.sh; OpenImageIO's dependencies alone are over 100 MB compressed).
// Throws std::runtime_error on failure.
void WriteImage(const Image& image, const std::string& path);

}  // namespace tessera::bench

#endif  // TESSERA_BENCH_EYELIGHT_IMAGE_CHECK_H_

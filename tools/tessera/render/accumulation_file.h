// The `.accum` file beside an image: the exact float sums a render has accumulated, so that
// `--resume` can go on from them and end with the same bits an uninterrupted render gives.
//
// Format (version 1): a text header, then the sums.
//   TESSERA-ACCUM 1\n
//   width W\n height H\n samples N\n key KEY\n      (one "name value" per line; KEY is one line)
//   \n                                               (an empty line ends the header)
//   W * H * 4 float32, little-endian: per pixel of the launch (row 0 at the bottom, as the
//   programs write it) the radiance sums r, g, b and the number of samples added (every pixel
//   holds `samples`).
#ifndef TESSERA_TOOLS_TESSERA_RENDER_ACCUMULATION_FILE_H_
#define TESSERA_TOOLS_TESSERA_RENDER_ACCUMULATION_FILE_H_

#include <cstdint>
#include <string>
#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"

namespace tessera::render {

struct Accumulation {
  int width = 0, height = 0;
  uint32_t samples = 0;     // samples per pixel in `sums`
  std::string key;          // what else the sums depend on (scene, frame, camera, seed, ...)
  std::vector<float> sums;  // width * height * 4
};

// Where the accumulation of the image at `image_path` is kept.
std::string AccumulationPath(const std::string& image_path);

// Written through a temporary file renamed when whole. Errors name the file.
absl::Status WriteAccumulation(const std::string& path, const Accumulation& accumulation);

// NOT_FOUND when there is no file; INVALID_ARGUMENT naming the file for one that is not an
// accumulation or is cut short.
absl::StatusOr<Accumulation> ReadAccumulation(const std::string& path);

}  // namespace tessera::render

#endif  // TESSERA_TOOLS_TESSERA_RENDER_ACCUMULATION_FILE_H_

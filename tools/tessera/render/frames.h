// Frame ranges (`--frames A-B[:step]`) and output patterns (`out.####.exr`).
#ifndef TESSERA_TOOLS_TESSERA_RENDER_FRAMES_H_
#define TESSERA_TOOLS_TESSERA_RENDER_FRAMES_H_

#include <string>
#include <vector>

#include "absl/status/statusor.h"

namespace tessera::render {

// "A" (one frame), "A-B" or "A-B:STEP": non-negative frame numbers A <= B and STEP >= 1.
// INVALID_ARGUMENT quoting `text` and saying what is wrong.
absl::StatusOr<std::vector<int>> ParseFrames(const std::string& text);

// Whether `path` holds a run of '#' in its file name (not in a directory name).
bool HasFramePattern(const std::string& path);

// `path` with each run of '#' in its file name replaced by `frame`, zero-padded to the run's
// length ("out.####.exr", 7 -> "out.0007.exr"; a longer number is written whole).
std::string ExpandFramePattern(const std::string& path, int frame);

}  // namespace tessera::render

#endif  // TESSERA_TOOLS_TESSERA_RENDER_FRAMES_H_

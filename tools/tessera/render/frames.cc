#include "tools/tessera/render/frames.h"

#include <cctype>
#include <climits>
#include <cstdio>

#include "absl/status/status.h"
#include "absl/strings/numbers.h"
#include "absl/strings/str_split.h"

namespace tessera::render {
namespace {

// The part of `path` after its last '/'.
size_t FileNameStart(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  return slash == std::string::npos ? 0 : slash + 1;
}

bool ParseNumber(absl::string_view text, int* value) {
  if (text.empty()) return false;
  for (char c : text) {
    if (!std::isdigit(static_cast<unsigned char>(c))) return false;
  }
  return absl::SimpleAtoi(text, value);
}

}  // namespace

absl::StatusOr<std::vector<int>> ParseFrames(const std::string& text) {
  auto bad = [&](const std::string& why) {
    return absl::InvalidArgumentError("--frames '" + text + "': " + why +
                                      " (expected A, A-B or A-B:STEP)");
  };
  absl::string_view range = text;
  int step = 1;
  if (const size_t colon = range.find(':'); colon != absl::string_view::npos) {
    if (!ParseNumber(range.substr(colon + 1), &step) || step < 1) {
      return bad("the step must be a whole number of at least 1");
    }
    range = range.substr(0, colon);
  }
  int first = 0, last = 0;
  if (const size_t dash = range.find('-'); dash != absl::string_view::npos) {
    if (!ParseNumber(range.substr(0, dash), &first) ||
        !ParseNumber(range.substr(dash + 1), &last)) {
      return bad("frame numbers must be whole numbers of at least 0");
    }
  } else {
    if (!ParseNumber(range, &first))
      return bad("frame numbers must be whole numbers of at least 0");
    last = first;
  }
  if (last < first) return bad("the last frame comes before the first");
  std::vector<int> frames;
  for (long long f = first; f <= last; f += step) frames.push_back(static_cast<int>(f));
  return frames;
}

bool HasFramePattern(const std::string& path) {
  return path.find('#', FileNameStart(path)) != std::string::npos;
}

std::string ExpandFramePattern(const std::string& path, int frame) {
  std::string out = path.substr(0, FileNameStart(path));
  for (size_t i = out.size(); i < path.size();) {
    if (path[i] != '#') {
      out += path[i++];
      continue;
    }
    size_t run = 0;
    while (i + run < path.size() && path[i + run] == '#') ++run;
    char digits[32];
    std::snprintf(digits, sizeof(digits), "%0*d", static_cast<int>(run), frame);
    out += digits;
    i += run;
  }
  return out;
}

}  // namespace tessera::render

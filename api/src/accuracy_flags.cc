#include "accuracy_flags.h"

#include <cstdio>
#include <cstdlib>
#include <mutex>

#include "absl/strings/ascii.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_split.h"
#include "tessera/accuracy.h"
#include "tessera/scheduler/log.h"

namespace tessera::api {
namespace {

struct Named {
  const char* name;
  uint32_t flag;
};
constexpr Named kNames[] = {
    {"robust", TESSERA_ACCURACY_ROBUST},      {"watertight", TESSERA_ACCURACY_WATERTIGHT},
    {"offset", TESSERA_ACCURACY_OFFSET_RAYS}, {"fast_math", TESSERA_ACCURACY_FAST_MATH},
    {"compact", TESSERA_ACCURACY_COMPACT},
};

}  // namespace

absl::StatusOr<uint32_t> ParseAccuracy(absl::string_view text) {
  uint32_t flags = 0;
  for (absl::string_view word : absl::StrSplit(text, ',', absl::SkipWhitespace())) {
    const std::string w = absl::AsciiStrToLower(absl::StripAsciiWhitespace(word));
    if (w == "all") {
      flags |= TESSERA_ACCURACY_ALL;
      continue;
    }
    if (w == "none" || w == "0") continue;
    bool found = false;
    for (const Named& n : kNames) {
      if (w == n.name) {
        flags |= n.flag;
        found = true;
      }
    }
    if (!found) {
      return absl::InvalidArgumentError(
          absl::StrCat("unknown accuracy setting '", w,
                       "' (known: robust, watertight, offset, fast_math, compact, all, none)"));
    }
  }
  return flags;
}

uint32_t AccuracyFromEnvironment() {
  const char* env = std::getenv("TESSERA_ACCURACY");
  if (env == nullptr) return 0;
  absl::StatusOr<uint32_t> flags = ParseAccuracy(env);
  if (flags.ok()) return *flags;
  static std::once_flag reported;
  std::call_once(reported, [&] {
    log::Warn(log::Component::kApi, "TESSERA_ACCURACY ignored: %s", flags.status().message());
  });
  return 0;
}

std::string AccuracyNames(uint32_t flags) {
  std::string out;
  for (const Named& n : kNames) {
    if (flags & n.flag) absl::StrAppend(&out, out.empty() ? "" : ",", n.name);
  }
  return out.empty() ? "none" : out;
}

}  // namespace tessera::api

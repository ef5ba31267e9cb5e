// TESSERA_ACCURACY_* flags (tessera/accuracy.h): their names, and a context's initial flags from
// the environment. Shared by the OptiX 3 and OptiX 7 host layers.
#ifndef TESSERA_API_SRC_ACCURACY_FLAGS_H_
#define TESSERA_API_SRC_ACCURACY_FLAGS_H_

#include <cstdint>
#include <string>

#include "absl/status/statusor.h"
#include "absl/strings/string_view.h"

namespace tessera::api {

// Flags named by `text`: comma-separated "robust", "watertight", "offset", "fast_math",
// "compact", "all" or "none" (case-insensitive, blanks ignored). An unknown name is an error
// naming it and the known ones.
absl::StatusOr<uint32_t> ParseAccuracy(absl::string_view text);

// What TESSERA_ACCURACY in the environment names; 0 when unset. An unparsable value is reported
// once on stderr and ignored (a context must still come up).
uint32_t AccuracyFromEnvironment();

// "robust,watertight", "none" for 0: the names of `flags`, for messages and logs.
std::string AccuracyNames(uint32_t flags);

// Whether `flags` holds only known bits; WATERTIGHT implies ROBUST wherever flags are applied.
inline bool KnownAccuracy(uint32_t flags) { return (flags & ~uint32_t{0x1F}) == 0; }

}  // namespace tessera::api

#endif  // TESSERA_API_SRC_ACCURACY_FLAGS_H_

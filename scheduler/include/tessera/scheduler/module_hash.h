// The wire's module hash (state.proto Program.module_hash): 64 lowercase hex digits of the
// SHA-256 of a module file's bytes. The host names modules by it and devices check what they
// receive against it, so both ends compute it here.
#ifndef TESSERA_SCHEDULER_MODULE_HASH_H_
#define TESSERA_SCHEDULER_MODULE_HASH_H_

#include <string>

#include "absl/strings/string_view.h"

namespace tessera::scheduler {

std::string ModuleHash(absl::string_view bytes);

// Whether `text` is digits and lowercase a-f only (a hash as this file writes it: also a safe
// file name).
bool IsLowerHex(absl::string_view text);

// Whether `hash` has the form ModuleHash gives: 64 lowercase hex digits.
inline bool IsModuleHash(absl::string_view hash) { return hash.size() == 64 && IsLowerHex(hash); }

}  // namespace tessera::scheduler

#endif  // TESSERA_SCHEDULER_MODULE_HASH_H_

// Content hashes. Buffer chunks and compile-cache keys: XXH64 (libxxhash), chosen for speed on
// multi-megabyte chunks. Program
// modules: SHA-256 (ModuleHash), because a device trusts a module's hash as its name for good,
// in a cache shared by every host and session it serves.
#ifndef TESSERA_API_SRC_HASH_H_
#define TESSERA_API_SRC_HASH_H_

#include <cstddef>
#include <cstdint>
#include <string>

#include "absl/strings/string_view.h"
#include "tessera/scheduler/module_hash.h"

namespace tessera::api {

uint64_t Hash64(const void* data, size_t size, uint64_t seed = 0);

// Named differently from Hash64 so that Hash64("text", seed) cannot pick the pointer overload.
inline uint64_t HashString(absl::string_view bytes, uint64_t seed = 0) {
  return Hash64(bytes.data(), bytes.size(), seed);
}

// A chunk hash is never 0, so 0 can mean "unknown" in device sync records.
inline uint64_t ChunkHash(const void* data, size_t size) {
  uint64_t h = Hash64(data, size);
  return h == 0 ? 1 : h;
}

// 16 lowercase hex digits.
std::string HexHash(uint64_t hash);

using scheduler::ModuleHash;  // the wire's module hash (tessera/scheduler/module_hash.h)

}  // namespace tessera::api

#endif  // TESSERA_API_SRC_HASH_H_

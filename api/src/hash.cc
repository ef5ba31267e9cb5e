#include "hash.h"

// Debian's libxxhash-dev: its header carries the whole implementation, inlined here, so that
// every target that compiles this file (libtessera and a few tests) needs no extra library.
#define XXH_INLINE_ALL
#include <xxhash.h>

#include "absl/strings/str_format.h"

namespace tessera::api {

uint64_t Hash64(const void* data, size_t size, uint64_t seed) { return XXH64(data, size, seed); }

std::string HexHash(uint64_t hash) { return absl::StrFormat("%016x", hash); }

}  // namespace tessera::api

// The 32-byte header of an OptiX 7 SBT record (OPTIX_SBT_RECORD_HEADER_SIZE) as
// optixSbtRecordPackHeader writes it on the host and the engine reads it on devices: which
// program group the record runs. A record whose header lacks the magic was never packed.
#ifndef TESSERA_WORKER_MEMORY_SBT_HEADER_H_
#define TESSERA_WORKER_MEMORY_SBT_HEADER_H_

#include <cstdint>

namespace tessera::memory {

inline constexpr uint64_t kSbtHeaderMagic = 0x3152485453455354ull;  // "TSETSHR1", little-endian

struct SbtHeader {
  uint64_t magic;          // kSbtHeaderMagic
  uint64_t program_group;  // the program group's id (v1::Optix7ProgramGroup.id)
  uint64_t reserved[2];    // zero
};
static_assert(sizeof(SbtHeader) == 32, "OPTIX_SBT_RECORD_HEADER_SIZE");

}  // namespace tessera::memory

#endif  // TESSERA_WORKER_MEMORY_SBT_HEADER_H_

// The acceleration descriptor of OptiX 7 builds (docs/device_memory.md, "Accelerations"): what
// optixAccelBuild writes into its output buffer in device memory, and what a worker reads to
// build its Embree scene. Position independent (offsets from the header, never addresses), so
// that optixAccelCompact and optixAccelRelocate are copies, and self-contained (a copy of the
// geometry, in one layout whatever the application's formats and strides), so that an
// application may free its inputs after the build, as OptiX allows. The traversable handle of a
// build is the descriptor's address. Little-endian; every offset is 8-byte aligned.
#ifndef TESSERA_WORKER_MEMORY_ACCEL_FORMAT_H_
#define TESSERA_WORKER_MEMORY_ACCEL_FORMAT_H_

#include <cstddef>
#include <cstdint>

#include "absl/status/statusor.h"

namespace tessera::memory {

inline constexpr char kAccelMagic[8] = {'T', 'S', 'R', '7', 'A', 'C', 'C', 'L'};
// 2: motion keys (AccelMotion) and spheres.
inline constexpr uint32_t kAccelFormatVersion = 2;

enum class AccelKind : uint32_t { kTriangles = 1, kCustom = 2, kInstances = 3, kSpheres = 4 };

struct AccelHeader {
  char magic[8];
  uint32_t version;
  AccelKind kind;
  uint64_t total_size;    // header included
  uint64_t content_hash;  // of the bytes after the header (the host's Hash64): workers' scene key
  uint32_t input_count;   // GAS: build inputs; IAS: 1
  uint32_t build_flags;   // OptixBuildFlags
  uint64_t primitive_count;  // over all inputs; instances for an IAS
  uint64_t inputs_offset;    // AccelInput[input_count] (GAS) or OptixInstance-sized records (IAS)
  uint64_t motion_offset;    // AccelMotion, or 0: built without motion (one key)
};
static_assert(sizeof(AccelHeader) == 64);

// The build's OptixMotionOptions, when it had two keys or more. A GAS then holds `keys` copies
// of its vertices (triangles, spheres) or boxes (custom primitives), key after key; an IAS holds
// its instances once (its motion options only say when its instances vanish).
struct AccelMotion {
  uint32_t keys;   // >= 2
  uint32_t flags;  // OptixMotionFlags
  float time_begin, time_end;
};
static_assert(sizeof(AccelMotion) == 16);

// One build input of a GAS. Triangles: `vertex_count` float[3] at `vertices_offset`, and
// `primitive_count` uint32[3] at `indices_offset` (always indexed: an unindexed input gets
// 0 1 2, 3 4 5 ...). Custom primitives: `primitive_count` boxes of float[6] (min xyz, max xyz) at
// `aabbs_offset`. Spheres: `primitive_count` float[4] (centre xyz, radius) at `vertices_offset`
// (`vertex_count` equals `primitive_count`). With motion, key k of the vertices or boxes follows
// key k-1 directly (key k of triangle vertices at vertices_offset + k * 12 * vertex_count).
// All: one OptixGeometryFlags word per SBT record at `flags_offset`, and a uint32 SBT index
// offset per primitive at `sbt_index_offsets_offset` (0 when one record).
struct AccelInput {
  uint32_t primitive_count;
  uint32_t primitive_index_offset;
  uint32_t num_sbt_records;
  uint32_t vertex_count;
  uint64_t vertices_offset;
  uint64_t indices_offset;
  uint64_t aabbs_offset;
  uint64_t flags_offset;
  uint64_t sbt_index_offsets_offset;
  uint64_t flags;  // kAccelInput* bits (0 in descriptors of Tessera before them)
};
// The input was written by OPTIX_BUILD_OPERATION_UPDATE: a worker that built the scene of the
// same buffer (ALLOW_UPDATE, the same counts and indices) refits it in place.
inline constexpr uint64_t kAccelInputUpdate = 1;
static_assert(sizeof(AccelInput) == 64);

// An IAS holds its instances as OptiX lays them out (OptixInstance, 80 bytes), copied from the
// build input (INSTANCE_POINTERS dereferenced), at inputs_offset.
inline constexpr size_t kInstanceBytes = 80;

// Checks a descriptor of `size` bytes at `data` (magic, version, sizes, every offset in range;
// not the hash, which the host computed over bytes it shipped by content) and returns its header;
// INVALID_ARGUMENT saying what is wrong.
absl::StatusOr<const AccelHeader*> ReadAccelHeader(const void* data, size_t size);

}  // namespace tessera::memory

#endif  // TESSERA_WORKER_MEMORY_ACCEL_FORMAT_H_

// The host's device memory for the OptiX 7 layer: the process's arena (worker/memory), the
// allocations cudaMalloc made in it, and which chunks the host wrote since devices last took them
// (docs/device_memory.md). The host's copy is authoritative: launches ship what changed.
#ifndef TESSERA_API_OPTIX7_HOST_DEVICE_MEMORY_H_
#define TESSERA_API_OPTIX7_HOST_DEVICE_MEMORY_H_

#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <utility>
#include <vector>

#include "absl/status/statusor.h"
#include "device_allocator.h"
#include "device_arena.h"

namespace tessera::optix7 {

class HostDeviceMemory {
 public:
  // Host writes are tracked in chunks of this many bytes, aligned to the arena's base.
  static constexpr size_t kChunkBytes = size_t{64} << 10;

  // The process's device memory, in memory::ProcessArena(); the error says why when the range
  // cannot be had.
  static absl::StatusOr<HostDeviceMemory*> Get();

  // `managed`: cudaMallocManaged memory, which the host reads and writes through pointers without
  // telling anyone: MarkManagedWritten treats all of it as written before each launch.
  absl::StatusOr<uintptr_t> Allocate(size_t bytes, bool managed = false);
  absl::Status Free(uintptr_t address);
  // Whether [address, address + length) lies in one live allocation.
  bool IsAllocated(uintptr_t address, size_t length) const;
  // Whether `address` is in the arena (allocated or not): a device pointer, not a host one.
  bool InArena(uintptr_t address) const;

  // Records a write to [address, address + length): the host's (cudaMemcpy, cudaMemset,
  // optixAccelBuild), or, with `by_device`, one a launch's programs made on a device (which
  // reaches the other devices as the bytes written, not as chunks: launch_target.cc). Each call
  // is a new write epoch.
  void MarkWritten(uintptr_t address, size_t length, bool by_device = false);
  // Marks every managed allocation written (by the host): what a launch does first, so that the
  // host's writes through pointers reach devices (chunks whose content did not change travel
  // nowhere: devices are sent what differs from their hashes).
  void MarkManagedWritten();

  // The chunk that holds `address` (its first byte's address).
  uintptr_t ChunkOf(uintptr_t address) const {
    const uintptr_t base = arena_->base();
    return base + (address - base) / kChunkBytes * kChunkBytes;
  }
  // The write epoch of the last MarkWritten (0: none yet).
  uint64_t epoch() const;
  // The chunks written after epoch `since` (by the host only, with `host_only`), by address,
  // ascending, with the epoch of their last write of any kind (what their content is as of).
  std::vector<std::pair<uintptr_t, uint64_t>> ChunksWrittenSince(uint64_t since,
                                                                 bool host_only = false) const;
  // The chunks written since the last call, by address, ascending (tests).
  std::vector<uintptr_t> TakeWrittenChunks();

  // The live allocations (address, size), by address, and a number that changes whenever they do.
  std::vector<std::pair<uintptr_t, size_t>> Allocations() const;
  uint64_t allocation_generation() const;

  size_t bytes_in_use() const;
  size_t capacity() const { return arena_->size(); }

 private:
  explicit HostDeviceMemory(memory::DeviceArena* arena);

  mutable std::mutex mutex_;
  memory::DeviceArena* arena_;  // the process's (memory::ProcessArena)
  memory::DeviceAllocator allocator_;
  struct Written {
    uint64_t any = 0;   // epoch of the chunk's last write
    uint64_t host = 0;  // epoch of its last host write (0: none)
  };
  std::map<uintptr_t, Written> written_;  // by chunk address
  uint64_t epoch_ = 0;
  uint64_t taken_epoch_ = 0;  // TakeWrittenChunks
  uint64_t allocation_generation_ = 0;
  std::map<uintptr_t, size_t> managed_;  // cudaMallocManaged allocations
};

}  // namespace tessera::optix7

#endif  // TESSERA_API_OPTIX7_HOST_DEVICE_MEMORY_H_

// The host's device memory for the OptiX 7 layer: the process's arena (worker/memory), the
// allocations cudaMalloc made in it, and which chunks the host wrote since devices last took them
// (docs/device_memory.md). The host's copy is authoritative: launches ship what changed.
#ifndef TESSERA_API_OPTIX7_HOST_DEVICE_MEMORY_H_
#define TESSERA_API_OPTIX7_HOST_DEVICE_MEMORY_H_

#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include <set>
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

  absl::StatusOr<uintptr_t> Allocate(size_t bytes);
  absl::Status Free(uintptr_t address);
  // Whether [address, address + length) lies in one live allocation.
  bool IsAllocated(uintptr_t address, size_t length) const;
  // Whether `address` is in the arena (allocated or not): a device pointer, not a host one.
  bool InArena(uintptr_t address) const;

  // Records a host write to [address, address + length) (cudaMemcpy, cudaMemset).
  void MarkWritten(uintptr_t address, size_t length);
  // The chunks written since the last call, by address, ascending; forgets them.
  std::vector<uintptr_t> TakeWrittenChunks();

  size_t bytes_in_use() const;
  size_t capacity() const { return arena_->size(); }

 private:
  explicit HostDeviceMemory(memory::DeviceArena* arena);

  mutable std::mutex mutex_;
  memory::DeviceArena* arena_;  // the process's (memory::ProcessArena)
  memory::DeviceAllocator allocator_;
  std::set<uintptr_t> written_;  // chunk addresses
};

}  // namespace tessera::optix7

#endif  // TESSERA_API_OPTIX7_HOST_DEVICE_MEMORY_H_

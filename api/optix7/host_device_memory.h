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

#include "absl/base/thread_annotations.h"
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

  // An allocation of CUDA device `owner` (cudaMalloc's current device). With one CUDA device
  // (the default) every allocation is device 0's; with one per Tessera device an allocation
  // ships only to its owner and to devices that enabled peer access to it (Allocations).
  // `managed`: cudaMallocManaged memory, which the host reads and writes through pointers without
  // telling anyone: MarkManagedWritten treats all of it as written before each launch.
  absl::StatusOr<uintptr_t> Allocate(size_t bytes, int owner = 0, bool managed = false);
  absl::Status Free(uintptr_t address);
  // Whether [address, address + length) lies in one live allocation.
  bool IsAllocated(uintptr_t address, size_t length) const;
  // Whether `address` is in the arena (allocated or not): a device pointer, not a host one.
  bool InArena(uintptr_t address) const;

  // Records a write to [address, address + length): the host's (cudaMemcpy, cudaMemset,
  // optixAccelBuild), or, with a non-zero `device_writer`, one that programs of a launch target
  // (launch_target.cc: one OptixDeviceContext's devices) made, which reaches that target's other
  // devices as the bytes written, not as chunks, and other targets' devices as chunks, as host
  // writes do. Each call is a new write epoch.
  void MarkWritten(uintptr_t address, size_t length, uint64_t device_writer = 0);
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
  // The chunks written after epoch `since`, by address, ascending, with the epoch of their last
  // write of any kind (what their content is as of). With a non-zero `except_writer` only those
  // written by someone else: the host or another launch target's programs.
  std::vector<std::pair<uintptr_t, uint64_t>> ChunksWrittenSince(uint64_t since,
                                                                 uint64_t except_writer = 0) const;
  // The chunks written since the last call, by address, ascending (tests).
  std::vector<uintptr_t> TakeWrittenChunks();

  // The live allocations (address, size), by address, and a number that changes whenever they do
  // or peer access does. With a `device` (>= 0) only those it may reach: its own and those of
  // devices it enabled peer access to (CUDA: another device's memory is not for its programs
  // otherwise, so they need not travel there).
  static constexpr int kAllDevices = -1;
  std::vector<std::pair<uintptr_t, size_t>> Allocations(int device = kAllDevices) const;
  uint64_t allocation_generation() const;
  // The owner of the allocation at `address` (its start or inside it), or -1 when none.
  int OwnerOf(uintptr_t address) const;

  // cudaDeviceEnablePeerAccess / cudaDeviceDisablePeerAccess of `device` to `peer`'s memory;
  // false when it already was (not) enabled.
  bool SetPeerAccess(int device, int peer, bool enabled);

  size_t bytes_in_use() const;
  size_t capacity() const { return arena_->size(); }

 private:
  explicit HostDeviceMemory(memory::DeviceArena* arena);
  void MarkWrittenLocked(uintptr_t address, size_t length, uint64_t device_writer)
      ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);

  mutable std::mutex mutex_;
  memory::DeviceArena* arena_;  // the process's (memory::ProcessArena)
  memory::DeviceAllocator allocator_;
  struct Written {
    uint64_t any = 0;   // epoch of the chunk's last write
    uint64_t host = 0;  // epoch of its last host write (0: none)
    // Epochs of the last write of each launch target whose programs wrote the chunk (few: one
    // per OptixDeviceContext that launched).
    std::vector<std::pair<uint64_t, uint64_t>> by_writer;
  };
  std::map<uintptr_t, Written> written_;  // by chunk address
  uint64_t epoch_ = 0;
  uint64_t taken_epoch_ = 0;  // TakeWrittenChunks
  uint64_t allocation_generation_ = 0;
  std::map<uintptr_t, size_t> managed_;    // cudaMallocManaged allocations
  std::map<uintptr_t, int> owners_;        // by allocation address
  std::map<int, std::vector<int>> peers_;  // device -> the devices whose memory it may reach
};

}  // namespace tessera::optix7

#endif  // TESSERA_API_OPTIX7_HOST_DEVICE_MEMORY_H_

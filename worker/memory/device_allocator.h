// The host's bookkeeping of device memory (cudaMalloc, cudaFree) inside the arena's addresses
// (device_arena.h). Allocations are 256-byte aligned, as cudaMalloc's are, and go to the lowest
// free range that fits, so that the same sequence of calls gives the same addresses on every run
// (a launch's output must not depend on where its inputs happened to land).
#ifndef TESSERA_WORKER_MEMORY_DEVICE_ALLOCATOR_H_
#define TESSERA_WORKER_MEMORY_DEVICE_ALLOCATOR_H_

#include <cstddef>
#include <cstdint>
#include <map>

#include "absl/status/statusor.h"

namespace tessera::memory {

class DeviceAllocator {
 public:
  static constexpr size_t kAlignment = 256;

  struct Allocation {
    uintptr_t address = 0;
    size_t size = 0;  // as asked for
  };
  // What a free gave back: the allocation, and the pages no live allocation touches any more,
  // [release_begin, release_end) (empty when begin == end), which the arena may release.
  struct Freed {
    Allocation allocation;
    uintptr_t release_begin = 0, release_end = 0;
  };

  // Hands out [base, base + size); base must be aligned to kAlignment.
  DeviceAllocator(uintptr_t base, size_t size, size_t page_size);

  // A new allocation of `bytes` (> 0). RESOURCE_EXHAUSTED, naming the size asked for and the
  // largest free range, when none fits.
  absl::StatusOr<uintptr_t> Allocate(size_t bytes);
  // Ends the allocation that starts at `address`. NOT_FOUND for any other address: one never
  // allocated, freed already, or inside an allocation.
  absl::StatusOr<Freed> Free(uintptr_t address);

  // The live allocation that holds all of [address, address + length) (length 0: the address),
  // or null: what a cudaMemcpy checks its device pointer against.
  const Allocation* Find(uintptr_t address, size_t length) const;

  // Every live allocation, by address.
  const std::map<uintptr_t, Allocation>& live() const { return live_; }

  size_t bytes_in_use() const { return bytes_in_use_; }
  size_t allocation_count() const { return live_.size(); }
  size_t LargestFree() const;

 private:
  static size_t Rounded(size_t bytes) { return (bytes + kAlignment - 1) / kAlignment * kAlignment; }

  uintptr_t base_;
  size_t size_;
  size_t page_;
  size_t bytes_in_use_ = 0;
  std::map<uintptr_t, Allocation> live_;  // by address
  std::map<uintptr_t, size_t> free_;      // free ranges by address, never adjacent to each other
};

}  // namespace tessera::memory

#endif  // TESSERA_WORKER_MEMORY_DEVICE_ALLOCATOR_H_

// Device memory for OptiX 7 launches (issue 25; docs/optix7.md, "Device memory"): one range of
// virtual addresses reserved at the same address in the host and in every worker process, so that
// a pointer an application keeps in its launch parameters, SBT records or instance arrays means the
// same bytes on every device. The range costs nothing until pages in it are committed.
#ifndef TESSERA_WORKER_MEMORY_DEVICE_ARENA_H_
#define TESSERA_WORKER_MEMORY_DEVICE_ARENA_H_

#include <cstddef>
#include <cstdint>
#include <memory>

#include "absl/status/statusor.h"

namespace tessera::memory {

// Where device memory lives unless TESSERA_DEVICE_MEMORY_BASE says otherwise: 32 TiB, far from
// where Linux puts executables (0x55…), the heap after them and mmap (down from 0x7f…), and 1 TiB
// of it, which is what cudaMalloc can hand out in all.
inline constexpr uintptr_t kDefaultArenaBase = uintptr_t{0x200000000000};
inline constexpr size_t kDefaultArenaSize = size_t{1} << 40;

// A reserved range of addresses [base, base + size), inaccessible until committed.
class DeviceArena {
 public:
  // Reserves exactly [base, base + size), never moving it: FAILED_PRECONDITION naming the range
  // when something of the process already lies there (another arena, a library), since a range at
  // another address would give pointers another meaning than on the other processes.
  // INVALID_ARGUMENT for a base or size that is not a multiple of the page size.
  static absl::StatusOr<std::unique_ptr<DeviceArena>> Reserve(uintptr_t base, size_t size);
  ~DeviceArena();
  DeviceArena(const DeviceArena&) = delete;
  DeviceArena& operator=(const DeviceArena&) = delete;

  uintptr_t base() const { return base_; }
  size_t size() const { return size_; }
  // Whether [address, address + length) lies inside the arena (length 0: the address alone).
  bool Contains(uintptr_t address, size_t length) const;

  // Makes the pages of [address, address + length) readable and writable (zeros where they were
  // never written or were released). OUT_OF_RANGE outside the arena.
  absl::Status Commit(uintptr_t address, size_t length);
  // Gives the pages wholly inside [address, address + length) back to the system and makes them
  // inaccessible again; pages the range only partly covers stay as they are.
  absl::Status Release(uintptr_t address, size_t length);

  static size_t PageSize();

 private:
  DeviceArena(uintptr_t base, size_t size) : base_(base), size_(size) {}
  uintptr_t base_;
  size_t size_;
};

// The arena of this process, reserved on first use at TESSERA_DEVICE_MEMORY_BASE (hex) or
// kDefaultArenaBase, kDefaultArenaSize bytes: the host's cudaMalloc memory, and in a worker
// process the copy of it that launches use. In-process devices share the host's. Thread-safe.
absl::StatusOr<DeviceArena*> ProcessArena();

}  // namespace tessera::memory

#endif  // TESSERA_WORKER_MEMORY_DEVICE_ARENA_H_

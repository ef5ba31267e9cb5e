// What programs wrote to device memory during a launch, found without copying all of it: the
// pages are write-protected before the launch, the first write to each faults, the fault handler
// keeps a copy of the page as it was and lets the write through, and afterwards only those pages
// are compared with their copies (docs/device_memory.md, "Gathering what programs wrote").
// Soft-dirty page bits would avoid the faults but are not available everywhere (not in the
// development sandbox), and a full copy before every launch costs as much memory again.
#ifndef TESSERA_WORKER_MEMORY_WRITE_TRACKER_H_
#define TESSERA_WORKER_MEMORY_WRITE_TRACKER_H_

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include "absl/status/statusor.h"

namespace tessera::memory {

class WriteTracker {
 public:
  // Bytes [address, address + length) that differ from before.
  using Run = std::pair<uintptr_t, size_t>;

  // Tracks writes to [base, base + size) (page aligned). At most one tracker is armed in a
  // process at a time: FAILED_PRECONDITION otherwise.
  static absl::StatusOr<std::unique_ptr<WriteTracker>> Create(uintptr_t base, size_t size);
  ~WriteTracker();
  WriteTracker(const WriteTracker&) = delete;
  WriteTracker& operator=(const WriteTracker&) = delete;

  // Write-protects the pages of [address, address + length) (readable and writable memory
  // inside the range); the first write to each is recorded from then on.
  absl::Status Protect(uintptr_t address, size_t length);
  // Copies the pages of [address, address + length) now instead of at their first write: for
  // memory that programs will mostly write, where a fault per page costs far more than a copy.
  absl::Status Snapshot(uintptr_t address, size_t length);
  // Makes every protected page writable again and returns what changed since Protect or
  // Snapshot, in address order, adjacent bytes merged; the tracker is then ready for the next
  // call. `faulted`, when given, receives for each protected range (by the address Protect was
  // given) how many of its pages were written (faulted), whether or not their bytes changed.
  std::vector<Run> Collect(std::vector<std::pair<uintptr_t, size_t>>* faulted = nullptr);

  // Pages written since Protect (for tests and statistics).
  size_t pages_written() const { return written_.load(std::memory_order_relaxed); }

 private:
  WriteTracker(uintptr_t base, size_t size, size_t page);
  static void OnFault(int signal, void* info, void* context);
  bool Take(uintptr_t address);  // in the fault handler: whether the fault was a tracked write

  uintptr_t base_;
  size_t size_;
  size_t page_;
  unsigned char* shadow_ = nullptr;        // the pages as they were, at their offsets
  std::atomic<uint8_t>* state_ = nullptr;  // per page: kFree, kProtected, kCopying, kWritten
  struct Protected {
    size_t p0, p1;      // pages [p0, p1)
    uintptr_t address;  // as Protect was given it
  };
  std::vector<Protected> protected_;
  std::vector<std::pair<size_t, size_t>> snapshots_;  // page ranges copied up front
  std::atomic<size_t> written_{0};
};

}  // namespace tessera::memory

#endif  // TESSERA_WORKER_MEMORY_WRITE_TRACKER_H_

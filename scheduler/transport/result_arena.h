// Shared memory between the host and a worker process it spawned, through which written regions
// travel instead of through the socket: the worker copies a region's bytes into the arena and
// sends only where they are; the host copies them out as the message arrives. Over the socket each
// byte is copied by protobuf, gRPC and the kernel on both sides (docs/devices.md).
//
// The arena holds kSlots slots. The host leases one slot to each call it makes and gets it back
// when the call ends, however it ends. A slot's state word (in the arena, shared) holds the token
// of the call that may write it and a writing bit. The worker sets the bit while it copies, and
// only if the token is its call's; the host gives a slot to a new call only if the bit is clear,
// by swapping in the new token. Whichever side swaps first wins: a worker still sending for a
// call the host gave up on (a cancel) cannot write into a slot the host has leased again.
#ifndef TESSERA_SCHEDULER_TRANSPORT_RESULT_ARENA_H_
#define TESSERA_SCHEDULER_TRANSPORT_RESULT_ARENA_H_

#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "tessera/v1/launch.pb.h"

namespace tessera::transport {

class ResultArena {
 public:
  static constexpr int kSlots = 8;
  // Regions smaller than this stay in the message: the copy saved is smaller than the bookkeeping.
  static constexpr uint64_t kMinRegionBytes = 4096;

  // Host: a new anonymous arena of `slot_bytes` per slot (pages are taken only when written).
  static absl::StatusOr<std::unique_ptr<ResultArena>> Create(uint64_t slot_bytes);
  // Worker: maps the arena the host passed down as descriptor `fd` (the worker owns it after).
  static absl::StatusOr<std::unique_ptr<ResultArena>> Map(int fd);
  ~ResultArena();
  ResultArena(const ResultArena&) = delete;
  ResultArena& operator=(const ResultArena&) = delete;

  int fd() const { return fd_; }  // for the child to inherit; -1 once closed
  void CloseFd();
  uint64_t slot_bytes() const { return slot_bytes_; }

  // ---- Host side.
  struct Lease {
    int slot = -1;  // -1: no slot free; the call sends its regions in messages
    uint64_t token = 0;
  };
  Lease Acquire();
  void Release(const Lease& lease);
  // Puts the bytes of `result`'s regions that lie in the leased slot back into the regions.
  // An error for a region outside the slot, or for any arena region when `arena` is null (a
  // worker this host did not give an arena): a malformed result, whose bytes would be lost.
  static absl::Status Restore(ResultArena* arena, const Lease& lease, v1::TileResult* result);
  // Bytes Restore took from the arena so far (tests, measurements).
  uint64_t restored_bytes() const { return restored_bytes_.load(std::memory_order_relaxed); }

  // ---- Worker side: moves one call's large regions into its slot while they fit.
  class Writer {
   public:
    Writer() = default;
    // A writer for the slot and token a launch request names; inactive if they are not valid.
    Writer(ResultArena* arena, const v1::LaunchRequest& request);
    void Move(v1::TileResult* result);

   private:
    ResultArena* arena_ = nullptr;
    int slot_ = -1;
    uint64_t token_ = 0;
    uint64_t used_ = 0;
  };

 private:
  ResultArena(int fd, unsigned char* base, uint64_t bytes);
  absl::Status RestoreRegion(const Lease& lease, v1::BufferRegion& r);
  std::atomic<uint64_t>& State(int slot) const;
  unsigned char* SlotData(int slot) const;

  int fd_;
  unsigned char* const base_;
  const uint64_t bytes_;
  const uint64_t slot_bytes_;
  std::mutex mu_;  // host: which slots are leased
  bool leased_[kSlots] = {};
  uint64_t next_token_ = 0;
  std::atomic<uint64_t> restored_bytes_{0};
};

}  // namespace tessera::transport

#endif  // TESSERA_SCHEDULER_TRANSPORT_RESULT_ARENA_H_

// The write epochs of one OptiX 3 device call (TesseraBufferView::write_epoch). Pieces start in
// the current epoch, which moves on as pieces finish; once no piece that started in an epoch is
// left, no program can mark with it any more and its elements can go out while later pieces
// trace (docs/devices.md, "write epochs").
//
// Every piece starts and finishes here, on every thread of the device: a lock taken twice a
// piece put 32 threads into the kernel's futex locks for more than half their time (pieces of a
// small launch take microseconds), so the common steps are atomic counts and the lock is taken
// only to move the epoch on (at most `epochs` times a call) and to claim epochs to send.
#ifndef TESSERA_WORKER_CORE_WRITE_EPOCHS_H_
#define TESSERA_WORKER_CORE_WRITE_EPOCHS_H_

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <mutex>

#include "replica.h"

namespace tessera::worker {

class WriteEpochs {
 public:
  static constexpr unsigned char kMaxEpochs = 8;

  WriteEpochs(Replica& replica, size_t pieces, unsigned char epochs)
      : replica_(replica), pieces_(pieces), epochs_(epochs) {
    replica_.SetWriteEpoch(1);
  }

  // A piece starts; returns its epoch, for Finished.
  unsigned char Started() {
    for (;;) {
      const unsigned char e = current_.load();
      running_[e].fetch_add(1);
      // Still current once counted: the epoch cannot close before this piece finishes (a claim
      // reads the count after the epoch moved on). Otherwise it moved on meanwhile, maybe closed
      // already: the piece starts in the new one, and a count this leaves at zero is claimed at
      // the next piece's end (this piece's at the latest).
      if (current_.load() == e) return e;
      if (running_[e].fetch_sub(1) == 1) claim_pending_.store(true);
    }
  }

  // A piece of `epoch` ended. Returns the epochs (*after, upto] the caller is to send (upto 0:
  // none); the caller then calls Sent(upto). One caller sends at a time, in epoch order.
  unsigned char Finished(unsigned char epoch, unsigned char* after) {
    const bool emptied = running_[epoch].fetch_sub(1) == 1;
    const size_t finished = finished_.fetch_add(1) + 1;
    bool moved = false;
    unsigned char current = current_.load();
    if (current < epochs_ && finished >= pieces_ * current / epochs_) {
      std::lock_guard<std::mutex> lock(mu_);
      current = current_.load();
      if (current < epochs_ && finished >= pieces_ * current / epochs_) {
        // The programs' epoch first: a piece that starts in the new epoch marks with it.
        replica_.SetWriteEpoch(current + 1);
        current_.store(current + 1);
        moved = true;
      }
      if (moved) return ClaimLocked(after);
    }
    // An epoch can close when it is no longer current and its last piece ends, or when it moves
    // on after its last piece ended: whichever comes second claims it.
    if (!(emptied && epoch < current_.load()) &&
        !(claim_pending_.load() && claim_pending_.exchange(false))) {
      return 0;
    }
    std::lock_guard<std::mutex> lock(mu_);
    return ClaimLocked(after);
  }

  unsigned char Sent(unsigned char upto, unsigned char* after) {
    std::lock_guard<std::mutex> lock(mu_);
    sent_ = upto;
    sending_ = false;
    return ClaimLocked(after);
  }

  // After every piece ended: the epochs up to this one went out.
  unsigned char sent() const {
    std::lock_guard<std::mutex> lock(mu_);
    return sent_;
  }

 private:
  unsigned char ClaimLocked(unsigned char* after) {
    if (sending_) return 0;  // the sender claims again when it is done (Sent)
    unsigned char closed = sent_;
    while (closed + 1 < current_.load() && running_[closed + 1].load() == 0) ++closed;
    if (closed == sent_) return 0;
    sending_ = true;
    *after = sent_;
    return closed;
  }

  Replica& replica_;
  const size_t pieces_;
  const unsigned char epochs_;
  mutable std::mutex mu_;   // moving the epoch on, sent_ and sending_
  unsigned char sent_ = 0;  // epochs up to this one went out
  bool sending_ = false;
  // Read by every piece, written a few times a call: apart from the counts every piece writes.
  alignas(64) std::atomic<unsigned char> current_{1};
  std::atomic<bool> claim_pending_{false};  // Started left an epoch's count at zero
  alignas(64) std::array<std::atomic<int>, kMaxEpochs + 1> running_{};
  alignas(64) std::atomic<size_t> finished_{0};
};

}  // namespace tessera::worker

#endif  // TESSERA_WORKER_CORE_WRITE_EPOCHS_H_

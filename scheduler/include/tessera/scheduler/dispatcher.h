// Runs one launch's tiles on a set of devices (docs/devices.md "Tiles and their assignment"): each
// device takes batches of tiles, two calls in flight; a batch counts only when its device finished
// all of it, so a device that is lost mid-batch costs time, not results: its unfinished tiles run
// on the others.
//
// Assignment: dynamic (any device takes the next tiles: fast devices take more) unless the launch
// needs stable ownership (GPU_LOCAL buffers: tile i stays on device i mod N for the same launch
// size and device set, so per-device accumulation sees the same pixels every launch). A lost
// device's tiles then move to the survivors, also by tile index.
#ifndef TESSERA_SCHEDULER_DISPATCHER_H_
#define TESSERA_SCHEDULER_DISPATCHER_H_

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <map>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "absl/base/thread_annotations.h"
#include "absl/status/status.h"
#include "tessera/scheduler/device.h"
#include "tessera/v1/launch.pb.h"

namespace tessera::scheduler {

struct DispatchDevice {
  // Null: a device of the launch's device set that is gone since before the launch began. With
  // stable ownership its tiles go to the others as a lost device's would, so that every other
  // device keeps its own tiles (the set's size, not the survivors', says who owns tile i).
  Device* device = nullptr;
  std::string name;          // for messages
  int threads = 1;           // a batch holds up to twice this many tiles
  v1::LaunchRequest header;  // session, launch id, entry point, dims; tiles empty
};

// The results of one finished batch: its tiles' results and the written regions (last).
struct FinishedBatch {
  size_t device = 0;
  size_t tiles = 0;
  std::vector<v1::TileResult> results;
  uint64_t sequence = 0;  // the call's place in its device's order (TileResult.call_sequence)
};

// A device that stopped answering or died during the launch.
struct LostDevice {
  size_t device = 0;
  absl::Status reason;
};

class Dispatcher {
 public:
  // Starts two threads per device at once (none for a null device). `progress`, when given,
  // counts the tiles devices finished, while their calls run (tesseraContextGetLaunchProgress):
  // a call's tiles count once it ends, or earlier as far as its device says; they are taken back
  // when the call fails (they run again elsewhere).
  // `min_indices_per_thread`: the fewest launch indices per device thread a call takes while the
  // queue holds enough (0: a 64x64 tile's worth); a launch whose indices cost little asks for more,
  // so that its calls are not mostly their own overhead.
  // `tile_costs`: what each tile (by index) cost in an earlier launch of the same tiles, or
  // empty: shared-queue batches are then cut to like costs instead of like tile counts, so that a
  // batch through an expensive part of the image is no longer the one the others wait for.
  Dispatcher(std::vector<DispatchDevice> devices, std::vector<v1::Tile> tiles,
             bool stable_ownership, std::atomic<uint64_t>* progress = nullptr,
             uint64_t min_indices_per_thread = 0, std::vector<float> tile_costs = {});
  // Stops and joins the device threads (cancelling running calls).
  ~Dispatcher();
  Dispatcher(const Dispatcher&) = delete;
  Dispatcher& operator=(const Dispatcher&) = delete;

  // Launching thread: moves finished batches into `out`, waiting for one until `deadline`.
  // A device's batches come in the order the device ran them (their call sequence), which is
  // not always the order its calls ended on the host: a device starts its next call while the
  // last one's results are still on their way. Returns true once every device thread has ended
  // and nothing is left to take.
  bool Wait(std::chrono::steady_clock::time_point deadline, std::vector<FinishedBatch>* out);

  // Stops handing out tiles and cancels running calls (the timeout callback asked to stop).
  void Cancel();

  // After Wait returned true: what each tile cost (by tile index), measured as its call's time on
  // its device over the call's tiles; empty unless every tile finished.
  std::vector<float> tile_costs() const;

  // After Wait returned true: OK when every tile finished; CANCELLED after Cancel(); else the
  // first failure: ABORTED (a device crashed running a program), UNAVAILABLE (every device was
  // lost), or the error a device reported for its tiles (a program fault, a bad message).
  // `failed_device` is the device of that failure, or -1.
  absl::Status status() const;
  int failed_device() const;
  std::vector<LostDevice> lost() const;

 private:
  struct Queue {
    std::deque<v1::Tile> tiles;
  };

  void Run(size_t d);
  // One call of device `d`'s thread: waits for tiles, takes a batch into `batch` (the caller's,
  // so that a failure can take it out of in_flight_), runs it and delivers or requeues it. False
  // when the thread should end. `lock` holds mu_ on entry and on return.
  bool RunCall(size_t d, std::unique_lock<std::mutex>& lock, std::vector<v1::Tile>& batch)
      ABSL_EXCLUSIVE_LOCKS_REQUIRED(mu_);
  void AddProgress(uint64_t tiles) {
    if (progress_ != nullptr) progress_->fetch_add(tiles, std::memory_order_relaxed);
  }
  // Whether device `d` may take tiles now: some are queued for it, and a suspect at the front, or
  // a suspect it runs alone, does not make it wait for its other call to end.
  bool CanTake(size_t d) const ABSL_EXCLUSIVE_LOCKS_REQUIRED(mu_);
  // Takes the next batch for device `d`; empty when the launch is over for it.
  std::vector<v1::Tile> Take(size_t d) ABSL_EXCLUSIVE_LOCKS_REQUIRED(mu_);
  // Hands the tiles of lost device `d` (its batch and, for stable ownership, its queue) on.
  // `ran_suspect`: the call held one suspect alone and the device said it started running it.
  void Requeue(size_t d, std::vector<v1::Tile> batch, bool ran_suspect = false)
      ABSL_EXCLUSIVE_LOCKS_REQUIRED(mu_);
  void Fail(size_t d, absl::Status status) ABSL_EXCLUSIVE_LOCKS_REQUIRED(mu_);
  // Hands a finished batch to the launching thread once the device's earlier calls are handed
  // over; batches without a sequence go at once.
  void Deliver(FinishedBatch batch) ABSL_EXCLUSIVE_LOCKS_REQUIRED(mu_);
  // Hands over device `d`'s held batches whatever came before them: the calls they wait for
  // failed or will never end (the device was lost, the launch failed or every thread ended).
  void Release(size_t d) ABSL_EXCLUSIVE_LOCKS_REQUIRED(mu_);

  std::vector<DispatchDevice> devices_;
  const bool stable_;
  std::atomic<uint64_t>* const progress_;
  bool build_only_ = false;  // set in the constructor, before the threads start
  uint64_t min_indices_per_thread_;
  std::vector<float> cost_hint_;                      // by tile index; empty: batches by tile count
  std::vector<float> measured_ ABSL_GUARDED_BY(mu_);  // by tile index
  // When each device's last call ended on the host: a call queued behind it starts then.
  std::vector<std::chrono::steady_clock::time_point> last_end_ ABSL_GUARDED_BY(mu_);
  size_t initial_tiles_ = 0;       // the launch's tiles, set in the constructor
  uint64_t tile_indices_ = 1;      // launch indices of the launch's largest tile, ditto
  std::atomic<bool> stop_{false};  // cancels running calls: user cancel or launch failure

  mutable std::mutex mu_;
  std::condition_variable work_cv_;  // device threads: tiles available or launch over
  std::condition_variable done_cv_;  // launching thread: a batch finished or a thread ended
  std::vector<Queue> queues_ ABSL_GUARDED_BY(mu_);  // stable: one per device; dynamic: [0]
  std::vector<bool> lost_ ABSL_GUARDED_BY(mu_);
  std::vector<LostDevice> lost_reasons_ ABSL_GUARDED_BY(mu_);
  std::vector<int> tile_losses_ ABSL_GUARDED_BY(mu_);  // by tile index: devices lost running it
  // Per device: the batches of its calls in flight (owned by the threads making them), to tell
  // whether a device that died was running a tile that had taken another device down.
  std::vector<std::vector<const std::vector<v1::Tile>*>> in_flight_ ABSL_GUARDED_BY(mu_);
  // Per device: whether its only call in flight runs one tile that was in flight on a lost
  // device (a suspect), so that losing this device too points at that tile's programs.
  std::vector<bool> alone_with_suspect_ ABSL_GUARDED_BY(mu_);
  uint64_t remaining_ ABSL_GUARDED_BY(mu_) = 0;  // tiles not yet finished
  size_t running_threads_ ABSL_GUARDED_BY(mu_) = 0;
  std::vector<FinishedBatch> finished_ ABSL_GUARDED_BY(mu_);
  // Per device: batches that ended before an earlier-run call, by sequence, and the sequence
  // handed over next.
  std::vector<std::map<uint64_t, FinishedBatch>> held_ ABSL_GUARDED_BY(mu_);
  std::vector<uint64_t> next_sequence_ ABSL_GUARDED_BY(mu_);
  absl::Status status_ ABSL_GUARDED_BY(mu_);
  int failed_device_ ABSL_GUARDED_BY(mu_) = -1;
  bool cancelled_ ABSL_GUARDED_BY(mu_) = false;
  std::vector<std::thread> threads_;  // last: started in the constructor body
};

}  // namespace tessera::scheduler

#endif  // TESSERA_SCHEDULER_DISPATCHER_H_

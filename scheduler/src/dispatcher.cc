#include "tessera/scheduler/dispatcher.h"

#include <algorithm>
#include <exception>
#include <system_error>
#include <utility>

#include "absl/strings/str_cat.h"
#include "tessera/scheduler/tiling.h"

namespace tessera::scheduler {
namespace {

// Calls a device runs back to back; more only queue up on the device.
constexpr int kCallsInFlight = 2;
// The most launch indices per device thread in one batch (64 of the largest 2D tiles). Batches
// of devices that share a queue are cut smaller by kGuidedShare, which balances the tail of a
// launch; this bound only keeps the first ones from growing without limit. It was four tiles:
// on the 2-core machine a 1080p launch over two one-thread workers then took 141 calls, whose
// sending (13-17% of the launch) took the core from tracing, and ran at 0.74-0.80 of linear
// against 0.88-0.92 with 43 calls, in alternation (bench/README.md). Counted in launch indices,
// not tiles, so that the small tiles of a launch over many threads do not multiply the calls.
constexpr uint64_t kIndicesPerThread = 64 * 64 * 64;
constexpr uint64_t kMinIndicesPerThread = 64 * 64;
// A call takes 1/(kGuidedShare * live devices) of the shared queue. An eighth made some 400 calls
// per 1080p launch over 16 workers, whose host time (about 0.45 ms each on the 16-core machine)
// took a core from the workers; a quarter makes half as many and ended no later (bench/README.md).
constexpr size_t kGuidedShare = 4;

}  // namespace

Dispatcher::Dispatcher(std::vector<DispatchDevice> devices, std::vector<v1::Tile> tiles,
                       bool stable_ownership, std::atomic<uint64_t>* progress,
                       uint64_t min_indices_per_thread, std::vector<float> tile_costs)
    : devices_(std::move(devices)),
      stable_(stable_ownership),
      progress_(progress),
      min_indices_per_thread_(std::max(min_indices_per_thread, kMinIndicesPerThread)),
      cost_hint_(std::move(tile_costs)) {
  const size_t n = devices_.size();
  std::lock_guard<std::mutex> lock(mu_);
  if (n == 0) {
    status_ = absl::UnavailableError("no device to run the launch on");
    return;
  }
  queues_.resize(stable_ ? n : 1);
  lost_.assign(n, false);
  held_.resize(n);
  next_sequence_.assign(n, 1);
  in_flight_.assign(n, {});
  alone_with_suspect_.assign(n, false);
  std::vector<size_t> live;
  for (size_t d = 0; d < n; ++d) {
    if (devices_[d].device == nullptr) {
      lost_[d] = true;  // gone before the launch: not reported as lost again
    } else {
      live.push_back(d);
    }
  }
  if (live.empty()) {
    status_ = absl::UnavailableError("no device to run the launch on");
    return;
  }
  uint32_t max_index = 0;
  for (const v1::Tile& t : tiles) max_index = std::max(max_index, t.index());
  tile_losses_.assign(tiles.empty() ? 0 : size_t{max_index} + 1, 0);
  initial_tiles_ = tiles.size();
  measured_.assign(tile_losses_.size(), 0.f);
  last_end_.assign(n, std::chrono::steady_clock::time_point());
  if (cost_hint_.size() != tile_losses_.size()) cost_hint_.clear();  // other tiles'
  double total_cost = 0;
  for (float c : cost_hint_) {
    if (!(c > 0.f)) {  // a tile never measured: no hint at all
      cost_hint_.clear();
      break;
    }
    total_cost += c;
  }
  // No tile counts as nearly free: one that was cheap last time may not be now.
  if (!cost_hint_.empty()) {
    const float least = static_cast<float>(total_cost / cost_hint_.size() / 8);
    for (float& c : cost_hint_) c = std::max(c, least);
  }
  // No tiles (the all-zero launch builds accelerations only): every device gets one empty call.
  build_only_ = tiles.empty();
  remaining_ = build_only_ ? live.size() : tiles.size();
  // In launch order: neighbouring tiles share a batch, and the caches. (An order spreading every
  // batch over the launch cut the idle time at the end of 16-worker launches from 5.1% to 3.0% but
  // made 2-worker ones 3-5% slower: bench/README.md.)
  for (v1::Tile& t : tiles) {
    tile_indices_ = std::max(tile_indices_, TileIndices(t));
    size_t queue = 0;
    if (stable_) {
      // Tile i belongs to device i mod N; a device gone before the launch hands its tiles to the
      // others by tile index, as Requeue does for one lost during it.
      queue = t.index() % n;
      if (lost_[queue]) queue = live[t.index() % live.size()];
    }
    queues_[queue].tiles.push_back(std::move(t));
  }
  // Two calls in flight per device (one for the all-zero launch): the device runs them one after
  // the other, so the next batch is waiting there when one ends, instead of a round trip later.
  const int calls = build_only_ ? 1 : kCallsInFlight;
  running_threads_ = live.size() * calls;
  try {
    threads_.reserve(live.size() * calls);
    for (int c = 0; c < calls; ++c) {
      for (size_t d : live) {
        threads_.emplace_back([this, d] { Run(d); });
      }
    }
  } catch (const std::exception& e) {
    // Out of threads or memory (a process limit, say): the launch fails, and the threads that did
    // start (blocked on mu_ until this returns) see stop_ and end; none of their calls began.
    running_threads_ = threads_.size();
    status_ = absl::ResourceExhaustedError(absl::StrCat("could not start the launch's ",
                                                        live.size() * calls, " dispatch threads (",
                                                        threads_.size(), " started): ", e.what()));
    stop_ = true;
  }
}

namespace {

// What an exception that escaped a dispatch thread's own work (not a device's call) means.
absl::Status DispatchFailure(const std::exception& e) {
  if (dynamic_cast<const std::bad_alloc*>(&e) != nullptr) {
    return absl::ResourceExhaustedError("out of memory while dispatching the launch's tiles");
  }
  return absl::ResourceExhaustedError(absl::StrCat("dispatching the launch's tiles: ", e.what()));
}

}  // namespace

Dispatcher::~Dispatcher() {
  {
    std::lock_guard<std::mutex> lock(mu_);
    stop_ = true;
  }
  work_cv_.notify_all();
  for (std::thread& t : threads_) t.join();
}

bool Dispatcher::CanTake(size_t d) const {
  const std::deque<v1::Tile>& queue = queues_[stable_ ? d : 0].tiles;
  if (queue.empty()) return false;
  if (in_flight_[d].empty()) return true;
  // A suspect runs on a device with no other call in flight, and nothing joins it there until it
  // ends: only then does losing the device point at the suspect's programs (Requeue).
  return !alone_with_suspect_[d] && tile_losses_[queue.front().index()] == 0;
}

std::vector<v1::Tile> Dispatcher::Take(size_t d) {
  std::deque<v1::Tile>& queue = queues_[stable_ ? d : 0].tiles;
  if (!CanTake(d)) return {};
  const uint64_t threads = static_cast<uint64_t>(std::max(devices_[d].threads, 1));
  // Sized by the launch's full tiles, not the queue's front, which may be a clipped edge tile.
  size_t batch = std::max<uint64_t>(1, kIndicesPerThread * threads / tile_indices_);
  if (devices_.size() == 1) {
    // Nothing to balance with: one call takes everything, and the device's own thread pool
    // balances its tiles without a barrier between batches.
    batch = queue.size();
  } else if (!stable_) {
    // Shrink batches as the shared queue drains so that no device is left holding a long tail
    // while the others idle: with two calls in flight per device, at most half of the queue is
    // out at once (and a lost device takes back no more than that).
    // But not below a 64x64 tile's worth of launch indices per thread (or what the launch asked
    // for: light launches want fewer, larger calls), short of a guided share of the whole launch
    // (so that a launch heavier than its estimate still splits in several calls per device): a
    // call costs a round trip, and one-tile calls of small tiles leave devices waiting for it.
    const size_t live =
        std::max<size_t>(1, static_cast<size_t>(std::count(lost_.begin(), lost_.end(), false)));
    const size_t share =
        std::max<size_t>(1, (initial_tiles_ + kGuidedShare * live - 1) / (kGuidedShare * live));
    const size_t floor = std::min<size_t>(
        std::max<uint64_t>(1, min_indices_per_thread_ * threads / tile_indices_), share);
    if (cost_hint_.empty()) {
      batch = std::clamp<size_t>(std::max(queue.size() / (kGuidedShare * live), floor), 1, batch);
    } else {
      // The same guided share, of the queue's cost rather than its tiles; but never more tiles
      // than the count's share: the hint comes from an earlier launch, and what was cheap there
      // may not be now. So hints only split expensive regions finer.
      double queued = 0;
      for (const v1::Tile& t : queue) queued += cost_hint_[t.index()];
      const double target = queued / static_cast<double>(kGuidedShare * live);
      const size_t most =
          std::min(batch, std::max<size_t>(floor, queue.size() / (kGuidedShare * live)));
      size_t n = 0;
      double cost = 0;
      while (n < queue.size() && n < most && (n < floor || cost < target)) {
        cost += cost_hint_[queue[n].index()];
        ++n;
      }
      batch = std::max<size_t>(n, 1);
    }
  }
  batch = std::min(batch, queue.size());
  std::vector<v1::Tile> tiles;
  tiles.reserve(batch);
  for (size_t i = 0; i < batch; ++i) {
    // A tile that was in flight on a lost device runs alone (Requeue): should its device be lost
    // too, that tile alone was running.
    const bool suspect = tile_losses_[queue.front().index()] > 0;
    if (suspect && !tiles.empty()) break;
    tiles.push_back(std::move(queue.front()));
    queue.pop_front();
    if (suspect) break;
  }
  // Whether the device now runs a suspect and nothing else: only then does its loss point at
  // that tile (Requeue).
  alone_with_suspect_[d] =
      in_flight_[d].empty() && tiles.size() == 1 && tile_losses_[tiles.front().index()] > 0;
  return tiles;
}

void Dispatcher::Fail(size_t d, absl::Status status) {
  if (status_.ok()) {
    status_ = std::move(status);
    failed_device_ = static_cast<int>(d);
  }
  Release(d);
  stop_ = true;
  work_cv_.notify_all();
}

void Dispatcher::Requeue(size_t d, std::vector<v1::Tile> batch, bool ran_suspect) {
  std::vector<size_t> survivors;
  for (size_t i = 0; i < devices_.size(); ++i) {
    if (!lost_[i]) survivors.push_back(i);
  }
  if (survivors.empty()) {
    std::string reasons;
    for (const LostDevice& l : lost_reasons_) {
      absl::StrAppend(&reasons, reasons.empty() ? "" : "; ", devices_[l.device].name, ": ",
                      l.reason.message());
    }
    // Still a connection failure (nothing is left to run on), but a tile that took a second
    // device down with it points at a program that kills workers without a crash report
    // (remote workers, whose stderr the host cannot read).
    // The tile may be in this call's batch or in the device's other call (the device died
    // running it before this call's end reached the host).
    std::string hint;
    auto moved_here = [&](const std::vector<v1::Tile>& tiles) {
      for (const v1::Tile& t : tiles) {
        if (tile_losses_[t.index()] >= 1) {
          hint = absl::StrCat(": tile ", t.index(),
                              " was running on two of them, a program may be crashing them");
          return true;
        }
      }
      return false;
    };
    if (!moved_here(batch)) {
      for (const std::vector<v1::Tile>* other : in_flight_[d]) {
        if (moved_here(*other)) break;
      }
    }
    Fail(d, absl::UnavailableError(absl::StrCat("every device was lost (", reasons, ")", hint)));
    return;
  }
  // Tiles of a lost device's calls become suspects and run one per call from then on (Take). A
  // device lost after it said it started running a suspect, with no other call, points at that
  // tile's programs: a program that kills workers without a crash report would otherwise take
  // every device down. A device lost before it said so may have been dead already when it was
  // given the tile (two workers killed at one moment): no evidence. Independent losses (workers
  // killed, a machine gone) cost time only: their tiles run again elsewhere.
  for (const v1::Tile& t : batch) {
    if (++tile_losses_[t.index()] >= 2 && batch.size() == 1 && ran_suspect &&
        alone_with_suspect_[d]) {
      Fail(d, absl::AbortedError(absl::StrCat(
                  "tile ", t.index(), " was running alone on ", devices_[d].name,
                  " when it was lost, after another device was lost running it: a program may "
                  "be crashing them")));
      return;
    }
  }
  if (stable_) {
    // Survivors take over by tile index, so the new owners are the same for every launch of this
    // size on the reduced device set.
    for (v1::Tile& t : queues_[d].tiles) batch.push_back(std::move(t));
    queues_[d].tiles.clear();
    for (v1::Tile& t : batch) {
      queues_[survivors[t.index() % survivors.size()]].tiles.push_back(std::move(t));
    }
  } else {
    for (auto it = batch.rbegin(); it != batch.rend(); ++it) {
      queues_[0].tiles.push_front(std::move(*it));
    }
  }
  work_cv_.notify_all();
}

void Dispatcher::Run(size_t d) {
  std::unique_lock<std::mutex> lock(mu_);
  while (true) {
    std::vector<v1::Tile> batch;
    try {
      if (!RunCall(d, lock, batch)) break;
    } catch (const std::exception& e) {
      // Memory ran out outside the device's call (taking tiles, building the request, keeping
      // results): the launch fails instead of the exception ending the process.
      if (!lock.owns_lock()) lock.lock();
      std::vector<const std::vector<v1::Tile>*>& calls = in_flight_[d];
      calls.erase(std::remove(calls.begin(), calls.end(), &batch), calls.end());
      Fail(d, DispatchFailure(e));
      break;
    }
  }
  if (--running_threads_ == 0) {
    for (size_t i = 0; i < devices_.size(); ++i) Release(i);
  }
  done_cv_.notify_all();
}

bool Dispatcher::RunCall(size_t d, std::unique_lock<std::mutex>& lock,
                         std::vector<v1::Tile>& batch) {
  DispatchDevice& device = devices_[d];
  work_cv_.wait(lock, [&]() ABSL_EXCLUSIVE_LOCKS_REQUIRED(mu_) {
    return stop_ || remaining_ == 0 || lost_[d] || build_only_ || CanTake(d);
  });
  if (stop_ || remaining_ == 0 || lost_[d]) return false;
  batch = Take(d);
  if (batch.empty() && !build_only_) return true;
  in_flight_[d].push_back(&batch);
  // A suspect alone: the device says when it starts running it, so that only a loss after that
  // counts against the tile (Requeue).
  const bool watch_start = alone_with_suspect_[d];
  lock.unlock();

  const auto taken = std::chrono::steady_clock::now();
  v1::LaunchRequest request = device.header;
  for (const v1::Tile& t : batch) *request.add_tiles() = t;
  request.set_report_start(watch_start);
  FinishedBatch finished;
  finished.device = d;
  finished.tiles = batch.size();
  std::mutex results_mu;  // devices call back from their own threads
  uint64_t reported = 0;  // tiles of this call the device said it finished (progress)
  bool started = false;   // the device said it began running the call (report_start)
  absl::Status status;
  try {
    status = device.device->Launch(request, stop_, [&](v1::TileResult&& result) {
      std::lock_guard<std::mutex> results_lock(results_mu);
      if (result.tile_index() == kHeartbeatTileIndex) {
        if (result.started()) started = true;
        const uint64_t done = std::min<uint64_t>(result.tiles_done(), batch.size());
        if (done > reported) AddProgress(done - reported);
        reported = std::max(reported, done);
        return;
      }
      finished.results.push_back(std::move(result));
    });
  } catch (const std::bad_alloc&) {
    status = absl::ResourceExhaustedError("out of memory running the launch's tiles");
  } catch (const std::system_error& e) {
    status = absl::ResourceExhaustedError(absl::StrCat("could not start a thread: ", e.what()));
  } catch (const std::exception& e) {
    status = absl::InternalError(absl::StrCat("threw: ", e.what()));
  } catch (...) {
    status = absl::InternalError("threw a non-standard exception");
  }

  for (const v1::TileResult& r : finished.results) {
    if (r.tile_index() == kFinalTileIndex && r.call_sequence() != 0) {
      finished.sequence = r.call_sequence();
    }
  }
  lock.lock();
  std::vector<const std::vector<v1::Tile>*>& calls = in_flight_[d];
  calls.erase(std::find(calls.begin(), calls.end(), &batch));
  // After a loss, a device's other thread may wait for this call's end to take a suspect (CanTake).
  if (!lost_reasons_.empty()) work_cv_.notify_all();
  if (status.ok()) {
    const auto ended = std::chrono::steady_clock::now();
    const double seconds =
        std::chrono::duration<double>(ended - std::max(taken, last_end_[d])).count();
    last_end_[d] = ended;
    for (const v1::Tile& t : batch) {
      measured_[t.index()] = static_cast<float>(std::max(seconds, 1e-9) / batch.size());
    }
    AddProgress(batch.size() - reported);
    remaining_ -= build_only_ ? 1 : batch.size();
    Deliver(std::move(finished));
    if (remaining_ == 0) work_cv_.notify_all();
    return !build_only_;
  }
  if (stop_) return false;  // cancelled, or the launch already failed elsewhere
  const absl::StatusCode code = status.code();
  if (code == absl::StatusCode::kUnavailable || code == absl::StatusCode::kDeadlineExceeded) {
    // The call's tiles count again where they run next. (Progress goes down only here: a
    // cancelled or failed launch keeps what it reported.)
    if (progress_ != nullptr) progress_->fetch_sub(reported, std::memory_order_relaxed);
    if (!lost_[d]) lost_reasons_.push_back({d, status});
    lost_[d] = true;
    Release(d);
    if (build_only_) {
      --remaining_;
      if (std::count(lost_.begin(), lost_.end(), false) == 0) Requeue(d, {});
    } else {
      Requeue(d, std::move(batch), watch_start && started);
    }
    return false;
  }
  if (code == absl::StatusCode::kAborted) {
    // The device crashed running a program: that program would crash the next device too.
    if (!lost_[d]) lost_reasons_.push_back({d, status});
    lost_[d] = true;
  }
  Fail(d, std::move(status));
  return false;
}

void Dispatcher::Deliver(FinishedBatch batch) {
  const size_t d = batch.device;
  if (batch.sequence == 0 || batch.sequence < next_sequence_[d]) {
    finished_.push_back(std::move(batch));  // unordered, or its predecessors were released
  } else {
    std::map<uint64_t, FinishedBatch>& held = held_[d];
    held.emplace(batch.sequence, std::move(batch));
    for (auto it = held.begin(); it != held.end() && it->first == next_sequence_[d];
         it = held.erase(it)) {
      finished_.push_back(std::move(it->second));
      ++next_sequence_[d];
    }
  }
  done_cv_.notify_all();
}

void Dispatcher::Release(size_t d) {
  for (auto& [sequence, batch] : held_[d]) {
    finished_.push_back(std::move(batch));
    next_sequence_[d] = sequence + 1;
  }
  held_[d].clear();
  done_cv_.notify_all();
}

bool Dispatcher::Wait(std::chrono::steady_clock::time_point deadline,
                      std::vector<FinishedBatch>* out) {
  std::unique_lock<std::mutex> lock(mu_);
  auto ready = [&]() ABSL_EXCLUSIVE_LOCKS_REQUIRED(mu_) {
    return !finished_.empty() || running_threads_ == 0;
  };
  if (deadline == std::chrono::steady_clock::time_point::max()) {
    done_cv_.wait(lock, ready);
  } else {
    done_cv_.wait_until(lock, deadline, ready);
  }
  for (FinishedBatch& b : finished_) out->push_back(std::move(b));
  finished_.clear();
  return running_threads_ == 0;
}

void Dispatcher::Cancel() {
  {
    std::lock_guard<std::mutex> lock(mu_);
    cancelled_ = true;
    stop_ = true;
  }
  work_cv_.notify_all();
}

std::vector<float> Dispatcher::tile_costs() const {
  std::lock_guard<std::mutex> lock(mu_);
  if (!status_.ok() || remaining_ != 0 || build_only_) return {};
  return measured_;
}

absl::Status Dispatcher::status() const {
  std::lock_guard<std::mutex> lock(mu_);
  if (!status_.ok()) return status_;
  if (cancelled_) return absl::CancelledError("launch cancelled");
  if (remaining_ != 0) {
    return absl::InternalError(absl::StrCat(remaining_, " tiles were never run"));
  }
  return absl::OkStatus();
}

int Dispatcher::failed_device() const {
  std::lock_guard<std::mutex> lock(mu_);
  return failed_device_;
}

std::vector<LostDevice> Dispatcher::lost() const {
  std::lock_guard<std::mutex> lock(mu_);
  return lost_reasons_;
}

}  // namespace tessera::scheduler

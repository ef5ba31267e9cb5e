#include "worker_service.h"

#include <malloc.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <future>
#include <mutex>
#include <new>
#include <thread>
#include <utility>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "tessera/scheduler/launch_timing.h"
#include "tessera/scheduler/log.h"
#include "tessera/scheduler/system_info.h"
#include "tessera/worker/inproc_device.h"
#include "transport/worker_wire.h"

#ifndef TESSERA_VERSION
#define TESSERA_VERSION "unknown"
#endif

namespace tessera::worker {
namespace {

using transport::DeltaAssembler;
using transport::SplitTileResult;
using transport::ToGrpcStatus;

// How often a launch looks at whether its call was cancelled (results wake it at once).
constexpr std::chrono::milliseconds kCancelPoll{20};
// How often a running launch says it is alive when no tile finished; well below the host's
// silence deadline (GrpcDevice, TESSERA_WORKER_TIMEOUT).
constexpr std::chrono::milliseconds kHeartbeatInterval{500};

// How many dropped sessions a worker remembers, to tell their hosts why (16 bytes each).
constexpr size_t kMaxDropped = 4096;

v1::TileResult Heartbeat(const v1::LaunchRequest& request) {
  v1::TileResult heartbeat;
  heartbeat.set_launch_id(request.launch_id());
  heartbeat.set_tile_index(kHeartbeatTileIndex);
  return heartbeat;
}

int ResolveThreads(int threads) {
  if (threads > 0) return threads;
  return scheduler::HardwareThreads();  // the CPUs it may run on
}

std::string DeviceName() {
  char host[256] = {};
  if (gethostname(host, sizeof(host) - 1) != 0) return "tessera-worker";
  return absl::StrCat("tessera-worker@", host);
}

// TESSERA_LAUNCH_TIMING=1 (as on the host): one line per call on stderr (the worker's log) with
// where its time went and what the process asked of the kernel meanwhile, to tell tracing from
// waiting, sending and system work when worker processes scale worse than threads.
class CallTiming {
 public:
  CallTiming() : enabled_(scheduler::LaunchTimingEnabled()), arrived_(Clock::now()) {}
  void Locked() {
    if (!enabled_) return;
    locked_ = Clock::now();
    getrusage(RUSAGE_SELF, &before_);
  }
  void Ran() {
    if (enabled_) ran_ = Clock::now();
  }
  void Report(const v1::LaunchRequest& request) {
    if (!enabled_) return;
    rusage after{};
    getrusage(RUSAGE_SELF, &after);
    const auto end = Clock::now();
    auto ms = [](Clock::duration d) {
      return std::chrono::duration<double, std::milli>(d).count();
    };
    log::Info(log::Component::kWorker,
              "call of launch %llu (%d tiles): waited %.1fms, ran %.1fms, sent the rest in %.1fms; "
              "cpu user %.1fms sys %.1fms, page faults %ld, context switches %ld voluntary %ld "
              "involuntary; monotonic clock %.3f to %.3fms",
              static_cast<unsigned long long>(request.launch_id()), request.tiles_size(),
              ms(locked_ - arrived_), ms(ran_ - locked_), ms(end - ran_),
              scheduler::Milliseconds(after.ru_utime, before_.ru_utime),
              scheduler::Milliseconds(after.ru_stime, before_.ru_stime),
              after.ru_minflt - before_.ru_minflt, after.ru_nvcsw - before_.ru_nvcsw,
              after.ru_nivcsw - before_.ru_nivcsw, ms(arrived_.time_since_epoch()),
              ms(end.time_since_epoch()));
  }

 private:
  using Clock = std::chrono::steady_clock;
  const bool enabled_;
  Clock::time_point arrived_, locked_, ran_;
  rusage before_{};
};

// Results travel from the launch's threads to the RPC thread, which alone writes to the stream.
class ResultQueue {
 public:
  void Push(v1::TileResult&& result) {
    std::lock_guard<std::mutex> lock(mu_);
    queue_.push_back(std::move(result));
    cv_.notify_one();
  }
  void Finish(absl::Status status) {
    std::lock_guard<std::mutex> lock(mu_);
    status_ = std::move(status);
    done_ = true;
    cv_.notify_one();
  }
  // Waits up to `timeout` for results; `*done` once the launch returned and nothing is left.
  std::deque<v1::TileResult> Take(std::chrono::milliseconds timeout, bool* done) {
    std::unique_lock<std::mutex> lock(mu_);
    cv_.wait_for(lock, timeout, [&] { return !queue_.empty() || done_; });
    std::deque<v1::TileResult> batch;
    batch.swap(queue_);
    *done = done_;
    return batch;
  }
  const absl::Status& status() const { return status_; }  // after done

 private:
  std::mutex mu_;
  std::condition_variable cv_;
  std::deque<v1::TileResult> queue_;
  bool done_ = false;
  absl::Status status_;
};

}  // namespace

WorkerService::WorkerService(int threads, transport::ResultArena* arena, SessionLimits limits)
    : threads_(ResolveThreads(threads)), name_(DeviceName()), arena_(arena), limits_(limits) {
  if (limits_.idle_timeout > absl::ZeroDuration()) reaper_ = std::thread([this] { ReapLoop(); });
}

WorkerService::~WorkerService() {
  {
    absl::MutexLock lock(&mu_);
    stopping_ = true;
  }
  reap_cv_.Signal();
  if (reaper_.joinable()) reaper_.join();
}

void WorkerService::Use::End() {
  if (session_ == nullptr) return;
  {
    absl::MutexLock lock(&service_->mu_);
    if (--session_->calls == 0) session_->idle_since = Clock::now();
  }
  session_.reset();
}

absl::Status WorkerService::Missing(uint64_t id, absl::string_view what) {
  auto dropped = dropped_.find(id);
  if (dropped == dropped_.end()) {
    return absl::FailedPreconditionError(
        absl::StrCat("no state for session ", id, " on this worker: ", what));
  }
  // A device loss to the host (UNAVAILABLE): it starts a new session from the whole state.
  return absl::UnavailableError(absl::StrFormat(
      "%s dropped session %d after %.0f s without a call (--session-idle-timeout %g): its state "
      "is gone, and the host starts the session afresh",
      name_, id, absl::ToDoubleSeconds(dropped->second),
      absl::ToDoubleSeconds(limits_.idle_timeout)));
}

WorkerService::Use WorkerService::UseExisting(uint64_t id) {
  absl::MutexLock lock(&mu_);
  auto it = sessions_.find(id);
  if (it == sessions_.end()) return Use();
  ++it->second->calls;
  return Use(this, it->second);
}

absl::Status WorkerService::ShuttingDown(absl::string_view what) {
  absl::MutexLock lock(&mu_);
  return absl::UnavailableError(absl::StrCat(name_, " (pid ", getpid(), ") is shutting down (",
                                             shutdown_reason_, "): it refused ", what,
                                             "; it finishes only launches already under way"));
}

void WorkerService::BeginShutdown(const std::string& why) {
  {
    absl::MutexLock lock(&mu_);
    shutdown_reason_ = why;
  }
  shutting_down_ = true;
}

void WorkerService::CountTiles(uint64_t tiles) {
  tiles_ += tiles;
  const int64_t second =
      std::chrono::duration_cast<std::chrono::seconds>(Clock::now() - started_).count();
  absl::MutexLock lock(&rate_mu_);
  TileSecond& slot = tile_seconds_[second % 60];
  if (slot.second != second) slot = TileSecond{second, 0};
  slot.tiles += tiles;
}

WorkerService::Stats WorkerService::GetStats() {
  Stats stats;
  {
    absl::MutexLock lock(&mu_);
    stats.sessions = static_cast<uint32_t>(sessions_.size());
  }
  stats.launches = launches_.load();
  stats.tiles = tiles_.load();
  const double uptime = std::chrono::duration<double>(Clock::now() - started_).count();
  const int64_t now = static_cast<int64_t>(uptime);
  uint64_t recent = 0;
  {
    absl::MutexLock lock(&rate_mu_);
    for (const TileSecond& slot : tile_seconds_) {
      if (slot.second >= 0 && slot.second > now - 60 && slot.second <= now) recent += slot.tiles;
    }
  }
  stats.tiles_per_s = static_cast<double>(recent) / std::clamp(uptime, 1.0, 60.0);
  return stats;
}

absl::StatusOr<WorkerService::Use> WorkerService::UseForDelta(uint64_t id, uint64_t sequence) {
  // A state update comes before a launch: a stopping worker takes none.
  if (shutting_down()) {
    return ShuttingDown(sequence == 1 ? "a new session" : "a state update");
  }
  std::vector<std::shared_ptr<Session>> dropped;  // destroyed after mu_ is released
  absl::MutexLock lock(&mu_);
  auto it = sessions_.find(id);
  if (it != sessions_.end()) {
    ++it->second->calls;
    return Use(this, it->second);
  }
  if (sequence != 1) {
    return Missing(id, absl::StrCat("state delta ", sequence, " out of order (expected 1)"));
  }
  const Clock::time_point now = Clock::now();
  if (limits_.max_sessions > 0 && sessions_.size() >= static_cast<size_t>(limits_.max_sessions)) {
    TakeIdleLocked(now, &dropped);
    if (sessions_.size() >= static_cast<size_t>(limits_.max_sessions)) {
      return absl::ResourceExhaustedError(absl::StrCat(
          name_, " (pid ", getpid(), ") already holds ", sessions_.size(),
          " sessions, as many as its --max-sessions ", limits_.max_sessions,
          " allows: a host context holds one until it is destroyed",
          limits_.idle_timeout > absl::ZeroDuration()
              ? absl::StrCat(" or has made no call for --session-idle-timeout ",
                             absl::ToDoubleSeconds(limits_.idle_timeout), " s")
              : std::string(),
          ". Destroy contexts that are done, or start the worker with a higher --max-sessions"));
    }
  }
  dropped_.erase(id);  // a host starting afresh with an id it used before
  auto session = std::make_shared<Session>(now);
  session->calls = 1;
  sessions_.emplace(id, session);
  return Use(this, std::move(session));
}

bool WorkerService::IsCurrent(uint64_t id, const std::shared_ptr<Session>& session) {
  absl::MutexLock lock(&mu_);
  auto it = sessions_.find(id);
  return it != sessions_.end() && it->second == session;
}

void WorkerService::ForgetIfEmpty(uint64_t id, const std::shared_ptr<Session>& session) {
  absl::MutexLock lock(&mu_);
  auto it = sessions_.find(id);
  if (it != sessions_.end() && it->second == session) sessions_.erase(it);
}

WorkerService::Clock::time_point WorkerService::TakeIdleLocked(
    Clock::time_point now, std::vector<std::shared_ptr<Session>>* dropped) {
  Clock::time_point next = Clock::time_point::max();
  if (limits_.idle_timeout <= absl::ZeroDuration()) return next;
  const auto timeout = absl::ToChronoNanoseconds(limits_.idle_timeout);
  for (auto it = sessions_.begin(); it != sessions_.end();) {
    auto current = it++;
    Session& session = *current->second;
    if (session.calls > 0) continue;  // its call's end starts its idle time afresh
    if (now - session.idle_since < timeout) {
      next = std::min(next, session.idle_since + timeout);
      continue;
    }
    const uint64_t id = current->first;
    dropped_[id] = absl::FromChrono(now - session.idle_since);
    dropped_order_.push_back(id);
    while (dropped_order_.size() > kMaxDropped) {
      dropped_.erase(dropped_order_.front());
      dropped_order_.pop_front();
    }
    dropped->push_back(std::move(current->second));
    sessions_.erase(current);
  }
  return next;
}

void WorkerService::ReapLoop() {
  // The loop sleeps until the earliest idle session is due, and an eighth of the timeout more, so
  // that sessions that went idle together (a host that vanished) are dropped, and logged, together.
  // A session in use has no due time yet (its idle time starts when its last call ends), so the
  // loop also looks again after a quarter of the timeout: a session is dropped within 1.25
  // timeouts of its last call.
  const auto period = absl::ToChronoNanoseconds(limits_.idle_timeout / 4);
  const auto slack = absl::ToChronoNanoseconds(limits_.idle_timeout / 8);
  for (;;) {
    std::vector<std::shared_ptr<Session>> dropped;
    {
      absl::MutexLock lock(&mu_);
      if (stopping_) return;
      const Clock::time_point now = Clock::now();
      Clock::time_point next = TakeIdleLocked(now, &dropped);
      next = next == Clock::time_point::max() ? now + period : std::min(next + slack, now + period);
      if (dropped.empty()) {
        reap_cv_.WaitWithTimeout(&mu_, absl::FromChrono(next - now));
        continue;
      }
    }
    log::Info(log::Component::kWorker,
              "dropped %zu session(s) without a call for %g s (--session-idle-timeout); %s",
              dropped.size(), absl::ToDoubleSeconds(limits_.idle_timeout),
              "their hosts, should they come back, are told so and start afresh");
    dropped.clear();  // the devices, replicas and plans go here, outside mu_
    // Give what they held back to the system: the worker keeps freed memory in its heap
    // otherwise (worker_main.cc raises glibc's trim threshold for its calls' messages).
    malloc_trim(0);
  }
}

grpc::Status WorkerService::Apply(grpc::ServerContext* context,
                                  grpc::ServerReader<v1::ApplyChunk>* reader,
                                  v1::ApplyReply* reply) {
  InProgress in_progress(this);
  // gRPC would answer an exception with "Unexpected error in RPC handling", naming nothing.
  try {
    return ApplyStream(context, reader);
  } catch (const std::bad_alloc&) {
    return grpc::Status(grpc::StatusCode::RESOURCE_EXHAUSTED,
                        "the worker ran out of memory taking the state update; nothing was "
                        "applied");
  }
}

grpc::Status WorkerService::ApplyStream(grpc::ServerContext* context,
                                        grpc::ServerReader<v1::ApplyChunk>* reader) {
  // No delta larger than the machine's memory can be applied: refuse it as it arrives.
  DeltaAssembler assembler(scheduler::TotalSystemMemory() > 0 ? scheduler::TotalSystemMemory()
                                                              : ~uint64_t{0});
  v1::ApplyChunk part;
  // The session is known from the first message: it is in use from then on (not dropped while a
  // large update arrives), and a session the worker cannot take is refused before the rest comes.
  Use use;
  uint64_t id = 0, sequence = 0;
  while (reader->Read(&part)) {
    if (!use && part.has_delta()) {
      id = part.delta().session_id();
      sequence = part.delta().sequence();
      absl::StatusOr<Use> found = UseForDelta(id, sequence);
      if (!found.ok()) return ToGrpcStatus(found.status());
      use = *std::move(found);
    }
    if (absl::Status s = assembler.Add(std::move(part)); !s.ok()) return ToGrpcStatus(s);
    part.Clear();
  }
  if (context->IsCancelled()) return grpc::Status(grpc::StatusCode::CANCELLED, "Apply cancelled");
  absl::StatusOr<v1::StateDelta> delta = std::move(assembler).Finish();
  if (!delta.ok()) return ToGrpcStatus(delta.status());
  if (!use) {  // the assembler takes no stream without its header; kept from a null session
    return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT, "state update without its header");
  }

  while (true) {
    use.get()->mu.Lock();
    // EndSession, or a failed first delta, may have dropped the session while this call waited
    // for it: a delta with sequence 1 starts a new one, any other finds none.
    if (IsCurrent(id, use.shared())) break;
    use.get()->Release();
    absl::StatusOr<Use> found = UseForDelta(id, sequence);
    if (!found.ok()) return ToGrpcStatus(found.status());
    use = *std::move(found);
  }
  Session* session = use.get();
  Held held{session};
  absl::Status status;
  if (session->device == nullptr || delta->sequence() == 1) {
    // The device is replaced only if the new one accepts the delta: a rejected delta leaves the
    // session as it was.
    std::unique_ptr<Device> fresh = CreateInprocDevice(threads_, /*results_in_rounds=*/true);
    status = fresh->Apply(*delta);
    if (status.ok()) {
      session->device = std::move(fresh);
    } else if (session->device == nullptr) {
      ForgetIfEmpty(id, use.shared());
    }
  } else {
    status = session->device->Apply(*delta);
  }
  if (status.ok()) {
    if (delta->launch_id() > session->state_launch_id.load()) {
      session->state_launch_id.store(delta->launch_id());  // under mu: no other writer
    }
    session->buffers.Apply(*delta);
    session->buffer_bytes.store(session->buffers.total(), std::memory_order_relaxed);
  }
  return ToGrpcStatus(status);
}

grpc::Status WorkerService::Launch(grpc::ServerContext* context, const v1::LaunchRequest* request,
                                   grpc::ServerWriter<v1::TileResult>* writer) {
  InProgress in_progress(this);
  Use use = UseExisting(request->session_id());
  if (!use) {
    absl::MutexLock lock(&mu_);
    return ToGrpcStatus(Missing(request->session_id(), "a state delta must come first"));
  }
  Session* session = use.get();
  // Calls of one launch carry its id; a call with another starts the next launch.
  if (session->last_launch_id.load() != request->launch_id()) {
    if (shutting_down()) {
      return ToGrpcStatus(ShuttingDown(absl::StrCat("launch ", request->launch_id())));
    }
    if (session->last_launch_id.exchange(request->launch_id()) != request->launch_id()) {
      ++launches_;
    }
  }
  CallTiming timing;
  // The host keeps a second call queued behind the running one; it says it is alive while it
  // waits, or the host would take the wait for a hung worker.
  auto last_write = std::chrono::steady_clock::now();
  while (true) {
    uint64_t seen;
    {
      std::lock_guard<std::mutex> lock(session->turn_mu);
      seen = session->releases;
    }
    if (session->mu.TryLock()) break;
    if (context->IsCancelled()) {
      return grpc::Status(grpc::StatusCode::CANCELLED, "launch cancelled");
    }
    // A cancelled call still running holds the device, maybe forever (a program that never
    // returns): say nothing, so that the host's silence deadline takes this worker for hung.
    if (!session->holder_cancelled.load() &&
        std::chrono::steady_clock::now() - last_write >= kHeartbeatInterval) {
      if (!writer->Write(Heartbeat(*request))) {
        return grpc::Status(grpc::StatusCode::CANCELLED, "the host went away");
      }
      last_write = std::chrono::steady_clock::now();
    }
    // Woken by the release; the timeout only paces heartbeats and cancel checks.
    std::unique_lock<std::mutex> lock(session->turn_mu);
    session->turn_cv.wait_for(lock, kCancelPoll, [&] { return session->releases != seen; });
  }
  Held held{session};
  timing.Locked();
  if (session->device == nullptr) {
    return grpc::Status(grpc::StatusCode::FAILED_PRECONDITION,
                        absl::StrCat("no state for session ", request->session_id()));
  }
  // A call of a launch older than the state the device holds was given up by its host (the
  // launch failed while this call waited for the device): running it would write into the next
  // launch's buffers.
  if (request->launch_id() < session->state_launch_id.load()) {
    return grpc::Status(
        grpc::StatusCode::FAILED_PRECONDITION,
        absl::StrCat("a call of launch ", request->launch_id(),
                     " came after the state update for launch ", session->state_launch_id.load(),
                     " in session ", request->session_id(), "; not run"));
  }
  Device& device = *session->device;
  // The host asks when a call holds one tile that another device was lost running: that this
  // worker got as far as running it is what makes its loss evidence against the tile.
  if (request->report_start()) {
    v1::TileResult started = Heartbeat(*request);
    started.set_started(true);
    if (!writer->Write(started)) {
      return grpc::Status(grpc::StatusCode::CANCELLED, "the host went away");
    }
  }

  std::atomic<bool> cancel{false};
  ResultQueue results;
  std::future<void> ran = session->calls_thread.Post([&] {
    absl::Status status;
    try {
      status = device.Launch(*request, cancel,
                             [&](v1::TileResult&& result) { results.Push(std::move(result)); });
    } catch (const std::exception& e) {
      status = absl::InternalError(absl::StrCat("launch threw: ", e.what()));
    } catch (...) {
      status = absl::InternalError("launch threw a non-standard exception");
    }
    timing.Ran();
    results.Finish(std::move(status));
  });
  bool done = false;
  bool writable = true;
  last_write = std::chrono::steady_clock::now();
  // Large regions go through the memory shared with the host, while the call's slot has room.
  transport::ResultArena::Writer arena_writer(arena_, *request);
  while (!done) {
    std::deque<v1::TileResult> batch = results.Take(kCancelPoll, &done);
    // The device is done with this call and its results are messages: the next call may trace
    // while they go out (they carry the call's sequence, by which the host orders calls).
    if (done) held.Release();
    if (context->IsCancelled()) cancel = true;
    if (cancel.load() && !done) session->holder_cancelled = true;
    if (batch.empty() && !done && writable &&
        std::chrono::steady_clock::now() - last_write >= kHeartbeatInterval) {
      batch.push_back(Heartbeat(*request));
    }
    if (!batch.empty()) last_write = std::chrono::steady_clock::now();
    for (v1::TileResult& result : batch) {
      if (!writable) break;
      arena_writer.Move(&result);
      for (v1::TileResult& piece : SplitTileResult(std::move(result))) {
        if (!writer->Write(piece)) {  // the client went away
          writable = false;
          cancel = true;
          break;
        }
      }
    }
  }
  ran.wait();
  timing.Report(*request);
  if (cancel.load() || context->IsCancelled()) {
    return grpc::Status(grpc::StatusCode::CANCELLED, "launch cancelled");
  }
  if (results.status().ok()) CountTiles(static_cast<uint64_t>(request->tiles_size()));
  return ToGrpcStatus(results.status());
}

grpc::Status WorkerService::EndSession(grpc::ServerContext* context,
                                       const v1::EndSessionRequest* request,
                                       v1::EndSessionReply* reply) {
  InProgress in_progress(this);
  {
    Use use = UseExisting(request->session_id());
    if (!use) {
      absl::MutexLock lock(&mu_);
      dropped_.erase(request->session_id());  // its host is done with it: nothing left to tell
      return grpc::Status::OK;
    }
    use.get()->mu.Lock();  // after the running Apply or Launch
    Held held{use.get()};
    use.get()->device.reset();
    ForgetIfEmpty(request->session_id(), use.shared());
  }
  // The session is gone with its last reference (above): its memory goes back to the system, as
  // for a session dropped for idleness.
  malloc_trim(0);
  return grpc::Status::OK;
}

grpc::Status WorkerService::AccelerationBounds(grpc::ServerContext* context,
                                               const v1::AccelerationBoundsRequest* request,
                                               v1::AccelerationBoundsReply* reply) {
  InProgress in_progress(this);
  Use use = UseExisting(request->session_id());
  if (!use) {
    absl::MutexLock lock(&mu_);
    return ToGrpcStatus(Missing(request->session_id(), "a state delta must come first"));
  }
  use.get()->mu.Lock();  // after the running Apply or Launch
  Held held{use.get()};
  if (use.get()->device == nullptr) {
    return grpc::Status(grpc::StatusCode::FAILED_PRECONDITION,
                        absl::StrCat("no state for session ", request->session_id()));
  }
  absl::StatusOr<v1::AccelerationBoundsReply> bounds =
      use.get()->device->AccelerationBounds(*request);
  if (!bounds.ok()) return ToGrpcStatus(bounds.status());
  *reply = *std::move(bounds);
  return grpc::Status::OK;
}

grpc::Status WorkerService::Health(grpc::ServerContext* context, const v1::HealthRequest* request,
                                   v1::HealthReply* reply) {
  // A host looking for devices (a first launch, a late worker probed in the background) must not
  // take one that is going away.
  if (shutting_down()) return ToGrpcStatus(ShuttingDown("a new host"));
  reply->set_device_name(name_);
  reply->set_thread_count(static_cast<uint32_t>(threads_));
  reply->set_pid(getpid());
  reply->set_version(TESSERA_VERSION);
  reply->set_total_memory(scheduler::TotalSystemMemory());
  reply->set_clock_khz(static_cast<uint32_t>(scheduler::CpuClockKHz()));
  reply->set_resident_bytes(ResidentBytes());
  reply->set_max_sessions(static_cast<uint32_t>(std::max(limits_.max_sessions, 0)));
  reply->set_session_idle_timeout_seconds(absl::ToDoubleSeconds(limits_.idle_timeout));
  std::vector<std::pair<uint64_t, v1::SessionHealth>> sessions;
  {
    absl::MutexLock lock(&mu_);
    const Clock::time_point now = Clock::now();
    sessions.reserve(sessions_.size());
    for (const auto& [id, session] : sessions_) {
      v1::SessionHealth h;
      h.set_session_id(id);
      h.set_buffer_bytes(session->buffer_bytes.load(std::memory_order_relaxed));
      h.set_busy(session->calls > 0);
      h.set_idle_seconds(session->calls > 0
                             ? 0.0
                             : std::chrono::duration<double>(now - session->idle_since).count());
      sessions.emplace_back(id, std::move(h));
    }
  }
  std::sort(sessions.begin(), sessions.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  reply->set_sessions(static_cast<uint32_t>(sessions.size()));
  for (auto& [id, h] : sessions) *reply->add_session_list() = std::move(h);
  return grpc::Status::OK;
}

}  // namespace tessera::worker

#include "worker_service.h"

#include <unistd.h>

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
#include "tessera/scheduler/launch_timing.h"
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
    std::fprintf(stderr,
                 "tessera-worker: call of launch %llu (%d tiles): waited %.1fms, ran %.1fms, "
                 "sent the rest in %.1fms; cpu user %.1fms sys %.1fms, page faults %ld, "
                 "context switches %ld voluntary %ld involuntary; monotonic clock %.3f to %.3fms\n",
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

WorkerService::WorkerService(int threads, transport::ResultArena* arena)
    : threads_(ResolveThreads(threads)), name_(DeviceName()), arena_(arena) {}

WorkerService::~WorkerService() = default;

std::shared_ptr<WorkerService::Session> WorkerService::FindSession(uint64_t id, bool create) {
  absl::MutexLock lock(&mu_);
  auto it = sessions_.find(id);
  if (it != sessions_.end()) return it->second;
  if (!create) return nullptr;
  auto session = std::make_shared<Session>();
  sessions_.emplace(id, session);
  return session;
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

grpc::Status WorkerService::Apply(grpc::ServerContext* context,
                                  grpc::ServerReader<v1::ApplyChunk>* reader,
                                  v1::ApplyReply* reply) {
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
  while (reader->Read(&part)) {
    if (absl::Status s = assembler.Add(std::move(part)); !s.ok()) return ToGrpcStatus(s);
    part.Clear();
  }
  if (context->IsCancelled()) return grpc::Status(grpc::StatusCode::CANCELLED, "Apply cancelled");
  absl::StatusOr<v1::StateDelta> delta = std::move(assembler).Finish();
  if (!delta.ok()) return ToGrpcStatus(delta.status());

  const uint64_t id = delta->session_id();
  std::shared_ptr<Session> session;
  while (true) {
    session = FindSession(id, /*create=*/true);
    session->mu.Lock();
    // A failed first delta may have dropped the session while this call waited for it.
    if (IsCurrent(id, session)) break;
    session->Release();
  }
  Held held{session.get()};
  if (session->device == nullptr || delta->sequence() == 1) {
    // The device is replaced only if the new one accepts the delta: a rejected delta leaves the
    // session as it was.
    std::unique_ptr<Device> fresh = CreateInprocDevice(threads_, /*results_in_rounds=*/true);
    absl::Status status = fresh->Apply(*delta);
    if (status.ok()) {
      session->device = std::move(fresh);
    } else if (session->device == nullptr) {
      ForgetIfEmpty(id, session);
    }
    return ToGrpcStatus(status);
  }
  return ToGrpcStatus(session->device->Apply(*delta));
}

grpc::Status WorkerService::Launch(grpc::ServerContext* context, const v1::LaunchRequest* request,
                                   grpc::ServerWriter<v1::TileResult>* writer) {
  std::shared_ptr<Session> session = FindSession(request->session_id(), /*create=*/false);
  if (session == nullptr) {
    return grpc::Status(grpc::StatusCode::FAILED_PRECONDITION,
                        absl::StrCat("no state for session ", request->session_id(),
                                     " on this worker: a state delta must come first"));
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
  Held held{session.get()};
  timing.Locked();
  if (session->device == nullptr) {
    return grpc::Status(grpc::StatusCode::FAILED_PRECONDITION,
                        absl::StrCat("no state for session ", request->session_id()));
  }
  Device& device = *session->device;

  std::atomic<bool> cancel{false};
  ResultQueue results;
  std::future<void> ran = session->calls.Post([&] {
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
  return ToGrpcStatus(results.status());
}

grpc::Status WorkerService::EndSession(grpc::ServerContext* context,
                                       const v1::EndSessionRequest* request,
                                       v1::EndSessionReply* reply) {
  std::shared_ptr<Session> session = FindSession(request->session_id(), /*create=*/false);
  if (session == nullptr) return grpc::Status::OK;
  session->mu.Lock();  // after the running Apply or Launch
  Held held{session.get()};
  session->device.reset();
  ForgetIfEmpty(request->session_id(), session);
  return grpc::Status::OK;
}

grpc::Status WorkerService::Health(grpc::ServerContext* context, const v1::HealthRequest* request,
                                   v1::HealthReply* reply) {
  reply->set_device_name(name_);
  reply->set_thread_count(static_cast<uint32_t>(threads_));
  reply->set_pid(getpid());
  reply->set_version(TESSERA_VERSION);
  reply->set_total_memory(scheduler::TotalSystemMemory());
  reply->set_clock_khz(static_cast<uint32_t>(scheduler::CpuClockKHz()));
  return grpc::Status::OK;
}

}  // namespace tessera::worker

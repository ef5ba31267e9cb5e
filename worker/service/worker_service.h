// The Worker gRPC service (proto/tessera/v1/worker.proto) over worker/core's in-process device:
// one device per host session, so several hosts (or contexts) can share a worker. Sessions are
// bounded: one without a call for the idle timeout is dropped (its host is likely gone), and a
// worker holds at most so many (docs/devices.md "Device specs").
#ifndef TESSERA_WORKER_SERVICE_WORKER_SERVICE_H_
#define TESSERA_WORKER_SERVICE_WORKER_SERVICE_H_

#include <grpcpp/grpcpp.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "absl/base/thread_annotations.h"
#include "absl/container/flat_hash_map.h"
#include "absl/status/statusor.h"
#include "absl/synchronization/mutex.h"
#include "absl/time/time.h"
#include "call_thread.h"
#include "memory_use.h"
#include "tessera/scheduler/device.h"
#include "tessera/v1/worker.grpc.pb.h"
#include "transport/result_arena.h"

namespace tessera::worker {

// How many host sessions a worker keeps, and for how long (tessera-worker's --max-sessions and
// --session-idle-timeout).
struct SessionLimits {
  // A session without a call for this long is dropped and its memory freed; its host, should it
  // come back, is told so (UNAVAILABLE) and starts afresh. Zero: never.
  absl::Duration idle_timeout = absl::Seconds(600);
  // A new session past this many is refused with RESOURCE_EXHAUSTED, after dropping the sessions
  // idle past the timeout. Zero: no limit.
  int max_sessions = 64;
};

class WorkerService final : public v1::Worker::Service {
 public:
  // `threads` <= 0: one per core. Every session's launches run on that many threads. `arena`:
  // memory shared with the host that spawned this worker, for written regions (may be null).
  explicit WorkerService(int threads, transport::ResultArena* arena = nullptr,
                         SessionLimits limits = SessionLimits());
  ~WorkerService() override;

  int thread_count() const { return threads_; }
  const SessionLimits& limits() const { return limits_; }

  // What the worker did since it started, for its status endpoint (--status-listen, GET /status).
  struct Stats {
    uint32_t sessions = 0;
    uint64_t launches = 0;   // distinct launches over all sessions
    uint64_t tiles = 0;      // tiles of calls that finished
    double tiles_per_s = 0;  // over the last minute (since the start, while that is shorter)
  };
  Stats GetStats();

  // A graceful stop (SIGTERM): from now on new sessions, state updates and launches not already
  // under way are refused as UNAVAILABLE naming `why` (the hosts run them on their other devices),
  // and so is Health (a host looking for devices does not take this one); calls of launches under
  // way go on. Thread-safety: any thread.
  void BeginShutdown(const std::string& why);
  bool shutting_down() const { return shutting_down_.load(); }
  // Apply, Launch, EndSession and AccelerationBounds calls running now.
  int calls_in_progress() const { return calls_in_progress_.load(); }

  // A delta with sequence 1 starts the session afresh (a host that re-creates its devices starts
  // over with the same session id); any other goes to the session's device, which rejects
  // out-of-order and inconsistent deltas and then keeps its state.
  grpc::Status Apply(grpc::ServerContext* context, grpc::ServerReader<v1::ApplyChunk>* reader,
                     v1::ApplyReply* reply) override;
  // Runs the launch on another thread and streams its results from this one, split into bounded
  // messages, so tiles never wait on the network; a cancelled call sets the launch's cancel flag.
  grpc::Status Launch(grpc::ServerContext* context, const v1::LaunchRequest* request,
                      grpc::ServerWriter<v1::TileResult>* writer) override;
  grpc::Status Health(grpc::ServerContext* context, const v1::HealthRequest* request,
                      v1::HealthReply* reply) override;
  // Forgets the session once its running call (if any) ended.
  grpc::Status EndSession(grpc::ServerContext* context, const v1::EndSessionRequest* request,
                          v1::EndSessionReply* reply) override;
  // The session's device answers (Device::AccelerationBounds), after its running call.
  grpc::Status AccelerationBounds(grpc::ServerContext* context,
                                  const v1::AccelerationBoundsRequest* request,
                                  v1::AccelerationBoundsReply* reply) override;

 private:
  using Clock = std::chrono::steady_clock;

  struct Session {
    explicit Session(Clock::time_point now) : idle_since(now) {}
    // Guarded by WorkerService::mu_: the calls using the session now (a session in use is never
    // dropped), and since when it has had none.
    int calls = 0;
    Clock::time_point idle_since;
    absl::Mutex mu;  // one Apply or Launch at a time (Device contract)
    std::unique_ptr<Device> device ABSL_GUARDED_BY(mu);  // null until a delta applied
    BufferBytes buffers ABSL_GUARDED_BY(mu);
    std::atomic<uint64_t> buffer_bytes{0};  // buffers.total(), for Health without waiting on mu
    // Counts releases of `mu`, so that a queued launch sleeps until the running call ends
    // instead of polling (sixteen workers polling every millisecond slowed tracing on gVisor).
    std::mutex turn_mu;
    std::condition_variable turn_cv;
    uint64_t releases = 0;
    // Set while the running Launch was cancelled by its host but its program has not returned
    // (one that never ends cannot be stopped): launches queued behind it stop sending
    // heartbeats, so the host sees a hung worker after TESSERA_WORKER_TIMEOUT instead of
    // waiting forever.
    std::atomic<bool> holder_cancelled{false};
    // The launch of the last Launch call: a call with another id starts a new launch.
    std::atomic<uint64_t> last_launch_id{0};
    // The newest launch whose state update was applied (StateDelta.launch_id): a call of an older
    // launch is refused (its host gave it up; it would write into the new state).
    std::atomic<uint64_t> state_launch_id{0};
    CallThread calls_thread;  // runs the session's launch calls, one after the other
    void Release() {
      holder_cancelled = false;
      mu.Unlock();
      {
        std::lock_guard<std::mutex> lock(turn_mu);
        ++releases;
      }
      turn_cv.notify_all();
    }
  };
  // Releases a session taken with `mu.Lock()`/`TryLock()` when the call ends, or earlier.
  struct Held {
    Session* session;
    bool released = false;
    void Release() {
      if (!released) session->Release();
      released = true;
    }
    ~Held() { Release(); }
  };
  // A call's use of a session, from when the call names it until it returns.
  class Use {
   public:
    Use() = default;
    Use(WorkerService* service, std::shared_ptr<Session> session)
        : service_(service), session_(std::move(session)) {}
    Use(Use&& other) noexcept = default;
    Use& operator=(Use&& other) noexcept {
      End();
      service_ = other.service_;
      session_ = std::move(other.session_);
      return *this;
    }
    ~Use() { End(); }
    Session* get() const { return session_.get(); }
    const std::shared_ptr<Session>& shared() const { return session_; }
    explicit operator bool() const { return session_ != nullptr; }
    void End();

   private:
    WorkerService* service_ = nullptr;
    std::shared_ptr<Session> session_;
  };

  // Apply, less the translation of an exhausted memory into a status.
  grpc::Status ApplyStream(grpc::ServerContext* context,
                           grpc::ServerReader<v1::ApplyChunk>* reader);
  // The session a delta with `sequence` for `id` goes to, in use: the existing one, or for
  // sequence 1 a new one (RESOURCE_EXHAUSTED at the session limit). Without a session, a later
  // sequence is UNAVAILABLE when the session was dropped for idleness (its host starts afresh),
  // and FAILED_PRECONDITION otherwise (out of order, as the device would say).
  absl::StatusOr<Use> UseForDelta(uint64_t id, uint64_t sequence);
  // The existing session `id`, in use; null when there is none.
  Use UseExisting(uint64_t id);
  // Why a call for session `id`, which this worker does not hold, cannot go on.
  absl::Status Missing(uint64_t id, absl::string_view what) ABSL_EXCLUSIVE_LOCKS_REQUIRED(mu_);
  bool IsCurrent(uint64_t id, const std::shared_ptr<Session>& session);
  void ForgetIfEmpty(uint64_t id, const std::shared_ptr<Session>& session);
  // Moves the sessions idle for the timeout out of `sessions_` (to be destroyed by the caller,
  // after releasing mu_), remembering their ids; returns when the next one may be due (max:
  // none).
  Clock::time_point TakeIdleLocked(Clock::time_point now,
                                   std::vector<std::shared_ptr<Session>>* dropped)
      ABSL_EXCLUSIVE_LOCKS_REQUIRED(mu_);
  // The thread that drops idle sessions (only with an idle timeout).
  void ReapLoop();
  // UNAVAILABLE once BeginShutdown was called, naming `what` was refused.
  absl::Status ShuttingDown(absl::string_view what);
  // Counts a call in calls_in_progress_ while it runs.
  class InProgress {
   public:
    explicit InProgress(WorkerService* s) : s_(s) { ++s_->calls_in_progress_; }
    ~InProgress() { --s_->calls_in_progress_; }
    InProgress(const InProgress&) = delete;
    InProgress& operator=(const InProgress&) = delete;

   private:
    WorkerService* s_;
  };

  const int threads_;
  const std::string name_;
  transport::ResultArena* const arena_;
  const SessionLimits limits_;
  absl::Mutex mu_;  // taken after a Session::mu, never before
  absl::flat_hash_map<uint64_t, std::shared_ptr<Session>> sessions_ ABSL_GUARDED_BY(mu_);
  // Sessions dropped for idleness, newest last, up to kMaxDropped: when their hosts come back they
  // are told why their state is gone.
  absl::flat_hash_map<uint64_t, absl::Duration> dropped_ ABSL_GUARDED_BY(mu_);
  std::deque<uint64_t> dropped_order_ ABSL_GUARDED_BY(mu_);
  bool stopping_ ABSL_GUARDED_BY(mu_) = false;
  absl::CondVar reap_cv_;
  std::thread reaper_;

  std::atomic<bool> shutting_down_{false};
  std::string shutdown_reason_ ABSL_GUARDED_BY(mu_);
  std::atomic<int> calls_in_progress_{0};
  std::atomic<uint64_t> launches_{0};
  std::atomic<uint64_t> tiles_{0};
  const Clock::time_point started_ = Clock::now();
  // Tiles finished in each of the last 60 seconds, by second since started_.
  struct TileSecond {
    int64_t second = -1;
    uint64_t tiles = 0;
  };
  absl::Mutex rate_mu_;
  TileSecond tile_seconds_[60] ABSL_GUARDED_BY(rate_mu_);
  void CountTiles(uint64_t tiles);
};

}  // namespace tessera::worker

#endif  // TESSERA_WORKER_SERVICE_WORKER_SERVICE_H_

// The Worker gRPC service (proto/tessera/v1/worker.proto) over worker/core's in-process device:
// one device per host session, so several hosts (or contexts) can share a worker.
#ifndef TESSERA_WORKER_SERVICE_WORKER_SERVICE_H_
#define TESSERA_WORKER_SERVICE_WORKER_SERVICE_H_

#include <grpcpp/grpcpp.h>

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>

#include "absl/base/thread_annotations.h"
#include "absl/container/flat_hash_map.h"
#include "absl/synchronization/mutex.h"
#include "call_thread.h"
#include "tessera/scheduler/device.h"
#include "tessera/v1/worker.grpc.pb.h"
#include "transport/result_arena.h"

namespace tessera::worker {

class WorkerService final : public v1::Worker::Service {
 public:
  // `threads` <= 0: one per core. Every session's launches run on that many threads. `arena`:
  // memory shared with the host that spawned this worker, for written regions (may be null).
  explicit WorkerService(int threads, transport::ResultArena* arena = nullptr);
  ~WorkerService() override;

  int thread_count() const { return threads_; }

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

 private:
  struct Session {
    absl::Mutex mu;  // one Apply or Launch at a time (Device contract)
    std::unique_ptr<Device> device ABSL_GUARDED_BY(mu);  // null until a delta applied
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
    CallThread calls;  // runs the session's launch calls, one after the other
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

  // Apply, less the translation of an exhausted memory into a status.
  grpc::Status ApplyStream(grpc::ServerContext* context,
                           grpc::ServerReader<v1::ApplyChunk>* reader);
  std::shared_ptr<Session> FindSession(uint64_t id, bool create);
  bool IsCurrent(uint64_t id, const std::shared_ptr<Session>& session);
  void ForgetIfEmpty(uint64_t id, const std::shared_ptr<Session>& session);

  const int threads_;
  const std::string name_;
  transport::ResultArena* const arena_;
  absl::Mutex mu_;  // taken after a Session::mu, never before
  absl::flat_hash_map<uint64_t, std::shared_ptr<Session>> sessions_ ABSL_GUARDED_BY(mu_);
};

}  // namespace tessera::worker

#endif  // TESSERA_WORKER_SERVICE_WORKER_SERVICE_H_

// A Device that is a `tessera-worker` process reached over gRPC (the transport adapter,
// docs/devices.md). gRPC stays behind this header: callers see the Device interface and absl
// statuses.
#ifndef TESSERA_SCHEDULER_TRANSPORT_GRPC_DEVICE_H_
#define TESSERA_SCHEDULER_TRANSPORT_GRPC_DEVICE_H_

#include <atomic>
#include <cstdint>
#include <memory>
#include <string>

#include "absl/status/statusor.h"
#include "absl/time/time.h"
#include "tessera/scheduler/device.h"
#include "transport/worker_process.h"

namespace tessera::transport {

// TESSERA_WORKER_TIMEOUT: how long a worker may stay silent (default 10 s).
absl::Duration SilenceDeadline();

// FAILED_PRECONDITION in a process forked (without exec) from one that had started gRPC: the
// child inherits gRPC's locks and state but not its threads, and crashed inside gRPC about once
// in 40 forks when it reached workers of its own (gRPC's fork support, GRPC_ENABLE_FORK_SUPPORT,
// did not prevent it). OK everywhere else.
absl::Status GrpcUsableInThisProcess();

// What a worker's Health call reports.
struct WorkerHealth {
  std::string device_name;
  int thread_count = 0;
  int64_t pid = 0;
  std::string version;
  uint64_t total_memory = 0;  // bytes; 0 when the worker did not say
  int clock_khz = 0;          // 0 when the worker did not say
};

class GrpcDevice : public Device {
 public:
  // Connects to the worker at "HOST:PORT" or "unix:PATH" and asks for its health. UNAVAILABLE
  // (RT_ERROR_CONNECTION_FAILED for the application) if it does not answer within `timeout`.
  static absl::StatusOr<std::unique_ptr<GrpcDevice>> Connect(
      const std::string& address, absl::Duration timeout = absl::Seconds(10));
  // Connects to a spawned worker at its address; the device owns the process and stops it last.
  static absl::StatusOr<std::unique_ptr<GrpcDevice>> Connect(
      std::unique_ptr<WorkerProcess> process, absl::Duration timeout = absl::Seconds(10));
  ~GrpcDevice() override;

  // name "worker", the address, and the worker's thread count.
  DeviceInfo Info() const override;
  // Streams the delta: the delta without chunks, then one message per buffer chunk.
  absl::Status Apply(const v1::StateDelta& delta) override;
  // Delivers TileResults as the worker streams them; a cancel reaches the worker within a few
  // milliseconds (the call is cancelled, which sets the worker's cancel flag).
  absl::Status Launch(const v1::LaunchRequest& request, const std::atomic<bool>& cancel,
                      const std::function<void(v1::TileResult&&)>& on_result) override;
  // Asks the worker, within the silence deadline (TESSERA_WORKER_TIMEOUT).
  absl::StatusOr<v1::AccelerationBoundsReply> AccelerationBounds(
      const v1::AccelerationBoundsRequest& request) override;

  // Asks the worker again.
  absl::StatusOr<WorkerHealth> Health(absl::Duration timeout = absl::Seconds(10)) const;
  // As reported when connecting.
  const WorkerHealth& health() const { return health_; }
  const std::string& address() const { return address_; }
  // The spawned worker, or null for a worker someone else runs.
  const WorkerProcess* process() const { return process_.get(); }

 private:
  struct Stub;  // the gRPC channel and stub, kept out of this header
  GrpcDevice() = default;
  absl::Status Open(absl::Duration timeout);  // channel, stub, first Health
  // A failed Launch call: ABORTED when the spawned worker crashed (naming the program from its
  // crash report), UNAVAILABLE when it died otherwise, else `status`.
  absl::Status LostOrFailed(absl::Status status);

  // Declared first so that it is destroyed last: the worker stops after the channel closes.
  std::unique_ptr<WorkerProcess> process_;
  std::string address_;
  std::unique_ptr<Stub> stub_;
  WorkerHealth health_;
  uint64_t session_id_ = 0;  // of the deltas applied, ended when the device goes
  // A call found the spawned worker gone or silent: it is killed when the device goes, rather
  // than asked to stop (a stopped worker would spend the whole grace).
  std::atomic<bool> lost_{false};
};

}  // namespace tessera::transport

#endif  // TESSERA_SCHEDULER_TRANSPORT_GRPC_DEVICE_H_

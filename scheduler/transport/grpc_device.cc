#include "transport/grpc_device.h"

#include <grpc/grpc.h>
#include <grpcpp/grpcpp.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <mutex>
#include <utility>

#include "absl/strings/match.h"
#include "absl/strings/numbers.h"
#include "absl/strings/str_cat.h"
#include "tessera/scheduler/log.h"
#include "tessera/scheduler/result_pool.h"
#include "tessera/v1/worker.grpc.pb.h"
#include "transport/apply_call.h"
#include "transport/call_watchdog.h"
#include "transport/credentials.h"
#include "transport/grpc_log.h"
#include "transport/result_arena.h"
#include "transport/worker_wire.h"

namespace tessera::transport {
namespace {

std::chrono::system_clock::time_point DeadlineIn(absl::Duration timeout) {
  return absl::ToChronoTime(absl::Now() + timeout);
}

// The process that started gRPC; 0 until one has.
std::atomic<pid_t> g_grpc_pid{0};

}  // namespace

absl::Status GrpcUsableInThisProcess() {
  const pid_t started = g_grpc_pid.load();
  if (started == 0 || started == getpid()) return absl::OkStatus();
  return absl::FailedPreconditionError(absl::StrCat(
      "this process was forked (without exec) from process ", started,
      ", which had started gRPC; gRPC cannot run in such a child, so it cannot reach worker "
      "processes (exec after fork, or use the inproc device)"));
}

// TESSERA_WORKER_TIMEOUT (seconds, default 10): how long a worker may stay silent during a launch
// before the host gives up on it and runs its tiles elsewhere.
// Workers send a heartbeat twice a second, so a limit under a second would take a working worker
// for a silent one. A value that is not a number of seconds from 1 up is said on stderr (once)
// and the default used, as TESSERA_MODULE_CACHE_MAX_MB is.
absl::Duration SilenceDeadline() {
  constexpr double kDefault = 10.0;
  constexpr double kMin = 1.0;
  const char* env = std::getenv("TESSERA_WORKER_TIMEOUT");
  if (env == nullptr || *env == '\0') return absl::Seconds(kDefault);
  double seconds = 0;
  if (absl::SimpleAtod(env, &seconds) && std::isfinite(seconds) && seconds >= kMin) {
    return absl::Seconds(seconds);
  }
  static std::once_flag warned;
  std::call_once(warned, [&] {
    log::Warn(log::Component::kScheduler,
              "TESSERA_WORKER_TIMEOUT='%s' is not a number of seconds from %g up (workers send a "
              "heartbeat twice a second); using %g",
              env, kMin, kDefault);
  });
  return absl::Seconds(kDefault);
}

struct GrpcDevice::Stub {
  std::shared_ptr<grpc::Channel> channel;
  std::unique_ptr<v1::Worker::Stub> worker;
};

absl::StatusOr<std::unique_ptr<GrpcDevice>> GrpcDevice::Connect(const std::string& address,
                                                                absl::Duration timeout) {
  std::unique_ptr<GrpcDevice> device(new GrpcDevice);
  device->address_ = address;
  if (absl::Status s = device->Open(timeout); !s.ok()) return s;
  return device;
}

absl::StatusOr<std::unique_ptr<GrpcDevice>> GrpcDevice::Connect(
    std::unique_ptr<WorkerProcess> process, absl::Duration timeout) {
  std::unique_ptr<GrpcDevice> device(new GrpcDevice);
  device->address_ = process->address();
  device->process_ = std::move(process);
  if (absl::Status s = device->Open(timeout); !s.ok()) return s;
  return device;
}

absl::Status GrpcDevice::Open(absl::Duration timeout) {
  if (absl::Status usable = GrpcUsableInThisProcess(); !usable.ok()) return usable;
  // gRPC 1.51 shuts its library down when the last channel goes, and that shutdown can block for
  // up to 10 s joining an executor thread (seen with rtContextDestroy); one reference that is
  // never released keeps the library up for the life of the host process instead.
  static const bool kKeepGrpcInitialised = [] {
    g_grpc_pid.store(getpid());
    RouteGrpcLogs();
    grpc_init();
    return true;
  }();
  (void)kKeepGrpcInitialised;

  grpc::ChannelArguments args;
  args.SetMaxReceiveMessageSize(kMaxMessageBytes);
  args.SetMaxSendMessageSize(kMaxMessageBytes);
  // Keepalive pings during calls notice a peer that vanished without closing the connection
  // (a remote machine that lost power); the worker permits pings at this rate.
  args.SetInt(GRPC_ARG_KEEPALIVE_TIME_MS, 30000);
  args.SetInt(GRPC_ARG_KEEPALIVE_TIMEOUT_MS, 20000);
  // Workers are reached directly; an http_proxy meant for the application must not reroute them.
  args.SetInt(GRPC_ARG_ENABLE_HTTP_PROXY, 0);
  stub_ = std::make_unique<Stub>();
  // TLS and the token as the environment says; refused before connecting to another machine
  // without them (docs/security.md).
  absl::StatusOr<std::shared_ptr<grpc::Channel>> channel = CreateWorkerChannel(address_, args);
  if (!channel.ok()) return channel.status();
  stub_->channel = *std::move(channel);
  stub_->worker = v1::Worker::NewStub(stub_->channel);
  absl::StatusOr<WorkerHealth> health = Health(timeout);
  if (!health.ok()) {
    // A worker that never answers is as unreachable as one that refuses the connection.
    if (health.status().code() == absl::StatusCode::kDeadlineExceeded) {
      return absl::UnavailableError(absl::StrCat("worker ", address_, " did not answer within ",
                                                 absl::FormatDuration(timeout)));
    }
    // A worker serving TLS closes a plain connection at once; gRPC says only "Socket closed".
    const char* ca = std::getenv(kTlsCaEnv);
    if (health.status().code() == absl::StatusCode::kUnavailable &&
        absl::StrContains(health.status().message(), "Socket closed") &&
        !absl::StartsWith(address_, "unix:") && (ca == nullptr || *ca == '\0')) {
      return absl::UnavailableError(absl::StrCat(
          health.status().message(), " (a worker that serves TLS closes plain connections: set ",
          kTlsCaEnv, " to the CA that signed its certificate, docs/security.md)"));
    }
    return health.status();
  }
  health_ = *std::move(health);
  return absl::OkStatus();
}

GrpcDevice::~GrpcDevice() {
  if (process_ != nullptr && lost_.load()) process_->Kill();
  // A worker someone else runs outlives this host: without this it would keep the session's
  // replica (every buffer) until it restarts. Best effort, briefly: a lost worker holds nothing.
  if (stub_ == nullptr || session_id_ == 0 || process_ != nullptr) return;
  grpc::ClientContext context;
  context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(1));
  v1::EndSessionRequest request;
  request.set_session_id(session_id_);
  v1::EndSessionReply reply;
  stub_->worker->EndSession(&context, request, &reply);
}

DeviceInfo GrpcDevice::Info() const { return DeviceInfo{"worker", address_, health_.thread_count}; }

absl::StatusOr<WorkerHealth> GrpcDevice::Health(absl::Duration timeout) const {
  grpc::ClientContext context;
  context.set_deadline(DeadlineIn(timeout));
  v1::HealthReply reply;
  grpc::Status status = stub_->worker->Health(&context, v1::HealthRequest(), &reply);
  if (!status.ok()) return FromGrpcStatus(status, address_);
  WorkerHealth health;
  health.device_name = reply.device_name();
  health.thread_count = static_cast<int>(reply.thread_count());
  health.pid = reply.pid();
  health.version = reply.version();
  health.total_memory = reply.total_memory();
  health.clock_khz = static_cast<int>(reply.clock_khz());
  return health;
}

absl::Status GrpcDevice::Apply(const v1::StateDelta& delta) {
  if (absl::Status s = CheckDeltaMessageSizes(delta); !s.ok()) {
    return absl::Status(s.code(), absl::StrCat("not sent to worker ", address_, ": ", s.message()));
  }
  session_id_ = delta.session_id();
  uint64_t bytes = 0;
  for (const v1::BufferChunk& chunk : delta.chunks()) bytes += chunk.data().size();
  // A worker that stops answering while it takes a delta (stopped, hung, its machine gone) must
  // not hold the launch for gRPC's keepalive (about 50 s), nor for ever when it stops reading: the
  // same silence deadline as during a launch, counted from the last message it accepted
  // (apply_call.h waits on its own deadline instead of inside a blocking write).
  const absl::Duration silence = SilenceDeadline();
  ApplyCall call(stub_->worker.get());
  // A failed Write means the call is over (the worker rejected the delta early, the connection
  // dropped, or the worker stopped taking messages); Finish says why.
  const bool sent =
      WriteApplyStream(delta, [&](const v1::ApplyChunk& m) { return call.Write(m, silence); });
  // Every message is out: the worker now builds its replica from them and says nothing until it
  // is done, which takes seconds for a delta of gigabytes. Allow for that at a slow machine's
  // pace (kApplyBytesPerSecond) before taking its silence for a hang.
  constexpr double kApplyBytesPerSecond = 50e6;
  const grpc::Status status = call.Finish(
      sent ? silence + absl::Seconds(static_cast<double>(bytes) / kApplyBytesPerSecond) : silence);
  if (call.silent()) {
    lost_ = true;
    return absl::DeadlineExceededError(
        absl::StrCat("worker ", address_, " did not take the state update within ",
                     absl::FormatDuration(silence),
                     " (hung or unreachable; TESSERA_WORKER_TIMEOUT sets the limit)"));
  }
  absl::Status result = FromGrpcStatus(status, address_);
  // A worker without room for this update (a shared worker at its session limit, one short of
  // memory) cannot serve this launch, though others may: it is unavailable to this host now, and
  // the host leaves it out as it would a lost one (the message says why).
  if (result.code() == absl::StatusCode::kResourceExhausted) {
    lost_ = true;
    return absl::UnavailableError(result.message());
  }
  // A connection that dropped: a spawned worker that died says how (killed between launches or
  // while taking this update, or crashed loading a module); a worker that rejected the update is
  // alive and says why itself. A worker killed mid-stream ends the call with whatever gRPC saw
  // first (UNAVAILABLE, or UNKNOWN/INTERNAL/CANCELLED for a stream cut short): LostOrFailed looks
  // at the process for each of them.
  if (result.ok()) return result;
  return LostOrFailed(std::move(result));
}

absl::Status GrpcDevice::Launch(const v1::LaunchRequest& request, const std::atomic<bool>& cancel,
                                const std::function<void(v1::TileResult&&)>& on_result) {
  // A worker this host spawned puts large written regions in memory both share (a slot leased
  // to this call); others, or with every slot busy, send them in the messages.
  ResultArena* arena = process_ != nullptr ? process_->result_arena() : nullptr;
  const ResultArena::Lease lease = arena != nullptr ? arena->Acquire() : ResultArena::Lease{};
  v1::LaunchRequest leased;
  if (lease.slot >= 0) {
    leased = request;
    leased.set_arena_slot(static_cast<uint32_t>(lease.slot));
    leased.set_arena_token(lease.token);
  }
  grpc::ClientContext context;
  grpc::Status status;
  absl::Status restored;
  bool silent = false;
  {
    // Watched from before the call starts: sending the request can wait on a worker that stopped
    // reading, and a cancel of a call not yet started cancels it as it starts.
    WatchedCall watcher(&context, cancel, SilenceDeadline());
    std::unique_ptr<grpc::ClientReader<v1::TileResult>> reader =
        stub_->worker->Launch(&context, lease.slot >= 0 ? leased : request);
    // Parsed into messages that held results before (result_pool.h): their buffers are reused.
    v1::TileResult result = scheduler::TakeTileResult();
    while (reader->Read(&result)) {
      watcher.Heard();
      // Heartbeats say the worker is alive, and some how far its call got (passed on for
      // progress). The written regions come as several results with kFinalTileIndex; whoever
      // called collects the whole call before applying any of it.
      const bool heartbeat = result.tile_index() == kHeartbeatTileIndex;
      if (heartbeat && result.tiles_done() == 0 && !result.started()) continue;
      if (!heartbeat) {
        restored = ResultArena::Restore(arena, lease, &result);
        if (!restored.ok()) {
          context.TryCancel();
          break;
        }
      }
      on_result(std::move(result));
      result = scheduler::TakeTileResult();
    }
    scheduler::RecycleTileResult(std::move(result));  // the one taken for a read that never came
    status = reader->Finish();
    silent = watcher.silent();
  }
  // The slot goes back however the call ended: a worker still sending for it finds the next
  // lease's token there and keeps its bytes in the messages.
  if (arena != nullptr) arena->Release(lease);
  if (!restored.ok()) {
    return absl::DataLossError(absl::StrCat("worker ", address_, ": ", restored.message()));
  }
  if (cancel.load()) return absl::CancelledError("launch cancelled");
  if (silent) {
    lost_ = true;
    return absl::DeadlineExceededError(absl::StrCat(
        "worker ", address_, " sent nothing for ", absl::FormatDuration(SilenceDeadline()),
        " (hung or unreachable; TESSERA_WORKER_TIMEOUT sets the limit)"));
  }
  if (!status.ok()) return LostOrFailed(FromGrpcStatus(status, address_));
  return absl::OkStatus();
}

absl::StatusOr<v1::AccelerationBoundsReply> GrpcDevice::AccelerationBounds(
    const v1::AccelerationBoundsRequest& request) {
  grpc::ClientContext context;
  context.set_deadline(DeadlineIn(SilenceDeadline()));
  v1::AccelerationBoundsReply reply;
  const grpc::Status status = stub_->worker->AccelerationBounds(&context, request, &reply);
  if (!status.ok()) return FromGrpcStatus(status, address_);
  return reply;
}

absl::Status GrpcDevice::LostOrFailed(absl::Status status) {
  if (status.code() == absl::StatusCode::kUnavailable) lost_ = true;
  if (process_ != nullptr) {
    // A spawned worker that died: a crash (a program's fault: say which program) or a kill. A
    // broken connection can come before the process is reaped, so it gets a moment; an error
    // the worker itself sent (a program's error, say) only a look: the worker is alive, and
    // waiting made every failed launch last a second.
    const absl::StatusCode code = status.code();
    const bool connection =
        code == absl::StatusCode::kUnavailable || code == absl::StatusCode::kUnknown ||
        code == absl::StatusCode::kInternal || code == absl::StatusCode::kCancelled;
    bool crashed = false;
    std::string exit =
        process_->WaitForExit(connection ? absl::Seconds(1) : absl::ZeroDuration(), &crashed);
    if (!exit.empty()) {
      std::string log = process_->LogTail(16384);
      size_t at = log.rfind(kCrashReportPrefix);
      if (crashed && at != std::string::npos) {
        std::string line = log.substr(at + sizeof(kCrashReportPrefix) - 1);
        line = line.substr(0, line.find('\n'));
        return absl::AbortedError(absl::StrCat("worker process ", address_, " crashed: ", line));
      }
      lost_ = true;
      return absl::UnavailableError(absl::StrCat("worker process ", address_, " ", exit));
    }
  }
  return status;
}

}  // namespace tessera::transport

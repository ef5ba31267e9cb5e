#include "transport/grpc_device.h"

#include <grpc/grpc.h>
#include <grpcpp/grpcpp.h>

#include <chrono>
#include <condition_variable>
#include <mutex>
#include <thread>
#include <utility>

#include "absl/strings/str_cat.h"
#include "tessera/v1/worker.grpc.pb.h"
#include "transport/worker_wire.h"

namespace tessera::transport {
namespace {

// How often a running launch looks at the cancel flag.
constexpr std::chrono::milliseconds kCancelPoll{2};

std::chrono::system_clock::time_point DeadlineIn(absl::Duration timeout) {
  return absl::ToChronoTime(absl::Now() + timeout);
}

// Cancels `context` once `cancel` becomes true, until stopped. Blocking reads on the stream cannot
// watch the flag themselves.
class CancelWatcher {
 public:
  CancelWatcher(grpc::ClientContext* context, const std::atomic<bool>& cancel)
      : thread_([this, context, &cancel] {
          std::unique_lock<std::mutex> lock(mu_);
          while (!stop_) {
            if (cancel.load()) {
              context->TryCancel();
              return;
            }
            cv_.wait_for(lock, kCancelPoll);
          }
        }) {}
  ~CancelWatcher() {
    {
      std::lock_guard<std::mutex> lock(mu_);
      stop_ = true;
    }
    cv_.notify_all();
    thread_.join();
  }

 private:
  std::mutex mu_;
  std::condition_variable cv_;
  bool stop_ = false;   // guarded by mu_
  std::thread thread_;  // last: starts after the members it uses
};

}  // namespace

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
  // gRPC 1.51 shuts its library down when the last channel goes, and that shutdown can block for
  // up to 10 s joining an executor thread (seen with rtContextDestroy); one reference that is
  // never released keeps the library up for the life of the host process instead.
  static const bool kKeepGrpcInitialised = [] {
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
  stub_->channel = grpc::CreateCustomChannel(address_, grpc::InsecureChannelCredentials(), args);
  stub_->worker = v1::Worker::NewStub(stub_->channel);
  absl::StatusOr<WorkerHealth> health = Health(timeout);
  if (!health.ok()) {
    // A worker that never answers is as unreachable as one that refuses the connection.
    if (health.status().code() == absl::StatusCode::kDeadlineExceeded) {
      return absl::UnavailableError(health.status().message());
    }
    return health.status();
  }
  health_ = *std::move(health);
  return absl::OkStatus();
}

GrpcDevice::~GrpcDevice() = default;

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
  return health;
}

absl::Status GrpcDevice::Apply(const v1::StateDelta& delta) {
  grpc::ClientContext context;
  v1::ApplyReply reply;
  std::unique_ptr<grpc::ClientWriter<v1::ApplyChunk>> writer =
      stub_->worker->Apply(&context, &reply);
  // A failed Write means the call is over (the worker rejected the delta early, or the connection
  // dropped); Finish says why.
  if (writer->Write(DeltaHeader(delta))) {
    v1::ApplyChunk message;
    for (const v1::BufferChunk& chunk : delta.chunks()) {
      *message.mutable_chunk() = chunk;
      if (!writer->Write(message)) break;
    }
    writer->WritesDone();
  }
  return FromGrpcStatus(writer->Finish(), address_);
}

absl::Status GrpcDevice::Launch(const v1::LaunchRequest& request, const std::atomic<bool>& cancel,
                                const std::function<void(v1::TileResult&&)>& on_result) {
  grpc::ClientContext context;
  std::unique_ptr<grpc::ClientReader<v1::TileResult>> reader =
      stub_->worker->Launch(&context, request);
  FinalResultJoiner final_result;
  grpc::Status status;
  {
    CancelWatcher watcher(&context, cancel);
    v1::TileResult result;
    while (reader->Read(&result)) {
      if (result.tile_index() == kFinalTileIndex) {
        final_result.Add(std::move(result));
      } else {
        on_result(std::move(result));
      }
      result.Clear();
    }
    status = reader->Finish();
  }
  if (cancel.load()) return absl::CancelledError("launch cancelled");
  if (!status.ok()) return FromGrpcStatus(status, address_);
  // The final contents, reassembled, come last as they do from an in-process device.
  if (!final_result.empty()) on_result(std::move(final_result).Take());
  return absl::OkStatus();
}

}  // namespace tessera::transport

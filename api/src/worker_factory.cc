// Installs worker devices into libtessera when scheduler/transport is part of the build
// (TESSERA_HAVE_TRANSPORT, set by api/CMakeLists.txt): `local:N` spawns N `tessera-worker`
// processes that the device owns and reaps; HOST:PORT and unix:PATH connect to running workers.
// Kept out of tessera::api_core so the core can be tested with fake devices alone.
#include "device_table.h"

#ifdef TESSERA_HAVE_TRANSPORT
#include <algorithm>

#include "system_info.h"
#include "transport/grpc_device.h"
#include "transport/worker_process.h"
#ifdef TESSERA_HAVE_WORKER_CORE
#include "tessera/worker/inproc_device.h"  // CheckInterruptSignal
#endif

namespace tessera::api {
namespace {

absl::StatusOr<std::unique_ptr<Device>> MakeWorkerDevice(const DeviceDesc& device) {
  if (device.type == DeviceSpecEntry::Type::kLocal) {
#ifdef TESSERA_HAVE_WORKER_CORE
    CheckInterruptSignal();  // the workers inherit the variable
#endif
    // The workers share the machine's cores; a context's CPU_NUM_THREADS, when the application
    // sets it, still overrides this per launch (it travels in ContextState).
    transport::WorkerProcess::Options options;
    options.threads = std::max(1, HardwareThreads() / std::max(1, device.local_count));
    options.index = device.local_index;
    // A worker stopped or hung while starting is a lost device like one silent in a launch:
    // dropped after the same deadline (a healthy one starts in a fraction of a second).
    options.start_timeout = transport::SilenceDeadline();
    auto process = transport::WorkerProcess::Spawn(std::move(options));
    if (!process.ok()) return process.status();
    auto connected =
        transport::GrpcDevice::Connect(*std::move(process), transport::SilenceDeadline());
    if (!connected.ok()) return connected.status();
    return std::unique_ptr<Device>(*std::move(connected));
  }
  // A running worker that does not answer within the silence deadline is hung or gone: every
  // launch tries it again, so it must not cost each of them more than a lost worker does.
  auto connected = transport::GrpcDevice::Connect(device.address, transport::SilenceDeadline());
  if (!connected.ok()) return connected.status();
  return std::unique_ptr<Device>(*std::move(connected));
}

// How long rtDeviceGetAttribute waits for a running worker to answer.
constexpr absl::Duration kProbeTimeout = absl::Seconds(5);

absl::StatusOr<WorkerFacts> ProbeWorker(const DeviceDesc& device) {
  auto connected = transport::GrpcDevice::Connect(device.address, kProbeTimeout);
  if (!connected.ok()) return connected.status();
  const transport::WorkerHealth& health = (*connected)->health();
  return WorkerFacts{health.thread_count, health.total_memory, health.clock_khz};
}

[[maybe_unused]] const bool kInstalled = [] {
  SetWorkerDeviceFactory(&MakeWorkerDevice);
  SetWorkerProbe(&ProbeWorker);
  SetWorkerTransportCheck(&transport::GrpcUsableInThisProcess);
  return true;
}();

}  // namespace
}  // namespace tessera::api
#endif

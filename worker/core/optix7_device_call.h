// One device call of an optixLaunch (a LaunchRequest with `optix7`): the engine prepared for the
// session's pipeline and SBT, the call's tiles run on the device's threads, and, when the host
// asks (Optix7Launch.report_writes), what programs wrote to device memory sent back as
// device-memory regions (docs/device_memory.md, "Gathering what programs wrote").
#ifndef TESSERA_WORKER_CORE_OPTIX7_DEVICE_CALL_H_
#define TESSERA_WORKER_CORE_OPTIX7_DEVICE_CALL_H_

#include <tbb/task_arena.h>

#include <atomic>
#include <cstdint>
#include <functional>

#include "absl/status/status.h"
#include "optix7_engine.h"
#include "optix7_session.h"
#include "tessera/v1/launch.pb.h"

namespace tessera::worker {

// Runs `request`'s tiles on the `threads` threads of `arena`; results go to `on_result` as for
// Device::Launch, the written regions last (call_sequence `sequence`). A device that shares the
// host's memory sends the written ranges without their bytes (they are in place already).
absl::Status RunOptix7Call(Optix7Engine& engine, const Optix7Session& session,
                           const v1::LaunchRequest& request, tbb::task_arena& arena, int threads,
                           uint64_t sequence, const std::atomic<bool>& cancel,
                           const std::function<void(v1::TileResult&&)>& on_result);

}  // namespace tessera::worker

#endif  // TESSERA_WORKER_CORE_OPTIX7_DEVICE_CALL_H_

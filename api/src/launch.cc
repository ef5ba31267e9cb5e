// Context::Launch: validate, ship state deltas, dispatch tiles to devices, gather results.
#include <algorithm>
#include <chrono>
#include <thread>

#include "absl/strings/str_cat.h"
#include "acceleration.h"
#include "buffer.h"
#include "context.h"
#include "gather.h"
#include "geometry.h"
#include "lowering.h"
#include "status.h"
#include "tiling.h"
#include "validate.h"

namespace tessera::api {
namespace {

// A device error as the application sees it: the RTresult from the table (or the status's own)
// and a message naming the device.
absl::Status DeviceError(const DeviceSlot& slot, const char* what, const absl::Status& status) {
  RTresult code = ToRtResult(status);
  if (code == RT_ERROR_INVALID_VALUE || code == RT_ERROR_INVALID_CONTEXT) {
    code = RT_ERROR_LAUNCH_FAILED;  // a device rejecting our own messages is a launch failure
  }
  return RtError(code,
                 absl::StrCat("device '", slot.desc.name, "' ", what, ": ", status.message()));
}

// Sets the running flag for the duration of a launch.
class RunningScope {
 public:
  explicit RunningScope(Context& c) : c_(c) { c_.set_running(true); }
  ~RunningScope() { c_.set_running(false); }

 private:
  Context& c_;
};

absl::Status CheckNothingMapped(Context& context) {
  for (const auto& [id, object] : context.objects()) {
    if (object->kind() == Kind::kBuffer && static_cast<Buffer*>(object)->mapped()) {
      return RtError(RT_ERROR_ALREADY_MAPPED,
                     absl::StrCat(object->Describe(), " is mapped; unmap it before launching"));
    }
  }
  return absl::OkStatus();
}

absl::Status ApplyDeltas(Context& context) {
  for (DeviceSlot& slot : context.device_slots()) {
    PreparedDelta prepared = BuildDelta(context, slot.sync);
    absl::Status status = slot.device->Apply(prepared.delta);
    if (!status.ok()) return DeviceError(slot, "rejected the state update", status);
    CommitDelta(std::move(prepared), &slot.sync);
  }
  // Every device now holds the current build epochs.
  for (const auto& [id, object] : context.objects()) {
    if (object->kind() == Kind::kAcceleration) static_cast<Acceleration*>(object)->ClearDirty();
    if (object->kind() == Kind::kGeometry) static_cast<Geometry*>(object)->ClearDirty();
  }
  return absl::OkStatus();
}

}  // namespace

absl::Status Context::Launch(unsigned entry_point, const std::vector<uint64_t>& dims) {
  if (running()) {
    return RtError(RT_ERROR_INVALID_CONTEXT, "a launch is already running on this context");
  }
  if (entry_point >= entry_point_count()) {
    return RtError(RT_ERROR_INVALID_VALUE,
                   absl::StrCat("entry point index ", entry_point, " is out of range (",
                                entry_point_count(), " entry points)"));
  }
  TS_RETURN_IF_ERROR(ValidateContext(*this));
  TS_RETURN_IF_ERROR(CheckNothingMapped(*this));
  TS_RETURN_IF_ERROR(EnsureDevices());
  RunningScope running_scope(*this);
  TS_RETURN_IF_ERROR(ApplyDeltas(*this));

  std::vector<DeviceSlot>& slots = device_slots();
  const size_t n = slots.size();
  v1::LaunchRequest common;
  common.set_launch_id(NextLaunchId());
  common.set_entry_point(entry_point);
  for (uint64_t d : dims) common.add_dims(d);
  std::vector<v1::LaunchRequest> requests(n, common);
  // Tile i goes to device i mod n: the same launch size and device set give every launch index
  // the same device each time, which GPU_LOCAL accumulation relies on.
  std::vector<v1::Tile> tiles = MakeTiles(dims, DefaultTileSize(dims.size()));
  for (v1::Tile& tile : tiles) *requests[tile.index() % n].add_tiles() = std::move(tile);
  for (size_t d = 0; d < n; ++d) requests[d].set_session_id(slots[d].sync.session_id);

  LaunchGather gather(*this, slots);
  std::atomic<bool> cancel{false};
  std::vector<std::thread> threads;
  threads.reserve(n);
  for (size_t d = 0; d < n; ++d) {
    threads.emplace_back([&, d] {
      absl::Status status;
      try {
        status = slots[d].device->Launch(requests[d], cancel, [&gather, d](v1::TileResult&& r) {
          gather.OnResult(d, std::move(r));
        });
      } catch (const std::exception& e) {
        status = absl::InternalError(absl::StrCat("threw: ", e.what()));
      } catch (...) {
        status = absl::InternalError("threw a non-standard exception");
      }
      gather.DeviceDone(d, std::move(status));
    });
  }

  // The launching thread applies results as they arrive and polls the timeout callback (OptiX
  // semantics: the callback runs on the application's thread and may ask to stop).
  bool cancelled = false;
  RTtimeoutcallback callback = timeout_callback();
  const auto interval = std::chrono::duration_cast<std::chrono::steady_clock::duration>(
      std::chrono::duration<double>(std::max(timeout_polling_seconds(), 0.001)));
  auto next_poll = std::chrono::steady_clock::now() + interval;
  while (true) {
    const bool polling = callback != nullptr && !cancelled;
    if (gather.ProcessUntil(polling ? next_poll : std::chrono::steady_clock::time_point::max())) {
      break;
    }
    if (polling && std::chrono::steady_clock::now() >= next_poll) {
      if (callback() != 0) {
        cancelled = true;
        cancel.store(true);
      }
      next_poll = std::chrono::steady_clock::now() + interval;
    }
  }
  for (std::thread& t : threads) t.join();

  absl::Status tile_status = gather.Finish();
  if (cancelled) {
    return RtError(RT_TIMEOUT_CALLBACK, "launch cancelled by the timeout callback");
  }
  for (size_t d = 0; d < n; ++d) {
    const absl::Status& status = gather.device_statuses()[d];
    if (!status.ok()) return DeviceError(slots[d], "failed the launch", status);
  }
  return tile_status;
}

}  // namespace tessera::api

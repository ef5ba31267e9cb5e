// What a device call keeps of its tiles while their pieces run, and the heartbeats that show a
// long call's progress: shared by OptiX 3 calls (inproc_device.cc) and OptiX 7 calls
// (optix7_call.cc).
#ifndef TESSERA_WORKER_CORE_CALL_PROGRESS_H_
#define TESSERA_WORKER_CORE_CALL_PROGRESS_H_

#include <chrono>
#include <cstdint>
#include <functional>

#include "tessera/scheduler/device.h"
#include "tessera/v1/launch.pb.h"

namespace tessera::worker {

// What a call knows of one of its tiles while its pieces run (guarded by the call's result lock).
struct TileState {
  v1::TileResult result;
  int pieces_left = 0;
  bool abandoned = false;  // a piece stopped at a cancel
};

// Counts a call's finished tiles and says how many now and then (a heartbeat with tiles_done),
// so that a long call shows progress before its results come back. Calls shorter than the
// interval say nothing. Guarded by the call's result lock.
class CallProgress {
 public:
  explicit CallProgress(std::chrono::steady_clock::time_point started) : last_(started) {}
  void TileFinished(const v1::LaunchRequest& request,
                    const std::function<void(v1::TileResult&&)>& on_result) {
    ++done_;
    const auto now = std::chrono::steady_clock::now();
    if (now - last_ < kInterval) return;
    last_ = now;
    v1::TileResult r;
    r.set_launch_id(request.launch_id());
    r.set_tile_index(kHeartbeatTileIndex);
    r.set_tiles_done(done_);
    on_result(std::move(r));
  }

 private:
  static constexpr std::chrono::milliseconds kInterval{100};
  std::chrono::steady_clock::time_point last_;
  uint32_t done_ = 0;
};

}  // namespace tessera::worker

#endif  // TESSERA_WORKER_CORE_CALL_PROGRESS_H_

// The Device interface: what the scheduler drives. An in-process device (worker/core) and, later,
// a gRPC client to a worker process implement it; both consume the same proto messages, so no
// device code reaches into host objects (DESIGN.md "Data flow").
#ifndef TESSERA_SCHEDULER_DEVICE_H_
#define TESSERA_SCHEDULER_DEVICE_H_

#include <atomic>
#include <functional>
#include <string>

#include "absl/status/status.h"
#include "tessera/v1/launch.pb.h"
#include "tessera/v1/state.pb.h"

namespace tessera {

struct DeviceInfo {
  std::string name;     // e.g. "inproc"
  std::string address;  // where it lives: "inproc", "127.0.0.1:5000", "unix:/tmp/w.sock"
  int thread_count = 0;
};

class Device {
 public:
  virtual ~Device() = default;

  virtual DeviceInfo Info() const = 0;

  // Applies everything that changed since the last delta. Atomic: on error the device keeps its
  // previous state and the status message names the offending object.
  virtual absl::Status Apply(const v1::StateDelta& delta) = 0;

  // Runs `request.tiles()` and calls `on_result` once per tile, from any thread, in any order.
  // After the last tile the device reports, through a TileResult with tile_index == UINT32_MAX,
  // the final contents of every OUTPUT and INPUT_OUTPUT buffer it holds (regions), unless
  // GPU_LOCAL. Returns when all tiles are done, or early once `cancel` becomes true.
  // Thread-safety: one launch at a time per device.
  virtual absl::Status Launch(const v1::LaunchRequest& request, const std::atomic<bool>& cancel,
                              const std::function<void(v1::TileResult&&)>& on_result) = 0;
};

// Marks the TileResult that carries the launch's final buffer contents.
inline constexpr uint32_t kFinalTileIndex = 0xFFFFFFFFu;

}  // namespace tessera

#endif  // TESSERA_SCHEDULER_DEVICE_H_

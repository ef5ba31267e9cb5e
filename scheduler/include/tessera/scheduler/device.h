// The Device interface: what the scheduler drives. An in-process device (worker/core) and, later,
// a gRPC client to a worker process implement it; both consume the same proto messages, so no
// device code reaches into host objects (docs/devices.md).
#ifndef TESSERA_SCHEDULER_DEVICE_H_
#define TESSERA_SCHEDULER_DEVICE_H_

#include <atomic>
#include <functional>
#include <string>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
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

  // Runs `request.tiles()` (one batch of a launch; a launch may take many calls) and calls
  // `on_result` once per tile that printed, raised an exception or failed, from any thread, in
  // any order, with its prints, exception reports and errors. Results with tile_index ==
  // kFinalTileIndex carry, as regions, every element of an OUTPUT or INPUT_OUTPUT buffer (not
  // GPU_LOCAL) that the call's programs accessed: one or more at the end, or some earlier (a
  // worker's call in rounds); an element in several carries its latest value in the last, so they
  // must be applied in the order they came, and they carry the call's place in the order the
  // device ran this launch's calls (call_sequence) so that the host can apply calls in that
  // order (0: unordered). Returns when all tiles are done, or early once
  // `cancel` becomes true. A device that is gone (process killed, connection lost, silent past its
  // deadline) answers UNAVAILABLE or DEADLINE_EXCEEDED: its tiles can run elsewhere. ABORTED means
  // the device's process crashed while running a program: running its tiles elsewhere would crash
  // that too. Thread-safety: callable from several threads; a device runs the calls one after the
  // other (its written regions belong to one call), so a second call waits inside the device.
  virtual absl::Status Launch(const v1::LaunchRequest& request, const std::atomic<bool>& cancel,
                              const std::function<void(v1::TileResult&&)>& on_result) = 0;

  // The primitive bounds this device's bounding-box programs gave when it last built GeometryGroup
  // `request.geometry_group()` with acceleration `request.acceleration()` at
  // `request.build_epoch()`, for rtAccelerationGetData (docs/acceleration_data.md). Bounds past
  // kMaxCarriedBoundsBytes in all are left out (has_bounds false). FAILED_PRECONDITION when the
  // device holds no such build (it ran no launch since, or none reached the group).
  virtual absl::StatusOr<v1::AccelerationBoundsReply> AccelerationBounds(
      const v1::AccelerationBoundsRequest& request) {
    (void)request;
    return absl::UnimplementedError("this device keeps no acceleration data");
  }
};

// The most bytes of primitive bounds one acceleration's data carries (about 1.4 million
// primitives): they travel in one message each way (rtAccelerationGetData's reply, the
// Acceleration object of a state delta), which must stay under the wire's 64 MiB.
inline constexpr uint64_t kMaxCarriedBoundsBytes = uint64_t{32} << 20;

// Marks the TileResult that carries the written regions of a Launch call.
inline constexpr uint32_t kFinalTileIndex = 0xFFFFFFFFu;
// Marks an empty TileResult a worker sends while it runs long tiles, so that the host can tell a
// busy worker from a hung one. Devices also pass such results to `on_result` with `tiles_done`
// set: how many of the call's tiles have finished so far, for launch progress (callers that do
// not show progress ignore them).
inline constexpr uint32_t kHeartbeatTileIndex = 0xFFFFFFFEu;

// Levels of Groups and Transforms (a Selector counts as a Group) a device traverses below the node
// a program traces: a GeometryGroup under 64 of them is the deepest it reaches. Deeper graphs
// fail rtContextValidate (api/src/validate.cc) and, from a host that does not check, the launch.
inline constexpr int kMaxGraphLevels = 64;

// The largest buffer element (RT_FORMAT_USER) devices accept; rtBufferSetElementSize refuses more.
inline constexpr uint64_t kMaxElementBytes = uint64_t{1} << 20;

// How a worker process that a program crashed starts the line it leaves on stderr (see
// worker/core crash_report.h); the host looks for it to name the program in the launch's error.
inline constexpr char kCrashReportPrefix[] = "tessera-worker: crashed: ";

// Whether `count` elements of `bytes` bytes, `stride` bytes apart from byte `offset` on, lie
// within `size` bytes (no overflow for any inputs; stride > 0): where built-in triangles read
// their vertices, indices and material indices, on the host (validation) and on devices.
inline bool StridedFits(uint64_t size, uint64_t offset, uint64_t count, uint64_t stride,
                        uint64_t bytes) {
  if (count == 0) return true;
  if (offset > size || bytes > size - offset) return false;
  return count - 1 <= (size - offset - bytes) / stride;
}

}  // namespace tessera

#endif  // TESSERA_SCHEDULER_DEVICE_H_

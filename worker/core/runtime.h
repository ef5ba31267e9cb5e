// The engine side of program execution: the TesseraRuntime table handed to modules, per-thread
// execution state, traversal through Embree, and the entry points the device calls.
#ifndef TESSERA_WORKER_CORE_RUNTIME_H_
#define TESSERA_WORKER_CORE_RUNTIME_H_

#include <array>
#include <atomic>
#include <cstdint>
#include <string>

#include "absl/status/status.h"
#include "tessera/detail/module_abi.h"
#include "tessera/v1/launch.pb.h"

namespace tessera::worker {

struct LaunchPlan;
struct BoundProgram;

const TesseraRuntime* EngineRuntime();

// A launch-stopping error (bad binding, a call where the OptiX table forbids it …).
struct FatalError {
  absl::Status status;
};

using Index3 = std::array<uint32_t, 3>;

// Runs the entry point's ray generation program at every launch index of the box
// [origin, origin + size) within [0, dims), x fastest; exceptions raised inside go to the
// exception program. Prints and exception reports are appended to `out`. Returns false, having
// stopped, when `cancel` or `stop` is set (checked before every launch index).
// `batched`: in blocks of the launch grid, whose first rays are traced as Embree packets
// (packet_trace.h). Throws FatalError.
bool RunTile(const LaunchPlan& plan, unsigned entry, const Index3& origin, const Index3& size,
             const Index3& dims, const std::atomic<bool>& cancel, const std::atomic<bool>& stop,
             v1::TileResult& out, bool batched = false);

// Runs a bounding box program for one primitive (at scene build time). Throws FatalError.
void RunBoundsProgram(const LaunchPlan& plan, const BoundProgram& program, unsigned primitive,
                      float result[6]);

}  // namespace tessera::worker

#endif  // TESSERA_WORKER_CORE_RUNTIME_H_

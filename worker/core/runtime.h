// The engine side of program execution: the TesseraRuntime table handed to modules, per-thread
// execution state, traversal through Embree, and the entry points the device calls.
#ifndef TESSERA_WORKER_CORE_RUNTIME_H_
#define TESSERA_WORKER_CORE_RUNTIME_H_

#include <array>
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

// Runs the entry point's ray generation program at one launch index; exceptions raised inside go
// to the exception program. Prints and exception reports are appended to `out`.
// Throws FatalError.
void RunLaunchIndex(const LaunchPlan& plan, unsigned entry, const Index3& index, const Index3& dims,
                    v1::TileResult& out);

// Runs a bounding box program for one primitive (at scene build time). Throws FatalError.
void RunBoundsProgram(const LaunchPlan& plan, const BoundProgram& program, unsigned primitive,
                      float result[6]);

}  // namespace tessera::worker

#endif  // TESSERA_WORKER_CORE_RUNTIME_H_

// The OptiX 7 execution engine of a device: what runs an optixLaunch's programs (raygen, miss,
// hit groups, exception, callables) over Embree scenes of the launch's accelerations, filling the
// TesseraOptix7Runtime table that program modules call through (tessera/optix7_device_abi.h).
// The device fills an Optix7State from state deltas, then per launch calls Prepare once and
// RunTile for each tile, holding Optix7CallMutex() throughout.
#ifndef TESSERA_WORKER_CORE_OPTIX7_ENGINE_H_
#define TESSERA_WORKER_CORE_OPTIX7_ENGINE_H_

#include <embree3/rtcore.h>

#include <atomic>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <unordered_map>

#include "absl/status/status.h"
#include "optix7_scene.h"
#include "runtime.h"
#include "tessera/v1/launch.pb.h"
#include "tessera/v1/state.pb.h"

namespace tessera::worker {

// What a device holds of a session's OptiX 7 state (filled from StateDeltas by the device).
struct Optix7State {
  std::unordered_map<uint64_t, v1::Optix7ProgramGroup> program_groups;  // by id
  std::unordered_map<uint64_t, v1::Optix7Pipeline> pipelines;           // by id
  std::map<uint64_t, uint64_t> allocations;  // live device memory: address -> size
};

// A process-wide mutex the device holds around Prepare + every RunTile of one call: a module's
// `params` global is shared by every session in the process.
std::mutex& Optix7CallMutex();

struct Optix7Launch;  // optix7_launch.h: what Prepare resolved

class Optix7Engine {
 public:
  explicit Optix7Engine(RTCDevice device);  // owns an Optix7SceneCache over `device`
  ~Optix7Engine();
  Optix7Engine(const Optix7Engine&) = delete;
  Optix7Engine& operator=(const Optix7Engine&) = delete;

  // Loads the pipeline's modules, resolves every program group's entry functions, copies the
  // launch parameters (launch.params(), params_size bytes of device memory) into each module's
  // params symbol (pipeline.params_name), checks the SBT (records inside allocations, strides
  // multiples of 16 and >= 32, headers packed for program groups of the pipeline, right kinds).
  // Errors (absl::Status) name the object: "SBT hit group record 3 at 0x...: ...".
  absl::Status Prepare(const Optix7State& state, const v1::Optix7Launch& launch,
                       const std::atomic<bool>* cancel);
  // Runs the raygen program at each launch index of the box [origin, origin+size) within dims,
  // x fastest, like worker::RunTile (runtime.h): false when cancel/stop stopped it; exception
  // reports appended to `out`; throws FatalError for launch-stopping errors. Called from many
  // threads at once after Prepare.
  bool RunTile(const Index3& origin, const Index3& size, const Index3& dims,
               const std::atomic<bool>& cancel, const std::atomic<bool>& stop, v1::TileResult& out);

  // Whether the prepared launch's tiles run with denormals flushed to zero (a fast-math module
  // or context, docs/fast_math.md); the caller sets each tracing thread's mode (float_mode.h).
  bool FlushDenormals() const;
  // The scene of traversable `handle` for the prepared launch. Thread-safe; tracing threads
  // cache the answer per launch, so the lock is taken once per thread, launch and handle.
  absl::StatusOr<const Optix7Scene*> Scene(uint64_t handle);

 private:
  std::mutex scenes_mu_;
  Optix7SceneCache scenes_;  // guarded by scenes_mu_
  std::unique_ptr<Optix7Launch> launch_;
};

}  // namespace tessera::worker

#endif  // TESSERA_WORKER_CORE_OPTIX7_ENGINE_H_

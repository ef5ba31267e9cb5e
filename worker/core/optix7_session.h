// What a device holds of one host session's OptiX 7 state: program groups and pipelines as the
// host's deltas described them, the host's device allocations, and their contents (written into
// this process's device memory range, memory::ProcessArena, at the host's addresses). An
// in-process device shares the host's memory: it keeps the allocation list, never bytes.
#ifndef TESSERA_WORKER_CORE_OPTIX7_SESSION_H_
#define TESSERA_WORKER_CORE_OPTIX7_SESSION_H_

#include "absl/status/status.h"
#include "optix7_engine.h"
#include "tessera/v1/state.pb.h"

namespace tessera::worker {

class Optix7Session {
 public:
  explicit Optix7Session(bool shares_host_memory) : shares_host_memory_(shares_host_memory) {}
  // A worker's session gives back the pages of its allocations.
  ~Optix7Session();
  Optix7Session(const Optix7Session&) = delete;
  Optix7Session& operator=(const Optix7Session&) = delete;

  // Whether `delta` carries OptiX 7 state at all.
  static bool Carries(const v1::StateDelta& delta);

  // Checks the OptiX 7 parts of `delta` without changing anything: objects with ids, entries
  // naming modules the device holds or the delta carries, allocations inside the arena and not
  // overlapping another session's (a worker holds one host's device memory at a time), memory
  // inside the allocations the delta leaves.
  absl::Status Check(const v1::StateDelta& delta) const;
  // Applies them: call after Check and after the replica accepted the delta.
  absl::Status Apply(const v1::StateDelta& delta);

  const Optix7State& state() const { return state_; }
  bool shares_host_memory() const { return shares_host_memory_; }

 private:
  const bool shares_host_memory_;
  Optix7State state_;
};

}  // namespace tessera::worker

#endif  // TESSERA_WORKER_CORE_OPTIX7_SESSION_H_

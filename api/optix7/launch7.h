// optixLaunch's work below the API: the pipeline's state and the device memory that changed go to
// the context's devices (the same devices, tiles, faults and gather as OptiX 3 launches,
// api/src/launch.cc), the launch runs tiled over them, and what programs wrote comes back into
// the host's device memory (docs/optix7.md, docs/device_memory.md).
#ifndef TESSERA_API_OPTIX7_LAUNCH7_H_
#define TESSERA_API_OPTIX7_LAUNCH7_H_

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "absl/status/status.h"
#include "optix_types.h"
#include "tessera/v1/state.pb.h"

namespace tessera::optix7 {

// What a launch needs of a program module: its file in the module cache (api/src/
// module_compiler.h), by content hash.
struct LaunchModule {
  std::string path;
  std::string hash;
  std::string bytes;  // shipped to devices that lack the module
};

// A program group as devices receive it, with the modules its entries name.
struct LaunchProgramGroup {
  v1::Optix7ProgramGroup wire;  // id, version, kind, entries
  std::vector<const LaunchModule*> modules;
};

// A pipeline as devices receive it.
struct LaunchPipeline {
  v1::Optix7Pipeline wire;  // id, version, program group ids, options
  std::vector<const LaunchProgramGroup*> groups;
};

// The devices of one OptixDeviceContext: created at its first launch from TESSERA_DEVICES (or
// the default), as an OptiX 3 context's are. Opaque; one per device context.
// The deleter is part of the pointer's type because LaunchTarget is incomplete to callers, whose
// std::default_delete could not destroy it.
class LaunchTarget;
void DestroyLaunchTarget(LaunchTarget* target);
struct LaunchTargetDeleter {
  void operator()(LaunchTarget* target) const { DestroyLaunchTarget(target); }
};
std::unique_ptr<LaunchTarget, LaunchTargetDeleter> CreateLaunchTarget();

// Runs one optixLaunch (width x height x depth) synchronously. Arguments are checked by the
// caller (api/optix7 optixLaunch); errors name what failed (a device, a program, an SBT record).
absl::Status Launch(LaunchTarget& target, const LaunchPipeline& pipeline, CUdeviceptr params,
                    size_t params_size, const OptixShaderBindingTable& sbt, unsigned width,
                    unsigned height, unsigned depth);

}  // namespace tessera::optix7

#endif  // TESSERA_API_OPTIX7_LAUNCH7_H_

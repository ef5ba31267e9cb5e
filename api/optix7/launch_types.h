// What a launch needs of modules, program groups, pipelines and devices, without OptiX headers of
// either root (launch7.h for the API side, launch_target.h for the devices' side).
#ifndef TESSERA_API_OPTIX7_LAUNCH_TYPES_H_
#define TESSERA_API_OPTIX7_LAUNCH_TYPES_H_

#include <memory>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
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
class LaunchTarget;
void DestroyLaunchTarget(LaunchTarget* target);
struct LaunchTargetDeleter {
  void operator()(LaunchTarget* target) const { DestroyLaunchTarget(target); }
};
// Bytes the target's launches sent to devices and received from them so far (launch_target.cc).
void TargetTransferStats(LaunchTarget& target, uint64_t* sent, uint64_t* received);
using LaunchTargetPtr = std::unique_ptr<LaunchTarget, LaunchTargetDeleter>;
// The devices are created at the first launch; this fails only when no context can be made.
// `cuda_device`: kEveryDevice (cuda_devices.h) to tile launches over every Tessera device of
// TESSERA_DEVICES, else the one Tessera device that is that CUDA device.
absl::StatusOr<LaunchTargetPtr> CreateLaunchTarget(int cuda_device);

}  // namespace tessera::optix7

#endif  // TESSERA_API_OPTIX7_LAUNCH_TYPES_H_

// Stands in for launch7.cc until launches land (issue 25): a target that runs nothing. Deleted
// when the real launch7.cc merges.
#include "launch7.h"

namespace tessera::optix7 {

class LaunchTarget {};

std::unique_ptr<LaunchTarget, LaunchTargetDeleter> CreateLaunchTarget() {
  return std::unique_ptr<LaunchTarget, LaunchTargetDeleter>(new LaunchTarget);
}

void DestroyLaunchTarget(LaunchTarget* target) { delete target; }

absl::Status Launch(LaunchTarget&, const LaunchPipeline&, CUdeviceptr, size_t,
                    const OptixShaderBindingTable&, unsigned, unsigned, unsigned) {
  return absl::UnimplementedError("optixLaunch: launches are not implemented yet (issue 25)");
}

}  // namespace tessera::optix7

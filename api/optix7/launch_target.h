// The launch target's side that sees api/src (an internal OptiX 3 context and its devices). Kept
// apart from launch7.h's callers: api/src's headers include the OptiX 3 root's optix.h, the API
// side the OptiX 7 root's, and no source may include both.
#ifndef TESSERA_API_OPTIX7_LAUNCH_TARGET_H_
#define TESSERA_API_OPTIX7_LAUNCH_TARGET_H_

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "launch_types.h"
#include "tessera/v1/launch.pb.h"

namespace tessera::optix7 {

// Runs `launch` of `pipeline` over `dims` (1 to 3 entries) on the target's devices.
absl::Status LaunchOnTarget(LaunchTarget& target, const LaunchPipeline& pipeline,
                            const v1::Optix7Launch& launch, const std::vector<uint64_t>& dims);

}  // namespace tessera::optix7

#endif  // TESSERA_API_OPTIX7_LAUNCH_TARGET_H_

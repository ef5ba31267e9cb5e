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
#include "absl/status/statusor.h"
#include "launch_types.h"
#include "optix_types.h"

namespace tessera::optix7 {

// Runs one optixLaunch (width x height x depth) synchronously. Arguments are checked by the
// caller (api/optix7 optixLaunch); errors name what failed (a device, a program, an SBT record).
// `accuracy_flags`: the context's TESSERA_ACCURACY_* bits, which devices build scenes and trace
// with (docs/optix7_engine.md, "Speed and accuracy").
absl::Status Launch(LaunchTarget& target, const LaunchPipeline& pipeline, CUdeviceptr params,
                    size_t params_size, const OptixShaderBindingTable& sbt, unsigned width,
                    unsigned height, unsigned depth, uint32_t accuracy_flags);

}  // namespace tessera::optix7

#endif  // TESSERA_API_OPTIX7_LAUNCH7_H_

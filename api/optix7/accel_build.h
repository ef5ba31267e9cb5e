// optixAccelComputeMemoryUsage and optixAccelBuild's work on the host: the size of an
// acceleration descriptor (worker/memory/accel_format.h) for some build inputs, and writing it
// into the output buffer, in device memory, from the application's inputs there. Workers build
// their Embree scenes from the descriptor; BVHs never travel.
#ifndef TESSERA_API_OPTIX7_ACCEL_BUILD_H_
#define TESSERA_API_OPTIX7_ACCEL_BUILD_H_

#include <cstddef>
#include <cstdint>

#include "absl/status/statusor.h"
#include "optix_types.h"

namespace tessera::optix7 {

class HostDeviceMemory;

// The output buffer a build of `inputs` needs, and the temporary buffers (Tessera uses none, but
// gives a small nonzero size: applications allocate what it says and may check the pointer).
// INVALID_ARGUMENT naming the input and field for inputs OptiX would refuse; UNIMPLEMENTED for
// what Tessera cannot build yet (curves, micromaps), saying which.
absl::StatusOr<OptixAccelBufferSizes> AccelBufferSizes(HostDeviceMemory& memory,
                                                       const OptixAccelBuildOptions& options,
                                                       const OptixBuildInput* inputs,
                                                       unsigned int count);

// Writes the descriptor of `inputs` at `output` (device memory, `output_size` bytes, 128-byte
// aligned) and returns its traversable handle, the output's address. The same errors as
// AccelBufferSizes, and INVALID_ARGUMENT for an output too small or not in one allocation.
absl::StatusOr<OptixTraversableHandle> BuildAccel(HostDeviceMemory& memory,
                                                  const OptixAccelBuildOptions& options,
                                                  const OptixBuildInput* inputs, unsigned int count,
                                                  CUdeviceptr output, size_t output_size);

}  // namespace tessera::optix7

#endif  // TESSERA_API_OPTIX7_ACCEL_BUILD_H_

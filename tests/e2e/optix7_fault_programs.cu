// The OptiX 7 fault tests' program: a raygen program slow enough per launch index (a chain of
// dependent reads of a noise buffer in device memory) for a worker to be killed in the middle of
// a launch, whose pixels depend on every read.
#include <optix.h>

#include "optix7_fault_params.h"

extern "C" {
__constant__ FaultParams params;
}

extern "C" __global__ void __raygen__slow() {
  const uint3 idx = optixGetLaunchIndex();
  unsigned int h = params.seed * 0x9E3779B9u ^ (idx.y * params.width + idx.x);
  for (unsigned int i = 0; i < params.iterations; ++i) {
    h = (h * 1664525u + 1013904223u) ^ params.noise[h % params.noise_words];
  }
  params.image[idx.y * params.width + idx.x] =
      make_uchar4(h & 0xff, (h >> 8) & 0xff, (h >> 16) & 0xff, 255);
}

// The motion blur sample's programs: an orthographic camera whose samples each pick a time in the
// shutter interval [0, 1] (stratified over every sample of every launch, jittered by a hash of
// the pixel), summed into an accumulation buffer; the last launch writes the average.
#include <optix.h>

#include "../common/vec_math.h"
#include "motion_blur.h"

extern "C" {
__constant__ Params params;
}

// A 32-bit integer hash (PCG's output function): the same jitter on every device and tiling.
static __forceinline__ __device__ unsigned int Hash(unsigned int v) {
  const unsigned int state = v * 747796405u + 2891336453u;
  const unsigned int word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
  return (word >> 22u) ^ word;
}

extern "C" __global__ void __raygen__rg() {
  const uint3 idx = optixGetLaunchIndex();
  const unsigned int pixel = idx.y * params.width + idx.x;
  const float x = (2.0f * (idx.x + 0.5f) / params.width - 1.0f) * params.half_extent.x;
  const float y = (2.0f * (idx.y + 0.5f) / params.height - 1.0f) * params.half_extent.y;
  const unsigned int total = params.launches * params.spp;
  float3 sum = make_float3(0.0f, 0.0f, 0.0f);
  for (unsigned int s = 0; s < params.spp; ++s) {
    const unsigned int stratum = params.launch * params.spp + s;
    const float jitter = (Hash(pixel * 9781u + stratum) & 0xFFFFu) / 65536.0f;
    const float time = (stratum + jitter) / total;
    unsigned int r, g, b;
    optixTrace(params.handle, make_float3(x, y, 2.0f), make_float3(0.0f, 0.0f, -1.0f), 0.0f, 1e16f,
               time, OptixVisibilityMask(255), OPTIX_RAY_FLAG_NONE, 0, 1, 0, r, g, b);
    sum = sum + make_float3(__uint_as_float(r), __uint_as_float(g), __uint_as_float(b));
  }
  float4 acc = params.launch == 0 ? make_float4(0.0f, 0.0f, 0.0f, 0.0f) : params.accum[pixel];
  acc = make_float4(acc.x + sum.x, acc.y + sum.y, acc.z + sum.z, 0.0f);
  params.accum[pixel] = acc;
  if (params.launch + 1 == params.launches) {
    params.image[pixel] = make_color(make_float3(acc.x, acc.y, acc.z) * (1.0f / total));
  }
}

extern "C" __global__ void __miss__ms() {
  optixSetPayload_0(__float_as_uint(0.1f));
  optixSetPayload_1(__float_as_uint(0.1f));
  optixSetPayload_2(__float_as_uint(0.15f));
}

extern "C" __global__ void __closesthit__ch() {
  const HitData* data = reinterpret_cast<const HitData*>(optixGetSbtDataPointer());
  optixSetPayload_0(__float_as_uint(data->color.x));
  optixSetPayload_1(__float_as_uint(data->color.y));
  optixSetPayload_2(__float_as_uint(data->color.z));
}

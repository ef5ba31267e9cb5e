// The triangle sample's programs: one primary ray per pixel, coloured by the barycentrics of the
// hit, or the miss record's background.
#include <optix.h>

#include "../common/vec_math.h"
#include "triangle.h"

extern "C" {
__constant__ Params params;
}

static __forceinline__ __device__ void SetPayload(float3 p) {
  optixSetPayload_0(__float_as_uint(p.x));
  optixSetPayload_1(__float_as_uint(p.y));
  optixSetPayload_2(__float_as_uint(p.z));
}

extern "C" __global__ void __raygen__rg() {
  const uint3 idx = optixGetLaunchIndex();
  const uint3 dim = optixGetLaunchDimensions();
  const float2 d =
      make_float2(2.0f * (idx.x + 0.5f) / dim.x - 1.0f, 2.0f * (idx.y + 0.5f) / dim.y - 1.0f);
  const float3 origin = params.cam_eye;
  const float3 direction = normalize(d.x * params.cam_u + d.y * params.cam_v + params.cam_w);
  unsigned int p0, p1, p2;
  optixTrace(params.handle, origin, direction, 0.0f, 1e16f, 0.0f, OptixVisibilityMask(255),
             OPTIX_RAY_FLAG_NONE, 0, 1, 0, p0, p1, p2);
  const float3 color = make_float3(__uint_as_float(p0), __uint_as_float(p1), __uint_as_float(p2));
  params.image[idx.y * params.image_width + idx.x] = make_color(color);
}

extern "C" __global__ void __miss__ms() {
  const MissData* data = reinterpret_cast<const MissData*>(optixGetSbtDataPointer());
  SetPayload(data->bg_color);
}

extern "C" __global__ void __closesthit__ch() {
  const float2 b = optixGetTriangleBarycentrics();
  SetPayload(make_float3(1.0f - b.x - b.y, b.x, b.y));
}

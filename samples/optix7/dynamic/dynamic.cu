// The dynamic sample's programs: a height field shaded by its normal, read from the vertex and
// index buffers the acceleration was built or updated from.
#include <optix.h>

#include "../common/vec_math.h"
#include "dynamic.h"

extern "C" {
__constant__ Params params;
}

extern "C" __global__ void __raygen__rg() {
  const uint3 idx = optixGetLaunchIndex();
  const float dx = 2.0f * (idx.x + 0.5f) / params.width - 1.0f;
  const float dy = 2.0f * (idx.y + 0.5f) / params.height - 1.0f;
  const float3 direction = normalize(dx * params.u + dy * params.v + params.w);
  unsigned int r, g, b;
  optixTrace(params.handle, params.eye, direction, 0.0f, 1e16f, 0.0f, OptixVisibilityMask(255),
             OPTIX_RAY_FLAG_DISABLE_ANYHIT, 0, 1, 0, r, g, b);
  params.image[idx.y * params.stride + params.x_offset + idx.x] =
      make_color(make_float3(__uint_as_float(r), __uint_as_float(g), __uint_as_float(b)));
}

extern "C" __global__ void __miss__ms() {
  optixSetPayload_0(__float_as_uint(0.05f));
  optixSetPayload_1(__float_as_uint(0.05f));
  optixSetPayload_2(__float_as_uint(0.1f));
}

extern "C" __global__ void __closesthit__ch() {
  const HitData* data = reinterpret_cast<const HitData*>(optixGetSbtDataPointer());
  const uint3 t = data->indices[optixGetPrimitiveIndex()];
  const float3 a = data->vertices[t.x], b = data->vertices[t.y], c = data->vertices[t.z];
  float3 n = normalize(cross(b - a, c - a));
  if (n.y < 0.0f) n = -n;
  const float shade = 0.15f + 0.85f * fmaxf(dot(n, normalize(make_float3(0.5f, 1.0f, 0.3f))), 0.0f);
  optixSetPayload_0(__float_as_uint(shade * 0.9f));
  optixSetPayload_1(__float_as_uint(shade * 0.6f));
  optixSetPayload_2(__float_as_uint(shade * 0.3f));
}

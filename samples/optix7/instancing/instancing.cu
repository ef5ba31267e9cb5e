// The instancing sample's programs: closest-hit shades a triangle by its object-space normal
// (from optixGetTriangleVertexData) carried to world space through the instance's transform,
// tinted per instance id; miss gives a gradient.
#include <optix.h>

#include "../common/vec_math.h"
#include "instancing.h"

extern "C" {
__constant__ Params params;
}

extern "C" __global__ void __raygen__rg() {
  const uint3 idx = optixGetLaunchIndex();
  const float dx = 2.0f * (idx.x + 0.5f) / params.width - 1.0f;
  const float dy = 2.0f * (idx.y + 0.5f) / params.height - 1.0f;
  const float3 direction = normalize(dx * params.u + dy * params.v + params.w);
  unsigned int r, g, b;
  optixTrace(params.handle, params.eye, direction, 0.0f, 1e16f, 0.0f, OptixVisibilityMask(1),
             OPTIX_RAY_FLAG_CULL_BACK_FACING_TRIANGLES, 0, 1, 0, r, g, b);
  params.image[idx.y * params.width + idx.x] =
      make_color(make_float3(__uint_as_float(r), __uint_as_float(g), __uint_as_float(b)));
}

extern "C" __global__ void __miss__ms() {
  const float t = 0.5f * (optixGetWorldRayDirection().y + 1.0f);
  optixSetPayload_0(__float_as_uint(0.1f + 0.1f * t));
  optixSetPayload_1(__float_as_uint(0.1f + 0.2f * t));
  optixSetPayload_2(__float_as_uint(0.2f + 0.3f * t));
}

extern "C" __global__ void __closesthit__ch() {
  const HitData* data = reinterpret_cast<const HitData*>(optixGetSbtDataPointer());
  float3 v[3];
  optixGetTriangleVertexData(optixGetGASTraversableHandle(), optixGetPrimitiveIndex(),
                             optixGetSbtGASIndex(), optixGetRayTime(), v);
  const float3 object_normal = cross(v[1] - v[0], v[2] - v[0]);
  const float3 n = normalize(optixTransformNormalFromObjectToWorldSpace(object_normal));
  const float3 light = normalize(make_float3(0.3f, 1.0f, 0.6f));
  const float shade = 0.2f + 0.8f * fmaxf(dot(n, light), 0.0f);
  const float tint = 0.6f + 0.1f * static_cast<float>(optixGetInstanceId() % 5);
  const float3 c = data->color * (shade * tint);
  optixSetPayload_0(__float_as_uint(c.x));
  optixSetPayload_1(__float_as_uint(c.y));
  optixSetPayload_2(__float_as_uint(c.z));
}

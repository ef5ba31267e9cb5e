// The cutouts sample's programs: leaves (quads) whose any-hit program ignores hits inside holes
// (a pattern of discs in the quad's parameters), for camera rays and for shadow rays (where the
// any-hit program ends the ray at the first opaque hit instead).
#include <optix.h>

#include "../common/vec_math.h"
#include "cutouts.h"

extern "C" {
__constant__ Params params;
}

namespace {

// Whether the hit lies in a hole. A quad (a, b, c, d) is the triangles (a, b, c) and (a, c, d);
// with a, b, c, d at (0,0), (1,0), (1,1), (0,1) of its parameters (s, t), the barycentrics give
// s = b1 + b2, t = b2 on the first and s = b1, t = b1 + b2 on the second. Holes are discs on a
// 4x4 grid of (s, t).
__forceinline__ __device__ bool InHole() {
  const float2 b = optixGetTriangleBarycentrics();
  const bool second = (optixGetPrimitiveIndex() & 1u) != 0;
  const float s = second ? b.x : b.x + b.y;
  const float t = second ? b.x + b.y : b.y;
  const float fs = 4.0f * s - 0.5f, ft = 4.0f * t - 0.5f;
  const float ds = fs - floorf(fs + 0.5f), dt = ft - floorf(ft + 0.5f);
  return ds * ds + dt * dt < 0.12f;
}

__forceinline__ __device__ void SetColor(float3 c) {
  optixSetPayload_0(__float_as_uint(c.x));
  optixSetPayload_1(__float_as_uint(c.y));
  optixSetPayload_2(__float_as_uint(c.z));
}

}  // namespace

extern "C" __global__ void __raygen__rg() {
  const uint3 idx = optixGetLaunchIndex();
  const float dx = 2.0f * (idx.x + 0.5f) / params.width - 1.0f;
  const float dy = 2.0f * (idx.y + 0.5f) / params.height - 1.0f;
  const float3 direction = normalize(dx * params.u + dy * params.v + params.w);
  unsigned int r, g, b, calls = 0;
  optixTrace(params.handle, params.eye, direction, 0.0f, 1e16f, 0.0f, OptixVisibilityMask(1),
             OPTIX_RAY_FLAG_NONE, kRadiance, kRayTypeCount, kRadiance, r, g, b, calls);
  const unsigned int pixel = idx.y * params.width + idx.x;
  params.image[pixel] =
      make_color(make_float3(__uint_as_float(r), __uint_as_float(g), __uint_as_float(b)));
  params.any_hit_calls[pixel] = calls;
}

extern "C" __global__ void __miss__sky() { SetColor(make_float3(0.55f, 0.7f, 0.9f)); }

extern "C" __global__ void __miss__shadow() { optixSetPayload_0(1u); }

extern "C" __global__ void __anyhit__radiance() {
  optixSetPayload_3(optixGetPayload_3() + 1);
  const HitData* data = reinterpret_cast<const HitData*>(optixGetSbtDataPointer());
  if (data->cutout && InHole()) optixIgnoreIntersection();
}

extern "C" __global__ void __anyhit__shadow() {
  const HitData* data = reinterpret_cast<const HitData*>(optixGetSbtDataPointer());
  if (data->cutout && InHole()) optixIgnoreIntersection();
  optixTerminateRay();  // an opaque hit: in shadow
}

extern "C" __global__ void __closesthit__radiance() {
  const HitData* data = reinterpret_cast<const HitData*>(optixGetSbtDataPointer());
  float3 v[3];
  optixGetTriangleVertexData(optixGetGASTraversableHandle(), optixGetPrimitiveIndex(),
                             optixGetSbtGASIndex(), 0.0f, v);
  float3 n = normalize(cross(v[1] - v[0], v[2] - v[0]));
  if (!optixIsFrontFaceHit()) n = -n;
  const float3 p = optixGetWorldRayOrigin() + optixGetRayTmax() * optixGetWorldRayDirection();
  unsigned int lit = 0;
  const float lambert = fmaxf(dot(n, params.light_direction), 0.0f);
  if (lambert > 0.0f) {
    optixTrace(params.handle, p, params.light_direction, 1e-3f, 1e16f, 0.0f, OptixVisibilityMask(1),
               OPTIX_RAY_FLAG_DISABLE_CLOSESTHIT, kShadow, kRayTypeCount, kShadow, lit);
  }
  SetColor(data->color * (0.25f + 0.75f * lambert * static_cast<float>(lit)));
}

// The spheres sample's programs: spheres as custom primitives (an intersection program reporting
// the hit distance and the normal as four attributes), Lambert shading with a shadow ray that
// stops at the first hit and runs no closest-hit program.
#include <optix.h>

#include "../common/vec_math.h"
#include "spheres.h"

extern "C" {
__constant__ Params params;
}

extern "C" __global__ void __raygen__camera() {
  const uint3 idx = optixGetLaunchIndex();
  const uint3 dim = optixGetLaunchDimensions();
  const float dx = 2.0f * (idx.x + 0.5f) / dim.x - 1.0f;
  const float dy = 2.0f * (idx.y + 0.5f) / dim.y - 1.0f;
  const float3 direction = normalize(dx * params.u + dy * params.v + params.w);
  unsigned int r, g, b;
  optixTrace(params.handle, params.eye, direction, 0.0f, 1e16f, 0.0f, OptixVisibilityMask(1),
             OPTIX_RAY_FLAG_NONE, kRadiance, kRayTypeCount, kRadiance, r, g, b);
  params.image[idx.y * params.width + idx.x] =
      make_color(make_float3(__uint_as_float(r), __uint_as_float(g), __uint_as_float(b)));
}

extern "C" __global__ void __miss__sky() {
  const MissData* data = reinterpret_cast<const MissData*>(optixGetSbtDataPointer());
  const float3 d = optixGetWorldRayDirection();
  const float3 sky = data->sky * (0.6f + 0.4f * d.y);
  optixSetPayload_0(__float_as_uint(sky.x));
  optixSetPayload_1(__float_as_uint(sky.y));
  optixSetPayload_2(__float_as_uint(sky.z));
}

extern "C" __global__ void __miss__shadow() { optixSetPayload_0(1u); }  // lit

extern "C" __global__ void __intersection__sphere() {
  const HitData* data = reinterpret_cast<const HitData*>(optixGetSbtDataPointer());
  const Sphere& s = data->spheres[optixGetPrimitiveIndex()];
  const float3 o = optixGetObjectRayOrigin() - s.center;
  const float3 d = optixGetObjectRayDirection();
  const float a = dot(d, d);
  const float b = dot(o, d);
  const float c = dot(o, o) - s.radius * s.radius;
  const float disc = b * b - a * c;
  if (disc < 0.0f) return;
  const float root = sqrtf(disc);
  const float tmin = optixGetRayTmin(), tmax = optixGetRayTmax();
  const float roots[2] = {(-b - root) / a, (-b + root) / a};
  for (int k = 0; k < 2; ++k) {
    const float t = roots[k];
    if (t > tmin && t < tmax) {
      const float3 n = (o + t * d) / s.radius;
      optixReportIntersection(t, 0, __float_as_uint(n.x), __float_as_uint(n.y),
                              __float_as_uint(n.z), __float_as_uint(s.radius));
      return;
    }
  }
}

extern "C" __global__ void __closesthit__sphere() {
  const HitData* data = reinterpret_cast<const HitData*>(optixGetSbtDataPointer());
  const Sphere& s = data->spheres[optixGetPrimitiveIndex()];
  const float3 n = normalize(make_float3(__uint_as_float(optixGetAttribute_0()),
                                         __uint_as_float(optixGetAttribute_1()),
                                         __uint_as_float(optixGetAttribute_2())));
  const float3 p = optixGetWorldRayOrigin() + optixGetRayTmax() * optixGetWorldRayDirection();
  const float lambert = fmaxf(dot(n, params.light_direction), 0.0f);
  unsigned int lit = 0;
  if (lambert > 0.0f) {
    optixTrace(params.handle, p + 1e-3f * n, params.light_direction, 0.0f, 1e16f, 0.0f,
               OptixVisibilityMask(1),
               OPTIX_RAY_FLAG_TERMINATE_ON_FIRST_HIT | OPTIX_RAY_FLAG_DISABLE_CLOSESTHIT |
                   OPTIX_RAY_FLAG_DISABLE_ANYHIT,
               kShadow, kRayTypeCount, kShadow, lit);
  }
  const float3 color = s.color * (0.15f + 0.85f * lambert * static_cast<float>(lit));
  optixSetPayload_0(__float_as_uint(color.x));
  optixSetPayload_1(__float_as_uint(color.y));
  optixSetPayload_2(__float_as_uint(color.z));
}

// Programs of the accuracy test (main.cc): a primary ray per launch index, a shadow ray from its
// hit, and an intersection program that reports whatever distance the host asks for.
#include <optix.h>

#include "params.h"

extern "C" {
__constant__ Params params;
}

extern "C" __global__ void __raygen__primary() {
  const unsigned i = optixGetLaunchIndex().x;
  if (i >= params.count) return;
  const TestRay r = params.rays[i];
  unsigned hit = 0, t = 0, prim = 0, shadow = 0;
  optixTrace(params.handle, r.origin, r.direction, r.tmin, r.tmax, 0.f, OptixVisibilityMask(255),
             OPTIX_RAY_FLAG_NONE, 0, 1, 0, hit, t, prim, shadow);
  params.results[i] = TestResult{hit, __uint_as_float(t), prim, shadow};
}

extern "C" __global__ void __miss__none() { optixSetPayload_0(0); }

extern "C" __global__ void __closesthit__record() {
  optixSetPayload_0(1);
  optixSetPayload_1(__float_as_uint(optixGetRayTmax()));
  optixSetPayload_2(optixGetPrimitiveIndex());
  if (params.shadow_mode == kNoShadow) return;
  const float3 o = optixGetWorldRayOrigin();
  const float3 d = optixGetWorldRayDirection();
  const float t = optixGetRayTmax();
  float3 origin;
  float tmin;
  if (params.shadow_mode == kSpawnPoint) {
    origin = tesseraOptixGetSpawnPoint(d);
    tmin = 0.f;
  } else {
    origin = make_float3(o.x + t * d.x, o.y + t * d.y, o.z + t * d.z);
    tmin = params.scene_epsilon;
  }
  unsigned occluded = 1;
  optixTrace(params.handle, origin, d, tmin, 1e30f, 0.f, OptixVisibilityMask(255),
             OPTIX_RAY_FLAG_TERMINATE_ON_FIRST_HIT | OPTIX_RAY_FLAG_DISABLE_CLOSESTHIT, 0, 1, 0,
             occluded);
  optixSetPayload_3(occluded);
}

// Custom primitives: reports the distance the launch index's ray names, whatever it is.
extern "C" __global__ void __intersection__report() {
  const unsigned i = optixGetLaunchIndex().x;
  optixReportIntersection(params.rays[i].report, 0);
}

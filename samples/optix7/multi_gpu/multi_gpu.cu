// The multi-GPU sample's programs: a camera that renders a band of rows (each device its own),
// Lambert-shaded triangles with shadow rays, and a gather program that assembles the bands from
// the other devices' memory through peer access.
#include <optix.h>

#include "../common/vec_math.h"
#include "multi_gpu.h"

extern "C" {
__constant__ Params params;
}

extern "C" __global__ void __raygen__band() {
  const uint3 idx = optixGetLaunchIndex();
  const unsigned int row = params.row_offset + idx.y;
  const float dx = 2.0f * (idx.x + 0.5f) / params.width - 1.0f;
  const float dy = 2.0f * (row + 0.5f) / params.height - 1.0f;
  const float3 direction = normalize(dx * params.u + dy * params.v + params.w);
  unsigned int r, g, b;
  optixTrace(params.handle, params.eye, direction, 0.0f, 1e16f, 0.0f, OptixVisibilityMask(1),
             OPTIX_RAY_FLAG_NONE, kRadiance, kRayTypeCount, kRadiance, r, g, b);
  params.image[idx.y * params.width + idx.x] =
      make_color(make_float3(__uint_as_float(r), __uint_as_float(g), __uint_as_float(b)));
}

extern "C" __global__ void __raygen__gather() {
  const uint3 idx = optixGetLaunchIndex();
  for (unsigned int i = 0; i < params.shares; ++i) {
    if (idx.y >= params.share_row[i] && idx.y < params.share_row[i + 1]) {
      params.image[idx.y * params.width + idx.x] =
          params.share[i][(idx.y - params.share_row[i]) * params.width + idx.x];
    }
  }
}

extern "C" __global__ void __miss__sky() {
  const MissData* data = reinterpret_cast<const MissData*>(optixGetSbtDataPointer());
  const float3 sky = data->sky * (0.6f + 0.4f * optixGetWorldRayDirection().y);
  optixSetPayload_0(__float_as_uint(sky.x));
  optixSetPayload_1(__float_as_uint(sky.y));
  optixSetPayload_2(__float_as_uint(sky.z));
}

extern "C" __global__ void __miss__shadow() { optixSetPayload_0(1u); }  // lit

extern "C" __global__ void __closesthit__shade() {
  const HitData* data = reinterpret_cast<const HitData*>(optixGetSbtDataPointer());
  const unsigned int prim = optixGetPrimitiveIndex();
  float3 n = data->normals[prim];
  if (dot(n, optixGetWorldRayDirection()) > 0.0f) n = -1.0f * n;  // the side the ray sees
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
  const float3 color = data->colors[prim] * (0.2f + 0.8f * lambert * static_cast<float>(lit));
  optixSetPayload_0(__float_as_uint(color.x));
  optixSetPayload_1(__float_as_uint(color.y));
  optixSetPayload_2(__float_as_uint(color.z));
}

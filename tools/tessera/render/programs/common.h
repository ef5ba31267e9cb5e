// Included first by every program of the path tracer: the program-side API, OptiX's vector math,
// and the types shared with the host.
#ifndef TESSERA_TOOLS_TESSERA_RENDER_PROGRAMS_COMMON_H_
#define TESSERA_TOOLS_TESSERA_RENDER_PROGRAMS_COMMON_H_

#include <optix.h>
#include <optixu/optixu_math_namespace.h>

#include <cmath>

#include "path_tracer.h"
#include "payloads.h"

using namespace optix;
using namespace path_tracer;

// Rec. 709 luminance: the host weighs emissive triangles with the same function.
static __device__ __inline__ float Luminance(const float3& c) {
  return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z;
}

// Light reaching the camera through this path: `light` times the path's throughput. With
// `clamp` > 0, light that arrives after a bounce (depth > 0) is scaled down to at most `clamp` in
// each component: biased, but it takes out the rare bright samples (caustics through glass and
// glossy metal) that show as speckles long before they average out (--clamp-indirect).
static __device__ __inline__ void AddLight(RadiancePayload& prd, const float3& light, float clamp) {
  float3 c = prd.throughput * light;
  if (clamp > 0.0f && prd.depth > 0) {
    const float peak = fmaxf(fmaxf(c.x, c.y), c.z);
    if (peak > clamp) c *= clamp / peak;
  }
  prd.radiance += c;
}

static __device__ __inline__ bool IsFinite(const float3& c) {
  return std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z);
}

#endif  // TESSERA_TOOLS_TESSERA_RENDER_PROGRAMS_COMMON_H_

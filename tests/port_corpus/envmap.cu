// The environment-map miss program of the OptiX SDK's tutorial and samples: a latitude-longitude
// rtTextureSampler<float4, 2> (float texels, as an .hdr image loads) looked up by the ray's
// direction; u runs around the y axis from -z, v from the nadir (0) to the zenith (1).
#include <optix.h>
#include <optixu/optixu_math_namespace.h>

#include "sample_common.h"

using namespace optix;

rtDeclareVariable(optix::Ray, ray, rtCurrentRay, );
rtDeclareVariable(PerRayData_radiance, prd_radiance, rtPayload, );
rtTextureSampler<float4, 2> envmap;

RT_PROGRAM void envmap_miss() {
  float theta = atan2f(ray.direction.x, ray.direction.z);
  float phi = M_PIf * 0.5f - acosf(ray.direction.y);
  float u = (theta + M_PIf) * (0.5f * M_1_PIf);
  float v = 0.5f * (1.0f + sin(phi));
  prd_radiance.result = make_float3(tex2D(envmap, u, v));
}

// Miss programs: the constant background of steps 0-4 and the environment map of steps 5 to 11
// (a latitude-longitude HDR image, as the SDK tutorial's envmap_miss reads it).
#include "tutorial.h"

rtDeclareVariable(float3, bg_color, , );
rtDeclareVariable(PerRayData_radiance, prd_radiance, rtPayload, );
rtDeclareVariable(optix::Ray, ray, rtCurrentRay, );
rtTextureSampler<float4, 2> envmap;

RT_PROGRAM void miss() { prd_radiance.result = bg_color; }

// The environment: u runs around the horizon from -z through +x, v from the nadir (0) to the
// zenith (1).
RT_PROGRAM void envmap_miss() {
  float theta = atan2f(ray.direction.x, ray.direction.z);
  float phi = M_PIf * 0.5f - acosf(ray.direction.y);
  float u = (theta + M_PIf) * (0.5f * M_1_PIf);
  float v = 0.5f * (1.0f + sinf(phi));
  prd_radiance.result = make_float3(tex2D(envmap, u, v));
}

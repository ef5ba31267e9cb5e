// Miss programs: the constant background of steps 0-4 and the sky gradient that stands in for
// the environment map from step 5 on (textures come later).
#include "tutorial.h"

rtDeclareVariable(float3, bg_color, , );
rtDeclareVariable(float3, horizon_color, , );
rtDeclareVariable(float3, ground_color, , );
rtDeclareVariable(PerRayData_radiance, prd_radiance, rtPayload, );
rtDeclareVariable(optix::Ray, ray, rtCurrentRay, );

RT_PROGRAM void miss() { prd_radiance.result = bg_color; }

// bg_color at the zenith, horizon_color at the horizon, fading to ground_color below it.
RT_PROGRAM void gradient_miss() {
  float y = normalize(ray.direction).y;
  if (y >= 0.0f) {
    prd_radiance.result = lerp(horizon_color, bg_color, smoothstep(0.0f, 0.6f, y));
  } else {
    prd_radiance.result = lerp(horizon_color, ground_color, smoothstep(0.0f, 0.5f, -y));
  }
}

// Any-hit programs for shadow rays (ray type 1). They live in their own module because they use
// the shadow payload, while the closest-hit modules use the radiance payload.
#include "tutorial.h"

rtDeclareVariable(PerRayData_shadow, prd_shadow, rtPayload, );
rtDeclareVariable(optix::Ray, ray, rtCurrentRay, );
rtDeclareVariable(float3, shading_normal, attribute shading_normal, );
rtDeclareVariable(float3, shadow_attenuation, , );

// Opaque material: the light is fully blocked and the ray can stop.
RT_PROGRAM void any_hit_shadow() {
  prd_shadow.attenuation = make_float3(0);
  rtTerminateRay();
}

// Glass: each surface lets through what Schlick's Fresnel term does not reflect, tinted by
// shadow_attenuation, and the ray goes on to further surfaces.
RT_PROGRAM void glass_any_hit_shadow() {
  float3 world_normal = normalize(rtTransformNormal(RT_OBJECT_TO_WORLD, shading_normal));
  float nDi = fabsf(dot(world_normal, ray.direction));

  prd_shadow.attenuation *=
      1 - tutorial::fresnel_schlick(nDi, 5, 1 - shadow_attenuation, make_float3(1));

  rtIgnoreIntersection();
}

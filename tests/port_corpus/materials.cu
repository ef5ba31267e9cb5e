// A Phong-like material and a miss program in the style of community path tracers: a shadow ray
// with OptiX 6 ray flags, the optixu helpers (fresnel_schlick, luminance, temperature, Onb,
// reflect, faceforward, lerp, smoothstep, expf and fmaxf of vectors), and the shared header.
#include <optix.h>
#include <optixu/optixu_math_namespace.h>

#include "sample_common.h"

using namespace optix;

rtDeclareVariable(float3, geometric_normal, attribute geometric_normal, );
rtDeclareVariable(float3, shading_normal, attribute shading_normal, );
rtDeclareVariable(PerRayData_radiance, prd_radiance, rtPayload, );
rtDeclareVariable(PerRayData_shadow, prd_shadow, rtPayload, );
rtDeclareVariable(optix::Ray, ray, rtCurrentRay, );
rtDeclareVariable(float, t_hit, rtIntersectionDistance, );
rtDeclareVariable(rtObject, top_shadower, , );
rtDeclareVariable(float3, light_pos, , );
rtDeclareVariable(float3, Kd, , );
rtDeclareVariable(unsigned int, shadow_ray_type, , );
rtDeclareVariable(float, scene_epsilon, , );

RT_PROGRAM void closest_hit_radiance() {
  float3 world_normal = normalize(rtTransformNormal(RT_OBJECT_TO_WORLD, shading_normal));
  float3 ffnormal = faceforward(world_normal, -ray.direction, world_normal);
  float3 hit_point = ray.origin + t_hit * ray.direction;
  float3 L = light_pos - hit_point;
  const float light_dist = length(L);
  L = normalize(L);
  float nDl = dot(ffnormal, L);

  PerRayData_shadow shadow_prd;
  shadow_prd.attenuation = make_float3(1.0f);
  if (nDl > 0.0f) {
    optix::Ray shadow_ray = make_Ray(hit_point, L, shadow_ray_type, scene_epsilon, light_dist);
    rtTrace(top_shadower, shadow_ray, shadow_prd, RT_VISIBILITY_ALL,
            RTrayflags(RT_RAY_FLAG_TERMINATE_ON_FIRST_HIT | RT_RAY_FLAG_DISABLE_CLOSESTHIT));
  }

  // A glossy term along a direction of the normal's frame, and a Fresnel-weighted tint.
  Onb onb(ffnormal);
  float3 lobe = make_float3(0.3f, 0.2f, 0.9f);
  onb.inverse_transform(lobe);
  const float3 R = reflect(ray.direction, ffnormal);
  const float fresnel =
      fresnel_schlick(fmaxf(0.0f, dot(-ray.direction, ffnormal)), 5.0f, 0.04f, 1.0f);
  float3 color = Kd * fmaxf(nDl, 0.0f) * shadow_prd.attenuation +
                 fresnel * temperature(0.5f + 0.5f * R.y) * 0.2f +
                 0.05f * fmaxf(make_float3(dot(lobe, L)), make_float3(0.0f));
  color = lerp(color, expf(-color), 0.1f) * smoothstep(0.0f, 1.0f, luminance(color) + 0.5f);
  prd_radiance.result = color;
}

RT_PROGRAM void any_hit_shadow() {
  prd_shadow.attenuation = make_float3(0.0f);
  rtTerminateRay();
}

RT_PROGRAM void miss() {
  const float t = 0.5f + 0.5f * ray.direction.y;
  prd_radiance.result = temperature(t) * 0.5f + make_float3(luminanceCIE(make_float3(t)) * 0.1f);
}

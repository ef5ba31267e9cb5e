// Declarations and helpers shared by the radiance closest-hit programs. Each module that
// includes this is one .cu file, so every declaration below exists once per module.
#ifndef TESSERA_SAMPLES_TUTORIAL_PROGRAMS_SHADING_H_
#define TESSERA_SAMPLES_TUTORIAL_PROGRAMS_SHADING_H_

#include "tutorial.h"

rtDeclareVariable(float3, geometric_normal, attribute geometric_normal, );
rtDeclareVariable(float3, shading_normal, attribute shading_normal, );

rtDeclareVariable(PerRayData_radiance, prd_radiance, rtPayload, );
rtDeclareVariable(optix::Ray, ray, rtCurrentRay, );
rtDeclareVariable(float, t_hit, rtIntersectionDistance, );

rtDeclareVariable(unsigned int, radiance_ray_type, , );
rtDeclareVariable(unsigned int, shadow_ray_type, , );
rtDeclareVariable(float, scene_epsilon, , );
rtDeclareVariable(rtObject, top_object, , );
rtDeclareVariable(rtObject, top_shadower, , );
rtDeclareVariable(int, max_depth, , );
rtDeclareVariable(float, importance_cutoff, , );

rtDeclareVariable(float3, Ka, , );
rtDeclareVariable(float3, Kd, , );
rtDeclareVariable(float3, Ks, , );
rtDeclareVariable(float, phong_exp, , );
rtDeclareVariable(float3, ambient_light_color, , );
rtBuffer<BasicLight> lights;

// The world-space shading normal, flipped to face the incoming ray.
static __device__ __inline__ float3 ffnormal_world() {
  float3 world_geo_normal = normalize(rtTransformNormal(RT_OBJECT_TO_WORLD, geometric_normal));
  float3 world_shade_normal = normalize(rtTransformNormal(RT_OBJECT_TO_WORLD, shading_normal));
  return faceforward(world_shade_normal, -ray.direction, world_geo_normal);
}

// How much of `light` reaches `hit_point` (a shadow ray to the light).
static __device__ __inline__ float3 light_attenuation(const float3& hit_point,
                                                      const BasicLight& light, const float3& L) {
  PerRayData_shadow shadow_prd;
  shadow_prd.attenuation = make_float3(1.0f);
  float Ldist = length(light.pos - hit_point);
  optix::Ray shadow_ray = optix::make_Ray(hit_point, L, shadow_ray_type, scene_epsilon, Ldist);
  rtTrace(top_shadower, shadow_ray, shadow_prd);
  return shadow_prd.attenuation;
}

// Ambient plus shadowed Lambert and Phong terms of every light (tutorial step 3).
static __device__ __inline__ float3 phong_shadowed(const float3& hit_point, const float3& ffnormal,
                                                   const float3& kd) {
  float3 color = Ka * ambient_light_color;
  for (unsigned int i = 0; i < lights.size(); ++i) {
    BasicLight light = lights[i];
    float3 L = normalize(light.pos - hit_point);
    float nDl = dot(ffnormal, L);

    if (nDl > 0.0f) {
      float3 attenuation = light_attenuation(hit_point, light, L);
      if (fmaxf(attenuation) > 0.0f) {
        float3 Lc = light.color * attenuation;
        color += kd * nDl * Lc;

        float3 H = normalize(L - ray.direction);
        float nDh = dot(ffnormal, H);
        if (nDh > 0) color += Ks * Lc * powf(nDh, phong_exp);
      }
    }
  }
  return color;
}

// Adds `reflectivity` times a recursive reflection ray unless its importance is below the
// cutoff or the ray tree is max_depth deep (tutorial step 4).
static __device__ __inline__ float3 reflect_ray(const float3& hit_point, const float3& ffnormal,
                                                const float3& reflectivity) {
  float importance = prd_radiance.importance * luminance(reflectivity);
  if (importance > importance_cutoff && prd_radiance.depth < max_depth) {
    PerRayData_radiance refl_prd;
    refl_prd.importance = importance;
    refl_prd.depth = prd_radiance.depth + 1;
    float3 R = reflect(ray.direction, ffnormal);
    optix::Ray refl_ray =
        optix::make_Ray(hit_point, R, radiance_ray_type, scene_epsilon, RT_DEFAULT_MAX);
    rtTrace(top_object, refl_ray, refl_prd);
    return reflectivity * refl_prd.result;
  }
  return make_float3(0.0f);
}

#endif  // TESSERA_SAMPLES_TUTORIAL_PROGRAMS_SHADING_H_

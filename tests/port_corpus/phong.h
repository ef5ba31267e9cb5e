// Phong shading in the style of the OptiX SDK's phong.h: ambient, then each light of a buffer of
// BasicLight with a shadow ray, a specular highlight, and a reflection ray while the ray tree's
// importance lasts. The closest-hit program that includes it picks Kd, Ka, Ks and the normal.
#pragma once

#include <optix.h>
#include <optixu/optixu_math_namespace.h>

#include "common_structs.h"
#include "sample_common.h"

rtDeclareVariable(int, max_depth, , );
rtBuffer<BasicLight> lights;
rtDeclareVariable(float3, ambient_light_color, , );
rtDeclareVariable(unsigned int, radiance_ray_type, , );
rtDeclareVariable(unsigned int, shadow_ray_type, , );
rtDeclareVariable(float, scene_epsilon, , );
rtDeclareVariable(rtObject, top_object, , );
rtDeclareVariable(rtObject, top_shadower, , );
rtDeclareVariable(optix::Ray, ray, rtCurrentRay, );
rtDeclareVariable(float, t_hit, rtIntersectionDistance, );
rtDeclareVariable(PerRayData_radiance, prd, rtPayload, );
rtDeclareVariable(PerRayData_shadow, prd_shadow, rtPayload, );

static __device__ void phongShadowed() {
  // This material is opaque: it stops every shadow ray that reaches it.
  prd_shadow.attenuation = optix::make_float3(0.0f);
  rtTerminateRay();
}

static __device__ void phongShade(float3 p_Kd, float3 p_Ka, float3 p_Ks, float3 p_normal,
                                  float p_phong_exp, float3 p_reflectivity) {
  float3 hit_point = ray.origin + t_hit * ray.direction;

  float3 result = p_Ka * ambient_light_color;

  unsigned int num_lights = lights.size();
  for (int i = 0; i < num_lights; ++i) {
    BasicLight light = lights[i];
    float Ldist = optix::length(light.pos - hit_point);
    float3 L = optix::normalize(light.pos - hit_point);
    float nDl = optix::dot(p_normal, L);

    float3 light_attenuation = make_float3(static_cast<float>(nDl > 0.0f));
    if (nDl > 0.0f && light.casts_shadow) {
      PerRayData_shadow shadow_prd;
      shadow_prd.attenuation = make_float3(1.0f);
      optix::Ray shadow_ray = optix::make_Ray(hit_point, L, shadow_ray_type, scene_epsilon, Ldist);
      rtTrace(top_shadower, shadow_ray, shadow_prd);
      light_attenuation = shadow_prd.attenuation;
    }

    if (fmaxf(light_attenuation) > 0.0f) {
      float3 Lc = light.color * light_attenuation;
      result += p_Kd * nDl * Lc;

      float3 H = optix::normalize(L - ray.direction);
      float nDh = optix::dot(p_normal, H);
      if (nDh > 0) {
        float power = pow(nDh, p_phong_exp);
        result += p_Ks * power * Lc;
      }
    }
  }

  if (fmaxf(p_reflectivity) > 0) {
    PerRayData_radiance new_prd;
    float3 ntsc_luminance = {0.30, 0.59, 0.11};
    new_prd.importance = prd.importance * optix::dot(p_reflectivity, ntsc_luminance);
    new_prd.depth = prd.depth + 1;
    if (new_prd.importance >= 0.01f && new_prd.depth <= max_depth) {
      float3 R = optix::reflect(ray.direction, p_normal);
      optix::Ray refl_ray =
          optix::make_Ray(hit_point, R, radiance_ray_type, scene_epsilon, RT_DEFAULT_MAX);
      rtTrace(top_object, refl_ray, new_prd);
      result += p_reflectivity * new_prd.result;
    }
  }

  prd.result = result;
}

// Tutorial step 10: glass. Refraction and reflection rays weighted by Schlick's Fresnel term,
// with Beer's law absorption inside the object.
#include "shading.h"

rtDeclareVariable(float3, cutoff_color, , );
rtDeclareVariable(float, fresnel_exponent, , );
rtDeclareVariable(float, fresnel_minimum, , );
rtDeclareVariable(float, fresnel_maximum, , );
rtDeclareVariable(float, refraction_index, , );
rtDeclareVariable(int, refraction_maxdepth, , );
rtDeclareVariable(int, reflection_maxdepth, , );
rtDeclareVariable(float3, refraction_color, , );
rtDeclareVariable(float3, reflection_color, , );
rtDeclareVariable(float3, extinction_constant, , );

RT_PROGRAM void glass_closest_hit_radiance() {
  const float3 h = ray.origin + t_hit * ray.direction;                                // hit point
  const float3 n = normalize(rtTransformNormal(RT_OBJECT_TO_WORLD, shading_normal));  // normal
  const float3 i = ray.direction;                                                     // incident

  float reflection = 1.0f;
  float3 result = make_float3(0.0f);

  // Beer's law attenuation for rays that travelled inside the glass.
  float3 beer_attenuation;
  if (dot(n, ray.direction) > 0) {
    beer_attenuation = expf(extinction_constant * t_hit);
  } else {
    beer_attenuation = make_float3(1);
  }

  // refraction
  if (prd_radiance.depth < min(refraction_maxdepth, max_depth)) {
    float3 t;  // transmission direction
    if (refract(t, i, n, refraction_index)) {
      // check for external or internal reflection
      float cos_theta = dot(i, n);
      if (cos_theta < 0.0f)
        cos_theta = -cos_theta;
      else
        cos_theta = dot(t, n);

      reflection =
          tutorial::fresnel_schlick(cos_theta, fresnel_exponent, fresnel_minimum, fresnel_maximum);

      float importance = prd_radiance.importance * (1.0f - reflection) *
                         luminance(refraction_color * beer_attenuation);
      if (importance > importance_cutoff) {
        optix::Ray refr_ray =
            optix::make_Ray(h, t, radiance_ray_type, scene_epsilon, RT_DEFAULT_MAX);
        PerRayData_radiance refr_prd;
        refr_prd.depth = prd_radiance.depth + 1;
        refr_prd.importance = importance;

        rtTrace(top_object, refr_ray, refr_prd);
        result += (1.0f - reflection) * refraction_color * refr_prd.result;
      } else {
        result += (1.0f - reflection) * refraction_color * cutoff_color;
      }
    }
    // else total internal reflection: all of it goes to the reflection ray below
  }

  // reflection
  if (prd_radiance.depth < min(reflection_maxdepth, max_depth)) {
    float3 r = reflect(i, n);

    float importance =
        prd_radiance.importance * reflection * luminance(reflection_color * beer_attenuation);
    if (importance > importance_cutoff) {
      optix::Ray refl_ray = optix::make_Ray(h, r, radiance_ray_type, scene_epsilon, RT_DEFAULT_MAX);
      PerRayData_radiance refl_prd;
      refl_prd.depth = prd_radiance.depth + 1;
      refl_prd.importance = importance;

      rtTrace(top_object, refl_ray, refl_prd);
      result += reflection * reflection_color * refl_prd.result;
    } else {
      result += reflection * reflection_color * cutoff_color;
    }
  }

  result = result * beer_attenuation;

  prd_radiance.result = result;
}

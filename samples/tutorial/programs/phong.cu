// Tutorial steps 1-3: Lambertian shading with ambient and point lights, Phong highlights, and
// shadows. One closest-hit program per step, named as in the SDK.
#include "shading.h"

// Step 1: ambient + Lambert.
RT_PROGRAM void closest_hit_radiance1() {
  float3 ffnormal = ffnormal_world();
  float3 color = Ka * ambient_light_color;

  float3 hit_point = ray.origin + t_hit * ray.direction;

  for (unsigned int i = 0; i < lights.size(); ++i) {
    BasicLight light = lights[i];
    float3 L = normalize(light.pos - hit_point);
    float nDl = dot(ffnormal, L);

    if (nDl > 0) color += Kd * nDl * light.color;
  }
  prd_radiance.result = color;
}

// Step 2: adds Phong highlights.
RT_PROGRAM void closest_hit_radiance2() {
  float3 ffnormal = ffnormal_world();
  float3 color = Ka * ambient_light_color;

  float3 hit_point = ray.origin + t_hit * ray.direction;

  for (unsigned int i = 0; i < lights.size(); ++i) {
    BasicLight light = lights[i];
    float3 L = normalize(light.pos - hit_point);
    float nDl = dot(ffnormal, L);

    if (nDl > 0) {
      float3 Lc = light.color;
      color += Kd * nDl * Lc;

      float3 H = normalize(L - ray.direction);
      float nDh = dot(ffnormal, H);
      if (nDh > 0) color += Ks * Lc * powf(nDh, phong_exp);
    }
  }
  prd_radiance.result = color;
}

// Step 3: the lights are seen through shadow rays (ray type 1).
RT_PROGRAM void closest_hit_radiance3() {
  float3 ffnormal = ffnormal_world();
  float3 hit_point = ray.origin + t_hit * ray.direction;
  prd_radiance.result = phong_shadowed(hit_point, ffnormal, Kd);
}

// Tutorial steps 4-7 for the floor: reflections, Schlick's Fresnel approximation, procedural
// tiles. Programs named as in the SDK.
#include "shading.h"

rtDeclareVariable(float3, reflectivity, , );
rtDeclareVariable(float3, reflectivity_n, , );
rtDeclareVariable(float3, tile_v0, , );
rtDeclareVariable(float3, tile_v1, , );
rtDeclareVariable(float3, crack_color, , );
rtDeclareVariable(float, crack_width, , );
rtDeclareVariable(float, tile_alternate, , ) = 1.0f;

// Step 4: a constant share of a recursive reflection ray.
RT_PROGRAM void floor_closest_hit_radiance4() {
  float3 ffnormal = ffnormal_world();
  float3 hit_point = ray.origin + t_hit * ray.direction;
  float3 color = phong_shadowed(hit_point, ffnormal, Kd);
  color += reflect_ray(hit_point, ffnormal, reflectivity);
  prd_radiance.result = color;
}

// Step 6: the reflected share grows towards grazing angles (Schlick).
RT_PROGRAM void floor_closest_hit_radiance5() {
  float3 ffnormal = ffnormal_world();
  float3 hit_point = ray.origin + t_hit * ray.direction;
  float3 color = phong_shadowed(hit_point, ffnormal, Kd);
  float3 r = schlick(-dot(ffnormal, ray.direction), reflectivity_n);
  color += reflect_ray(hit_point, ffnormal, r);
  prd_radiance.result = color;
}

// Step 7: tiles with dark cracks between them. Beyond the SDK, every other tile (checkerboard)
// has its diffuse color scaled by tile_alternate, so neighbouring tiles can be told apart.
RT_PROGRAM void floor_closest_hit_radiance() {
  float3 ffnormal = ffnormal_world();
  float3 hit_point = ray.origin + t_hit * ray.direction;

  float v0 = dot(tile_v0, hit_point);
  float v1 = dot(tile_v1, hit_point);
  float tile0 = floorf(v0);
  float tile1 = floorf(v1);
  v0 = v0 - tile0;
  v1 = v1 - tile1;

  float3 local_Kd;
  if (v0 > crack_width && v1 > crack_width) {
    local_Kd = Kd;
    if ((static_cast<long long>(tile0) + static_cast<long long>(tile1)) & 1) {
      local_Kd *= tile_alternate;
    }
  } else {
    local_Kd = crack_color;
  }

  float3 color = phong_shadowed(hit_point, ffnormal, local_Kd);
  float3 r = schlick(-dot(ffnormal, ray.direction), reflectivity_n);
  color += reflect_ray(hit_point, ffnormal, r);
  prd_radiance.result = color;
}

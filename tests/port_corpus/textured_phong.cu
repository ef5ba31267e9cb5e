// A textured Phong material in the style of the OptiX SDK's obj_material.cu and the textured
// materials of its samples: Kd from an rtTextureSampler<float4, 2> the host makes from a uchar4
// buffer (normalized float reads, bilinear, repeat), at the texcoord attribute the intersection
// program reports, and phong.h for the rest.
#include <optix.h>
#include <optixu/optixu_math_namespace.h>

#include "phong.h"

using namespace optix;

rtTextureSampler<float4, 2> kd_map;
rtDeclareVariable(float3, Ks, , );
rtDeclareVariable(float, phong_exp, , );
rtDeclareVariable(float3, reflectivity, , );
rtDeclareVariable(float2, texcoord_scale, , ) = {1.0f, 1.0f};

rtDeclareVariable(float3, texcoord, attribute texcoord, );
rtDeclareVariable(float3, geometric_normal, attribute geometric_normal, );
rtDeclareVariable(float3, shading_normal, attribute shading_normal, );

RT_PROGRAM void any_hit_shadow() { phongShadowed(); }

RT_PROGRAM void closest_hit_radiance() {
  float3 world_shading_normal = normalize(rtTransformNormal(RT_OBJECT_TO_WORLD, shading_normal));
  float3 world_geometric_normal =
      normalize(rtTransformNormal(RT_OBJECT_TO_WORLD, geometric_normal));
  float3 ffnormal = faceforward(world_shading_normal, -ray.direction, world_geometric_normal);

  const float2 uv = make_float2(texcoord) * texcoord_scale;
  float3 Kd = make_float3(tex2D(kd_map, uv.x, uv.y));
  float3 Ka = Kd;  // the texture's colour in shadow too, as textured SDK samples do
  phongShade(Kd, Ka, Ks, ffnormal, phong_exp, reflectivity);
}

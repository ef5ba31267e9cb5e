// Miss programs: what a radiance ray that leaves the scene sees (an equirectangular environment
// map, or a constant colour), and the verdict of a shadow ray that reached its light.
#include "common.h"

rtDeclareVariable(RadiancePayload, prd, rtPayload, );
rtDeclareVariable(ShadowPayload, shadow_prd, rtPayload, );
rtDeclareVariable(optix::Ray, ray, rtCurrentRay, );

rtDeclareVariable(float3, background_color, , );
rtDeclareVariable(int, environment_texture, , );  // a texture sampler id; 0: the colour above
rtDeclareVariable(float, environment_intensity, , );
rtDeclareVariable(float, clamp_indirect, , );  // 0: off

// Direction to equirectangular coordinates: u = 0.5 straight ahead (-Z), growing towards +X;
// v = 0 straight up (+Y), the top row of the image.
static __device__ __inline__ float2 Equirectangular(const float3& d) {
  const float u = 0.5f + atan2f(d.x, -d.z) * (0.5f * M_1_PIf);
  const float v = acosf(clamp(d.y, -1.0f, 1.0f)) * M_1_PIf;
  return make_float2(u, v);
}

RT_PROGRAM void miss_radiance() {
  prd.done = 1;
  if (prd.aov_only) {
    prd.albedo = make_float3(0.0f);
    prd.normal = make_float3(0.0f);
    prd.hit_distance = 0.0f;  // none
    return;
  }
  float3 background = background_color;
  if (environment_texture != RT_TEXTURE_ID_NULL) {
    const float2 uv = Equirectangular(normalize(ray.direction));
    background =
        environment_intensity * make_float3(rtTex2D<float4>(environment_texture, uv.x, uv.y));
  }
  // The environment is only reached by BSDF sampling, so it counts fully.
  AddLight(prd, background, clamp_indirect);
}

RT_PROGRAM void miss_shadow() { shadow_prd.visible = 1; }

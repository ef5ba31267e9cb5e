// The closest-hit program of radiance rays, shared by every material (each Material object sets
// its own factors and texture ids below). At each hit it
//   1. adds the surface's emission, weighted by multiple importance sampling against the
//      emissive-triangle sampling of the hit before (full weight after the camera or glass),
//   2. estimates direct light (next-event estimation): one punctual light picked uniformly, and
//      one point on an emissive triangle picked by power, each with a shadow ray,
//   3. samples the BSDF for the next direction (bsdf.h) and hands it to the ray generation
//      program, which traces it, ending the path by Russian roulette after three bounces.
#include "bsdf.h"

// ---- Per material (Material scope) --------------------------------------------------------------
rtDeclareVariable(float4, base_color_factor, , );
rtDeclareVariable(int, base_color_texture, , );  // texture sampler ids; 0: none
rtDeclareVariable(float, metallic_factor, , );
rtDeclareVariable(float, roughness_factor, , );
rtDeclareVariable(int, metallic_roughness_texture, , );  // B: metallic, G: roughness
rtDeclareVariable(float3, emissive_factor, , );
rtDeclareVariable(int, emissive_texture, , );
rtDeclareVariable(int, normal_texture, , );
rtDeclareVariable(float, normal_scale, , );
rtDeclareVariable(float, ior, , );
rtDeclareVariable(float, transmission, , );
rtDeclareVariable(float, specular_factor, , );  // the dielectric specular layer's weight
rtDeclareVariable(int, double_sided, , );

// ---- Scene (Context scope) ----------------------------------------------------------------------
rtDeclareVariable(rtObject, top_object, , );
rtDeclareVariable(int, max_depth, , );
rtDeclareVariable(float, clamp_indirect, , );  // 0: off
rtBuffer<PunctualLight> lights;
rtBuffer<EmissiveTriangle> emissive_triangles;
rtBuffer<float> emissive_cdf;
rtDeclareVariable(float, emissive_power, , );  // sum of area * luminance(emission)

// ---- The hit ------------------------------------------------------------------------------------
rtDeclareVariable(RadiancePayload, prd, rtPayload, );
rtDeclareVariable(optix::Ray, ray, rtCurrentRay, );
rtDeclareVariable(float, t_hit, rtIntersectionDistance, );
rtDeclareVariable(float3, geometric_normal, attribute geometric_normal, );
rtDeclareVariable(float3, shading_normal, attribute shading_normal, );
rtDeclareVariable(float2, texcoord, attribute texcoord, );
rtDeclareVariable(float4, tangent, attribute tangent, );

static __device__ __inline__ float4 Texture(int id, const float2& uv) {
  return rtTex2D<float4>(id, uv.x, uv.y);
}

// The shading normal after the normal map (tangent space, glTF's convention: +Y up in the map).
static __device__ __inline__ float3 ApplyNormalMap(const float3& n) {
  if (normal_texture == RT_TEXTURE_ID_NULL || tangent.w == 0.0f) return n;
  const float3 t_object = make_float3(tangent.x, tangent.y, tangent.z);
  float3 t = rtTransformVector(RT_OBJECT_TO_WORLD, t_object);
  t = t - dot(t, n) * n;  // Gram-Schmidt against the interpolated normal
  if (dot(t, t) <= 0.0f) return n;
  t = normalize(t);
  const float3 b = cross(n, t) * tangent.w;
  const float4 texel = Texture(normal_texture, texcoord);
  const float3 m = make_float3((2.0f * texel.x - 1.0f) * normal_scale,
                               (2.0f * texel.y - 1.0f) * normal_scale, 2.0f * texel.z - 1.0f);
  const float3 mapped = m.x * t + m.y * b + m.z * n;
  return dot(mapped, mapped) > 0.0f ? normalize(mapped) : n;
}

static __device__ __inline__ SurfaceMaterial LoadMaterial() {
  float4 base = base_color_factor;
  if (base_color_texture != RT_TEXTURE_ID_NULL) base *= Texture(base_color_texture, texcoord);
  float metallic = metallic_factor, roughness = roughness_factor;
  if (metallic_roughness_texture != RT_TEXTURE_ID_NULL) {
    const float4 mr = Texture(metallic_roughness_texture, texcoord);
    metallic *= mr.z;
    roughness *= mr.y;
  }
  SurfaceMaterial m;
  m.base_color = make_float3(base);
  m.metallic = clamp(metallic, 0.0f, 1.0f);
  m.roughness = clamp(roughness, 0.0f, 1.0f);
  m.transmission = clamp(transmission, 0.0f, 1.0f);
  m.specular = clamp(specular_factor, 0.0f, 1.0f);
  m.ior = ior > 0.0f ? ior : 1.5f;
  return m;
}

static __device__ __inline__ float3 Emission() {
  float3 e = emissive_factor;
  if (emissive_texture != RT_TEXTURE_ID_NULL) e *= make_float3(Texture(emissive_texture, texcoord));
  return e;
}

// Whether nothing blocks the segment from `origin` towards `direction` up to `distance`.
static __device__ __inline__ bool Visible(const float3& origin, const float3& direction,
                                          float distance) {
  ShadowPayload shadow;
  shadow.visible = 0;
  ++prd.rays;
  rtTrace(top_object, optix::make_Ray(origin, direction, kShadowRay, 0.0f, distance), shadow,
          RT_VISIBILITY_ALL,
          static_cast<RTrayflags>(RT_RAY_FLAG_TERMINATE_ON_FIRST_HIT |
                                  RT_RAY_FLAG_DISABLE_CLOSESTHIT | RT_RAY_FLAG_DISABLE_ANYHIT));
  return shadow.visible != 0;
}

// Direct light from one of the punctual lights, picked uniformly. `ng` faces `wo`'s side.
static __device__ __inline__ float3 SamplePunctualLight(const float3& p, const float3& ng,
                                                        const ShadingFrame& frame,
                                                        const SurfaceMaterial& m,
                                                        const LobeProbabilities& lobes,
                                                        const float3& wo) {
  const unsigned int count = static_cast<unsigned int>(lights.size());
  unsigned int index = static_cast<unsigned int>(Rnd(prd.rng) * static_cast<float>(count));
  if (index >= count) index = count - 1;
  const PunctualLight light = lights[index];
  float3 wi, radiance;
  float distance;
  if (light.type == kDirectionalLight) {
    wi = -light.direction;
    distance = RT_DEFAULT_MAX;
    radiance = light.intensity;
  } else {
    const float3 to_light = light.position - p;
    const float distance2 = dot(to_light, to_light);
    distance = sqrtf(distance2);
    wi = to_light * (1.0f / distance);
    radiance = light.intensity * (1.0f / distance2);
    if (light.range > 0.0f) {  // glTF's recommended window: smooth to zero at the range
      const float r = distance / light.range, r4 = r * r * r * r;
      radiance *= clamp(1.0f - r4, 0.0f, 1.0f);
    }
    if (light.type == kSpotLight) {
      const float cone =
          clamp(dot(light.direction, -wi) * light.spot_scale + light.spot_offset, 0.0f, 1.0f);
      radiance *= cone * cone;
    }
  }
  if (dot(ng, wi) <= 0.0f || fmaxf(radiance) <= 0.0f) return make_float3(0.0f);
  float pdf;
  const float3 wi_local = ToLocal(frame, wi);
  const float3 f = EvalBsdf(m, lobes, wo, wi_local, &pdf);
  if (fmaxf(f) <= 0.0f) return make_float3(0.0f);
  if (!Visible(tesseraSpawnPoint(wi), wi, distance)) return make_float3(0.0f);
  return f * radiance * (wi_local.z * static_cast<float>(count));
}

// Direct light from a point on an emissive triangle, the triangle picked with probability
// proportional to its power, the point uniformly on it; weighted against BSDF sampling.
static __device__ __inline__ float3 SampleEmissiveTriangle(const float3& p, const float3& ng,
                                                           const ShadingFrame& frame,
                                                           const SurfaceMaterial& m,
                                                           const LobeProbabilities& lobes,
                                                           const float3& wo) {
  // The first triangle whose running sum passes u.
  const float u = Rnd(prd.rng);
  unsigned int lo = 0, hi = static_cast<unsigned int>(emissive_cdf.size()) - 1;
  while (lo < hi) {
    const unsigned int mid = (lo + hi) / 2;
    if (u < emissive_cdf[mid]) {
      hi = mid;
    } else {
      lo = mid + 1;
    }
  }
  const EmissiveTriangle tri = emissive_triangles[lo];
  const float s = sqrtf(Rnd(prd.rng)), v = Rnd(prd.rng);
  const float b1 = s * (1.0f - v), b2 = s * v;
  const float3 to_light = tri.p0 + b1 * tri.e1 + b2 * tri.e2 - p;
  const float distance2 = dot(to_light, to_light);
  const float distance = sqrtf(distance2);
  const float3 wi = to_light * (1.0f / distance);
  float cos_light = -dot(tri.normal, wi);
  if (tri.double_sided) cos_light = fabsf(cos_light);
  if (cos_light <= 1e-6f || dot(ng, wi) <= 0.0f) return make_float3(0.0f);

  float3 emission = tri.emission;
  if (tri.emissive_texture != RT_TEXTURE_ID_NULL) {
    const float2 uv = (1.0f - b1 - b2) * tri.uv0 + b1 * tri.uv1 + b2 * tri.uv2;
    emission *= make_float3(Texture(tri.emissive_texture, uv));
  }
  // Picking the triangle (area * L / power) times a point on it (1 / area): an area density of
  // L / power, the same for every point of every emissive triangle; in solid angle:
  const float light_pdf = Luminance(tri.emission) / emissive_power * distance2 / cos_light;
  float bsdf_pdf;
  const float3 wi_local = ToLocal(frame, wi);
  const float3 f = EvalBsdf(m, lobes, wo, wi_local, &bsdf_pdf);
  if (fmaxf(f) <= 0.0f || light_pdf <= 0.0f) return make_float3(0.0f);
  // Stop short of the light itself, which the shadow ray would otherwise hit.
  if (!Visible(tesseraSpawnPoint(wi), wi, distance * 0.999f)) return make_float3(0.0f);
  return f * emission * (wi_local.z * PowerHeuristic(light_pdf, bsdf_pdf) / light_pdf);
}

RT_PROGRAM void closest_hit() {
  const float3 wo = -ray.direction;
  float3 ng = normalize(rtTransformNormal(RT_OBJECT_TO_WORLD, geometric_normal));
  float3 n = ApplyNormalMap(normalize(rtTransformNormal(RT_OBJECT_TO_WORLD, shading_normal)));
  const bool front = dot(ng, wo) > 0.0f;
  const SurfaceMaterial m = LoadMaterial();

  // Both sides of a surface reflect alike: turn the normals to the side the ray came from. (For
  // glass, `front` still says whether the ray enters or leaves.)
  if (!front) {
    ng = -ng;
    n = -n;
  }
  if (dot(n, wo) <= 0.0f) n = ng;  // an interpolated or mapped normal facing away from the ray

  if (prd.aov_only) {
    prd.albedo = m.base_color;
    prd.normal = n;
    prd.hit_distance = t_hit;
    prd.done = 1;
    return;
  }

  // 1. Emission, on the front only unless the material is double-sided (as a renderer that culls
  // back faces of single-sided glTF materials would show it).
  const float3 emission = Emission();
  if ((front || double_sided) && fmaxf(emission) > 0.0f) {
    float weight = 1.0f;
    if (prd.depth > 0 && !prd.specular && emissive_power > 0.0f) {
      const float cos_light = fabsf(dot(ng, wo));
      const float light_pdf =
          cos_light > 0.0f ? Luminance(emissive_factor) / emissive_power * t_hit * t_hit / cos_light
                           : 0.0f;
      weight = PowerHeuristic(prd.bsdf_pdf, light_pdf);
    }
    AddLight(prd, emission * weight, clamp_indirect);
  }
  if (prd.depth >= max_depth) {
    prd.done = 1;
    return;
  }

  const float3 p = ray.origin + t_hit * ray.direction;
  const ShadingFrame frame = MakeShadingFrame(n);
  const float3 wo_local = ToLocal(frame, wo);
  const LobeProbabilities lobes = ChooseLobes(m, wo_local);

  // 2. Next-event estimation (nothing for pure glass, which no light direction can reach).
  if (lobes.diffuse + lobes.specular > 0.0f) {
    float3 direct = make_float3(0.0f);
    if (lights.size() != 0) direct += SamplePunctualLight(p, ng, frame, m, lobes, wo_local);
    if (emissive_power > 0.0f) direct += SampleEmissiveTriangle(p, ng, frame, m, lobes, wo_local);
    AddLight(prd, direct, clamp_indirect);
  }

  // 3. The next direction.
  BsdfSample s;
  if (!SampleBsdf(m, lobes, wo_local, front, prd.rng, &s)) {
    prd.done = 1;
    return;
  }
  const float3 wi = normalize(ToWorld(frame, s.wi));
  // A reflection must leave on the ray's side of the geometry, a refraction on the other.
  if ((dot(ng, wi) > 0.0f) == s.transmitted) {
    prd.done = 1;
    return;
  }
  prd.throughput *= s.weight;
  prd.bsdf_pdf = s.pdf;
  prd.specular = s.delta;
  prd.origin = tesseraSpawnPoint(wi);
  prd.direction = wi;
  prd.depth += 1;

  // Russian roulette after three bounces: go on with the probability of the throughput's largest
  // component (at most 0.95), and weigh survivors up by its inverse.
  if (prd.depth > 3) {
    const float survive = fminf(fmaxf(prd.throughput), 0.95f);
    if (!(Rnd(prd.rng) < survive)) {
      prd.done = 1;
      return;
    }
    prd.throughput *= 1.0f / survive;
  }
}

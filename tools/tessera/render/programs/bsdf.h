// The material model: glTF 2.0 metallic-roughness (the specification's appendix B), with
// KHR_materials_transmission as smooth glass.
//
//   f = (1 - metallic) (1 - transmission) [ (1 - s F_d) base / pi + s F_d * specular ] dielectric
//     + metallic F_m * specular                                                     metal
//     + (1 - metallic) transmission * (smooth dielectric: reflect or refract)       glass (delta)
//
// `specular` is GGX (Trowbridge-Reitz) with alpha = roughness^2 and Smith's separable masking,
// F_d is Schlick's Fresnel with F0 from the IOR (0.04 at 1.5), s the specular layer's weight
// (KHR_materials_specular; 0 for an OBJ material without Ks, which is then Lambertian and skips
// the GGX terms), F_m Schlick's with F0 = base colour.
// Sampling picks one lobe by an estimate of its share at the outgoing direction and evaluates the
// others for the density (one-sample MIS over lobes); GGX directions come from its distribution
// of visible normals (Heitz 2018). All directions here are in the shading frame, z along the
// shading normal, and point away from the surface.
#ifndef TESSERA_TOOLS_TESSERA_RENDER_PROGRAMS_BSDF_H_
#define TESSERA_TOOLS_TESSERA_RENDER_PROGRAMS_BSDF_H_

#include "common.h"

struct SurfaceMaterial {
  float3 base_color;
  float metallic;
  float roughness;
  float transmission;
  float ior;
  float specular;  // the dielectric specular layer's weight, 0..1
};

// An orthonormal frame around unit `n` (Duff et al. 2017: no branch on the normal's direction).
struct ShadingFrame {
  float3 t, b, n;
};

static __device__ __inline__ ShadingFrame MakeShadingFrame(const float3& n) {
  const float sign = copysignf(1.0f, n.z);
  const float a = -1.0f / (sign + n.z);
  const float b = n.x * n.y * a;
  ShadingFrame o;
  o.t = make_float3(1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x);
  o.b = make_float3(b, sign + n.y * n.y * a, -n.y);
  o.n = n;
  return o;
}
static __device__ __inline__ float3 ToLocal(const ShadingFrame& o, const float3& v) {
  return make_float3(dot(v, o.t), dot(v, o.b), dot(v, o.n));
}
static __device__ __inline__ float3 ToWorld(const ShadingFrame& o, const float3& v) {
  return v.x * o.t + v.y * o.b + v.z * o.n;
}

// ---- Pieces -------------------------------------------------------------------------------------

static __device__ __inline__ float Pow5(float x) {
  const float x2 = x * x;
  return x2 * x2 * x;
}
static __device__ __inline__ float SchlickF(float f0, float cos_theta) {
  return f0 + (1.0f - f0) * Pow5(fmaxf(0.0f, 1.0f - cos_theta));
}
static __device__ __inline__ float3 SchlickF(const float3& f0, float cos_theta) {
  return f0 + (make_float3(1.0f) - f0) * Pow5(fmaxf(0.0f, 1.0f - cos_theta));
}

// GGX's alpha^2 from perceptual roughness; a floor keeps a mirror's peak finite in floats.
static __device__ __inline__ float GgxAlpha(float roughness) {
  return fmaxf(roughness * roughness, 2e-3f);
}
static __device__ __inline__ float GgxD(float n_dot_h, float a2) {
  const float d = n_dot_h * n_dot_h * (a2 - 1.0f) + 1.0f;
  return a2 / (M_PIf * d * d);
}
static __device__ __inline__ float SmithG1(float n_dot_x, float a2) {
  return 2.0f * n_dot_x / (n_dot_x + sqrtf(a2 + (1.0f - a2) * n_dot_x * n_dot_x));
}

// A microfacet normal from GGX's distribution of normals visible from `wo` (Heitz 2018,
// "Sampling the GGX Distribution of Visible Normals").
static __device__ __inline__ float3 SampleGgxVisibleNormal(const float3& wo, float alpha, float u1,
                                                           float u2) {
  const float3 vh = normalize(make_float3(alpha * wo.x, alpha * wo.y, wo.z));
  const float len2 = vh.x * vh.x + vh.y * vh.y;
  const float3 t1 =
      len2 > 0.0f ? make_float3(-vh.y, vh.x, 0.0f) * (1.0f / sqrtf(len2)) : make_float3(1, 0, 0);
  const float3 t2 = cross(vh, t1);
  const float r = sqrtf(u1), phi = 2.0f * M_PIf * u2;
  const float p1 = r * cosf(phi);
  const float s = 0.5f * (1.0f + vh.z);
  const float p2 = (1.0f - s) * sqrtf(fmaxf(0.0f, 1.0f - p1 * p1)) + s * r * sinf(phi);
  const float3 nh = p1 * t1 + p2 * t2 + sqrtf(fmaxf(0.0f, 1.0f - p1 * p1 - p2 * p2)) * vh;
  return normalize(make_float3(alpha * nh.x, alpha * nh.y, fmaxf(1e-6f, nh.z)));
}

// Unpolarized Fresnel reflectance of a smooth dielectric; `eta` is the index on the incident side
// over the index on the other side, `cos_i` the incident cosine (> 0).
static __device__ __inline__ float FresnelDielectric(float cos_i, float eta) {
  const float sin2_t = eta * eta * fmaxf(0.0f, 1.0f - cos_i * cos_i);
  if (sin2_t >= 1.0f) return 1.0f;  // total internal reflection
  const float cos_t = sqrtf(1.0f - sin2_t);
  const float rs = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
  const float rp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
  return 0.5f * (rs * rs + rp * rp);
}

// ---- The BSDF -----------------------------------------------------------------------------------

// How often each lobe is sampled at outgoing direction `wo` (they add up to 1, or all are 0 for
// a black surface).
struct LobeProbabilities {
  float diffuse, specular, transmission;
};

static __device__ __inline__ float DielectricF0(float ior) {
  const float r = (ior - 1.0f) / (ior + 1.0f);
  return r * r;
}

static __device__ __inline__ LobeProbabilities ChooseLobes(const SurfaceMaterial& m,
                                                           const float3& wo) {
  const float kd = (1.0f - m.metallic) * (1.0f - m.transmission);
  const float f_d = m.specular * SchlickF(DielectricF0(m.ior), wo.z);
  const float3 f_m = SchlickF(m.base_color, wo.z);
  LobeProbabilities p;
  p.diffuse = kd * (1.0f - f_d) * Luminance(m.base_color);
  p.specular = Luminance(kd * f_d * make_float3(1.0f) + m.metallic * f_m);
  p.transmission = (1.0f - m.metallic) * m.transmission;
  // Highlights of mostly diffuse surfaces are found by next-event estimation too, but not those
  // of the environment: keep sampling them now and then.
  if (p.specular > 0.0f) p.specular = fmaxf(p.specular, 0.1f * (p.diffuse + p.transmission));
  const float sum = p.diffuse + p.specular + p.transmission;
  if (sum > 0.0f) {
    p.diffuse /= sum;
    p.specular /= sum;
    p.transmission /= sum;
  }
  return p;
}

// The non-delta part of the BSDF for light arriving from `wi` and leaving towards `wo`, and the
// density with which SampleBsdf would have picked `wi` (`*pdf`, solid angle).
static __device__ __inline__ float3 EvalBsdf(const SurfaceMaterial& m, const LobeProbabilities& p,
                                             const float3& wo, const float3& wi, float* pdf) {
  *pdf = 0.0f;
  if (wo.z <= 0.0f || wi.z <= 0.0f) return make_float3(0.0f);
  const float kd = (1.0f - m.metallic) * (1.0f - m.transmission);
  if (m.metallic == 0.0f && (m.specular == 0.0f || kd == 0.0f)) {  // no glossy layer: Lambert
    *pdf = p.diffuse * wi.z * M_1_PIf;
    return kd * M_1_PIf * m.base_color;
  }
  const float3 h = normalize(wo + wi);
  const float v_dot_h = fmaxf(0.0f, dot(wo, h));
  const float a2 = GgxAlpha(m.roughness) * GgxAlpha(m.roughness);
  const float d = GgxD(h.z, a2);
  const float g1_o = SmithG1(wo.z, a2);
  const float specular = d * g1_o * SmithG1(wi.z, a2) / (4.0f * wo.z * wi.z);
  const float f_d = m.specular * SchlickF(DielectricF0(m.ior), v_dot_h);
  const float3 f_m = SchlickF(m.base_color, v_dot_h);
  const float3 diffuse = kd * (1.0f - f_d) * M_1_PIf * m.base_color;
  const float3 f = diffuse + (kd * f_d * make_float3(1.0f) + m.metallic * f_m) * specular;
  *pdf = p.diffuse * wi.z * M_1_PIf + p.specular * g1_o * d / (4.0f * wo.z);
  return f;
}

struct BsdfSample {
  float3 wi;      // the sampled direction (shading frame), towards where light comes from
  float3 weight;  // f * cos / pdf: what the path's throughput is multiplied by
  float pdf;      // solid-angle density; 0 for the glass lobe (a delta)
  bool delta;     // from the glass lobe: lights cannot sample it, so its hits count emission fully
  bool transmitted;  // refracted through the surface
};

// Picks the next direction. `entering` says whether `wo` is on the geometric front (outside) of a
// transmissive surface. False when the path ends here (a black surface, a direction below it).
static __device__ __inline__ bool SampleBsdf(const SurfaceMaterial& m, const LobeProbabilities& p,
                                             const float3& wo, bool entering, Rng& rng,
                                             BsdfSample* s) {
  const float u = Rnd(rng), u1 = Rnd(rng), u2 = Rnd(rng);
  s->delta = false;
  s->transmitted = false;
  if (u < p.diffuse) {
    cosine_sample_hemisphere(u1, u2, s->wi);
  } else if (u < p.diffuse + p.specular) {
    const float3 h = SampleGgxVisibleNormal(wo, GgxAlpha(m.roughness), u1, u2);
    s->wi = reflect(-wo, h);
  } else if (p.transmission > 0.0f) {
    // Smooth glass: reflect with the Fresnel reflectance, else refract. The lobe's own weight over
    // its probability is all that is left, tinted by the base colour where light goes through.
    const float eta = entering ? 1.0f / m.ior : m.ior;
    const float cos_i = fmaxf(wo.z, 1e-6f);
    const float fresnel = FresnelDielectric(cos_i, eta);
    const float share = (1.0f - m.metallic) * m.transmission / p.transmission;
    s->delta = true;
    s->pdf = 0.0f;
    if (u1 < fresnel) {
      s->wi = make_float3(-wo.x, -wo.y, wo.z);
      s->weight = make_float3(share);
    } else {
      const float cos_t = sqrtf(fmaxf(0.0f, 1.0f - eta * eta * (1.0f - cos_i * cos_i)));
      s->wi = normalize(make_float3(-eta * wo.x, -eta * wo.y, -cos_t));
      s->weight = share * m.base_color;
      s->transmitted = true;
    }
    return true;
  } else {
    return false;  // black: nothing is reflected
  }
  const float3 f = EvalBsdf(m, p, wo, s->wi, &s->pdf);
  if (s->pdf <= 0.0f) return false;  // below the surface
  s->weight = f * (s->wi.z / s->pdf);
  return true;
}

// The power heuristic (Veach, beta = 2) for one sample of each of two strategies.
static __device__ __inline__ float PowerHeuristic(float pdf, float other_pdf) {
  const float a = pdf * pdf, b = other_pdf * other_pdf;
  return a + b > 0.0f ? a / (a + b) : 0.0f;
}

#endif  // TESSERA_TOOLS_TESSERA_RENDER_PROGRAMS_BSDF_H_

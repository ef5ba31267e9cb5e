// tessera-bench-tradeoff's probes: rays read from a buffer, what each hits, and whether a
// secondary ray leaving the hit hits the surface again. Secondary rays start at the hit point with
// tmin scene_epsilon, as OptiX 3 applications write them; TESSERA_ACCURACY_OFFSET_RAYS moves them
// past the hit's error bound instead.
#include <optix.h>
#include <optixu/optixu_math_namespace.h>

using namespace optix;

rtDeclareVariable(rtObject, top_object, , );
rtDeclareVariable(float, scene_epsilon, , );
rtDeclareVariable(optix::Ray, ray, rtCurrentRay, );
rtDeclareVariable(float, t_hit, rtIntersectionDistance, );

// ---- Probes -----------------------------------------------------------------------------------
rtBuffer<float4, 1> rays;            // per probe: (origin, tmin), (direction, tmax)
rtBuffer<float4, 1> secondary_dirs;  // per probe: a direction into the hit face's outer side, or 0
rtBuffer<uint4, 1> probe_results;  // (1 hit / 0 miss, 1 the secondary ray hit something, primitive)
rtDeclareVariable(unsigned int, probe_index, rtLaunchIndex, );

struct ProbePayload {
  unsigned int hit;
  unsigned int secondary;
  unsigned int primitive;
};
struct ShadowPayload {
  unsigned int hit;
};
rtDeclareVariable(ProbePayload, probe, rtPayload, );
rtDeclareVariable(ShadowPayload, shadow, rtPayload, );

RT_PROGRAM void probe_shoot() {
  const float4 o = rays[2 * probe_index];
  const float4 d = rays[2 * probe_index + 1];
  ProbePayload p;
  p.hit = 0;
  p.secondary = 0;
  p.primitive = 0;
  rtTrace(top_object, make_Ray(make_float3(o), make_float3(d), 0, o.w, d.w), p);
  probe_results[probe_index] = make_uint4(p.hit, p.secondary, p.primitive, 0);
}

RT_PROGRAM void probe_closest_hit() {
  probe.hit = 1;
  probe.primitive = rtGetPrimitiveIndex();
  const float3 dir = make_float3(secondary_dirs[probe_index]);
  if (dir.x == 0.f && dir.y == 0.f && dir.z == 0.f) return;
  ShadowPayload s;
  s.hit = 0;
  rtTrace(top_object,
          make_Ray(ray.origin + t_hit * ray.direction, dir, 1, scene_epsilon, RT_DEFAULT_MAX), s);
  probe.secondary = s.hit;
}

RT_PROGRAM void shadow_closest_hit() { shadow.hit = 1; }

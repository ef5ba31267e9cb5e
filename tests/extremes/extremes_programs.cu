// Programs of the extremes suite (extremes_test.cc): rays read from a buffer, what each hit, how
// many candidates its any-hit program saw, and whether a secondary ray leaving the hit (by the
// spawn mode) hit anything again.
#include <optix.h>
#include <optixu/optixu_math_namespace.h>

using namespace optix;

rtBuffer<float4, 1> rays;            // per launch index: (origin, tmin), (direction, tmax)
rtBuffer<float4, 1> secondary_dirs;  // per launch index: the secondary ray's direction
rtBuffer<uint4, 1> results;  // t's bits (0xFFFFFFFF: miss), primitive, candidates, secondary hit
rtDeclareVariable(rtObject, top_object, , );
rtDeclareVariable(unsigned int, launch_index, rtLaunchIndex, );
// 0: no secondary ray; 1: from the hit point with tmin scene_epsilon; 2: from tesseraSpawnPoint
// with tmin 0; 3: from the hit point with tmin 0 (TESSERA_ACCURACY_OFFSET_RAYS moves it); 4: as 2,
// after a spawn point toward the other side from the same hit (the engine prepares a hit's spawn
// points once: the second must still start on its own side).
rtDeclareVariable(unsigned int, spawn_mode, , );
rtDeclareVariable(float, scene_epsilon, , );
rtDeclareVariable(optix::Ray, ray, rtCurrentRay, );
rtDeclareVariable(float, t_hit, rtIntersectionDistance, );

struct Payload {
  float t;
  unsigned int primitive;
  unsigned int candidates;
  unsigned int secondary;
};
struct ShadowPayload {
  unsigned int hit;
};
rtDeclareVariable(Payload, payload, rtPayload, );
rtDeclareVariable(ShadowPayload, shadow, rtPayload, );

RT_PROGRAM void shoot() {
  const float4 o = rays[2 * launch_index];
  const float4 d = rays[2 * launch_index + 1];
  Payload p;
  p.t = __uint_as_float(0xFFFFFFFFu);
  p.primitive = 0xFFFFFFFFu;
  p.candidates = 0;
  p.secondary = 0;
  rtTrace(top_object, make_Ray(make_float3(o), make_float3(d), 0, o.w, d.w), p);
  results[launch_index] = make_uint4(__float_as_uint(p.t), p.primitive, p.candidates, p.secondary);
}

RT_PROGRAM void closest_hit() {
  payload.t = t_hit;
  payload.primitive = rtGetPrimitiveIndex();
  if (spawn_mode == 0) return;
  const float3 hit = ray.origin + t_hit * ray.direction;
  const float3 dir = make_float3(secondary_dirs[launch_index]);
  ShadowPayload s;
  s.hit = 0;
  if (spawn_mode == 1) {
    rtTrace(top_object, make_Ray(hit, dir, 1, scene_epsilon, RT_DEFAULT_MAX), s);
  } else if (spawn_mode == 2) {
    rtTrace(top_object, make_Ray(tesseraSpawnPoint(dir), dir, 1, 0.f, RT_DEFAULT_MAX), s);
  } else if (spawn_mode == 4) {
    const float3 other_side = tesseraSpawnPoint(-dir);
    const float3 origin = tesseraSpawnPoint(dir);
    rtTrace(top_object, make_Ray(origin, dir, 1, 0.f, RT_DEFAULT_MAX), s);
    if (other_side.x == origin.x && other_side.y == origin.y && other_side.z == origin.z) {
      s.hit = 2;  // both on one side
    }
  } else {
    rtTrace(top_object, make_Ray(hit, dir, 1, 0.f, RT_DEFAULT_MAX), s);
  }
  payload.secondary = s.hit;
}

RT_PROGRAM void shadow_closest_hit() { shadow.hit = 1; }

// Counts every candidate and keeps it.
RT_PROGRAM void counting_any_hit() { payload.candidates += 1; }

// ---- A mesh as an OptiX 3 application writes it: an intersection program with its own test -----
rtBuffer<float3> vertex_buffer;
rtBuffer<int3> index_buffer;

RT_PROGRAM void mesh_bounds(int prim, float result_box[6]) {
  const int3 v = index_buffer[prim];
  const float3 a = vertex_buffer[v.x], b = vertex_buffer[v.y], c = vertex_buffer[v.z];
  const float3 lo = fminf(fminf(a, b), c), hi = fmaxf(fmaxf(a, b), c);
  result_box[0] = lo.x;
  result_box[1] = lo.y;
  result_box[2] = lo.z;
  result_box[3] = hi.x;
  result_box[4] = hi.y;
  result_box[5] = hi.z;
}

// The OptiX SDK's triangle_mesh.cu test: optixu's intersect_triangle (Moeller-Trumbore).
RT_PROGRAM void mesh_intersect(int prim) {
  const int3 v = index_buffer[prim];
  float3 n;
  float t, beta, gamma;
  if (intersect_triangle(ray, vertex_buffer[v.x], vertex_buffer[v.y], vertex_buffer[v.z], n, t,
                         beta, gamma)) {
    if (rtPotentialIntersection(t)) rtReportIntersection(0);
  }
}

// ---- Invalid rays (edge_cases_test.cc) -------------------------------------------------------
rtBuffer<uint4, 1> outcomes;  // per launch index: 1 miss ran, 2 exception ran (x = what)
rtDeclareVariable(Payload, marker, rtPayload, );

RT_PROGRAM void marking_miss() { marker.secondary = 1; }

RT_PROGRAM void shoot_marked() {
  const float4 o = rays[2 * launch_index];
  const float4 d = rays[2 * launch_index + 1];
  Payload p;
  p.t = 0.f;
  p.primitive = 0;
  p.candidates = 0;
  p.secondary = 0;
  rtTrace(top_object, make_Ray(make_float3(o), make_float3(d), 0, o.w, d.w), p);
  outcomes[launch_index] = make_uint4(p.secondary, 0, 0, 0);
}

RT_PROGRAM void invalid_ray_exception() {
  outcomes[launch_index] = make_uint4(2, rtGetExceptionCode(), 0, 0);
}

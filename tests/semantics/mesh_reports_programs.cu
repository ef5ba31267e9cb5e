// Programs of mesh_reports_test.cc: intersection programs that report more than once per call, on
// an OptiX 3 mesh traced as native Embree triangles (builder Trbvh) and as user geometry (Bvh),
// and one that leaves an attribute unwritten. The bounds program is semantics_programs.cu's.
#include <optix.h>
#include <optixu/optixu_math_namespace.h>

using namespace optix;

struct Radiance {
  unsigned any_hits;
  unsigned attribute;
  float t;
  unsigned partial;
};
struct Shadow {
  unsigned any_hits;
};

rtDeclareVariable(uint2, launch_index, rtLaunchIndex, );
rtDeclareVariable(rtObject, top_object, , );
rtDeclareVariable(optix::Ray, ray, rtCurrentRay, );
rtDeclareVariable(float, hit_t, rtIntersectionDistance, );
rtDeclareVariable(Radiance, radiance, rtPayload, );
rtDeclareVariable(Shadow, shadow, rtPayload, );
rtDeclareVariable(unsigned, a_id, attribute a_id, );
rtDeclareVariable(unsigned, b_id, attribute b_id, );
rtBuffer<float3> vertex_buffer;
rtBuffer<int3> index_buffer;
rtBuffer<uint4, 2> output;

// Moeller-Trumbore for triangle `prim` of the mesh.
static __device__ bool Triangle(int prim, float& t) {
  const int3 v = index_buffer[prim];
  const float3 p0 = vertex_buffer[v.x], p1 = vertex_buffer[v.y], p2 = vertex_buffer[v.z];
  const float3 e1 = p1 - p0, e2 = p2 - p0;
  const float3 pv = cross(ray.direction, e2);
  const float det = dot(e1, pv);
  if (fabsf(det) < 1e-12f) return false;
  const float inv = 1.f / det;
  const float3 tv = ray.origin - p0;
  const float u = dot(tv, pv) * inv;
  if (u < 0.f || u > 1.f) return false;
  const float3 qv = cross(tv, e1);
  const float w = dot(ray.direction, qv) * inv;
  if (w < 0.f || u + w > 1.f) return false;
  t = dot(e2, qv) * inv;
  return true;
}

// Tests every triangle in one call, nearest first: the report for the hit Embree found must win,
// not the last one.
RT_PROGRAM void intersect_all(int) {
  for (int k = 0; k < 4; ++k) {
    float t;
    if (Triangle(k, t) && rtPotentialIntersection(t)) {
      a_id = k;
      rtReportIntersection(0);
    }
  }
}

// Reports its triangle twice: the first report stands, and any-hit programs run once.
RT_PROGRAM void intersect_twice(int prim) {
  float t;
  if (!Triangle(prim, t)) return;
  if (rtPotentialIntersection(t)) {
    a_id = prim;
    rtReportIntersection(0);
  }
  if (rtPotentialIntersection(t)) {
    a_id = prim + 100;
    rtReportIntersection(0);
  }
}

// Writes b_id only at launch index x = 1: elsewhere it must read zero, whatever ran before.
RT_PROGRAM void intersect_partial(int prim) {
  float t;
  if (Triangle(prim, t) && rtPotentialIntersection(t)) {
    a_id = prim;
    if (launch_index.x == 1) b_id = 1000 + launch_index.y;
    rtReportIntersection(0);
  }
}

RT_PROGRAM void closest_hit() {
  radiance.attribute = a_id;
  radiance.t = hit_t;
  radiance.partial = b_id;
}
RT_PROGRAM void count_any_hit() { ++radiance.any_hits; }
RT_PROGRAM void shadow_any_hit() {
  ++shadow.any_hits;
  rtTerminateRay();
}

RT_PROGRAM void ray_gen() {
  // Off the squares' diagonals, where two triangles tie and either may rightly win.
  const float3 origin =
      make_float3(0.1f * launch_index.x - 0.33f, 0.1f * launch_index.y - 0.37f, 0.f);
  Radiance r = {0, 0xAAAA, -1.f, 0xBBBB};
  rtTrace(top_object, make_Ray(origin, make_float3(0.f, 0.f, 1.f), 0, 0.001f, 1000.f), r);
  Shadow s = {0};
  rtTrace(top_object, make_Ray(origin, make_float3(0.f, 0.f, 1.f), 1, 0.001f, 1000.f), s);
  output[launch_index] =
      make_uint4(r.any_hits | (s.any_hits << 8), r.attribute, __float_as_uint(r.t), r.partial);
}

// A selector's visit program that traverses its first child.
RT_PROGRAM void visit_first() { rtIntersectChild(0); }

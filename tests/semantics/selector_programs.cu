// Programs of selector_test.cc (OptiX 3 guide, "Selector Programs"): visit programs that pick a
// child by the ray's direction (the guide's example), by a variable of the selector's scope, or
// visit several children; planes at a depth each child's geometry sets, shaded with a value its
// material sets.
#include <optix.h>
#include <optixu/optixu_math_namespace.h>

using namespace optix;

struct Payload {
  float value;   // the closest hit's material value, -1 on a miss
  float t;       // its distance
  float visits;  // visit programs run for the ray
  float seen;    // what the (last) visit program saw: the ray's origin x, or a distance
};

rtDeclareVariable(uint2, launch_index, rtLaunchIndex, );
rtDeclareVariable(rtObject, top_object, , );
rtDeclareVariable(optix::Ray, ray, rtCurrentRay, );
rtDeclareVariable(float, hit_t, rtIntersectionDistance, );
rtDeclareVariable(Payload, prd, rtPayload, );
rtBuffer<float4, 2> result;

// Rays start at (x, 0, 0) and go along +z, tilted up on even rows and down on odd ones.
RT_PROGRAM void trace_raygen() {
  Payload p = {0.f, 0.f, 0.f, 0.f};
  const float3 origin = make_float3(static_cast<float>(launch_index.x), 0.f, 0.f);
  const float3 dir = make_float3(0.f, launch_index.y % 2 == 0 ? 0.125f : -0.125f, 1.f);
  rtTrace(top_object, make_Ray(origin, dir, 0, 0.f, RT_DEFAULT_MAX), p);
  result[launch_index] = make_float4(p.value, p.t, p.visits, p.seen);
}

RT_PROGRAM void miss() {
  prd.value = -1.f;
  prd.t = -1.f;
}

// ---- A plane z = plane_z, in its geometry's scope --------------------------------------------
rtDeclareVariable(float, plane_z, , );
rtDeclareVariable(float, value, , );

RT_PROGRAM void plane_intersect(int) {
  const float t = (plane_z - ray.origin.z) / ray.direction.z;
  if (rtPotentialIntersection(t)) rtReportIntersection(0);
}
RT_PROGRAM void plane_bounds(int, float result[6]) {
  result[0] = result[1] = -1e6f;
  result[3] = result[4] = 1e6f;
  result[2] = plane_z - 0.01f;
  result[5] = plane_z + 0.01f;
}
RT_PROGRAM void closest_hit() {
  prd.value = value;
  prd.t = hit_t;
}

// ---- Visit programs --------------------------------------------------------------------------
// The guide's example; it counts itself in the payload and records the ray's origin x in the
// selector's space (Table 6: object space).
RT_PROGRAM void visit_by_direction() {
  prd.visits += 1.f;
  prd.seen = ray.origin.x;
  rtIntersectChild(static_cast<unsigned>(ray.direction.y < 0));
}

// A variable of the program's or the selector's scope picks the child.
rtDeclareVariable(unsigned, choice, , );
RT_PROGRAM void visit_by_choice() { rtIntersectChild(choice); }

// Both children, the second after recording the distance the first left.
RT_PROGRAM void visit_both() {
  rtIntersectChild(0);
  prd.seen = hit_t;
  rtIntersectChild(1);
}

RT_PROGRAM void visit_out_of_range() { rtIntersectChild(5); }

// A visit program may not trace.
RT_PROGRAM void visit_traces() {
  Payload p = {0.f, 0.f, 0.f, 0.f};
  rtTrace(top_object, ray, p);
}

// The child picked by a callable program (selector_other_programs.cu).
rtCallableProgram(void, pick, ());
RT_PROGRAM void visit_via_callable() {
  prd.visits += 1.f;
  pick();
}

// Programs of flattened_graph_test.cc: what programs see of a hit below Groups and Transforms
// (distance, primitive, transforms in intersection and closest-hit programs) and how many
// candidates an any-hit program meets.
#include <optix.h>
#include <optixu/optixu_math_namespace.h>

using namespace optix;

struct Seen {
  float4 hit;        // t, instance tag, primitive, any-hit candidates of ray type 1
  float4 point;      // rtTransformPoint(object to world, origin), object-to-world m[0]
  float4 matrix;     // object-to-world m[3], m[7], m[11]; world-to-object m[11]
  float4 intersect;  // the intersection program's rtTransformPoint(object to world, (1, 2, 3)),
                     // the closest-hit program's rtTransformNormal(object to world, +z).z
};

rtDeclareVariable(uint2, launch_index, rtLaunchIndex, );
rtDeclareVariable(rtObject, top_object, , );
rtDeclareVariable(Seen, seen, rtPayload, );
rtDeclareVariable(optix::Ray, ray, rtCurrentRay, );
rtDeclareVariable(float, t_hit, rtIntersectionDistance, );
rtDeclareVariable(float4, sphere, , );
rtDeclareVariable(float, tag, , );
rtDeclareVariable(float3, is_point, attribute is_point, );
rtDeclareVariable(float, primitive, attribute primitive, );
rtBuffer<float4, 2> out_hit;
rtBuffer<float4, 2> out_point;
rtBuffer<float4, 2> out_matrix;
rtBuffer<float4, 2> out_intersect;
rtBuffer<float3> vertex_buffer;
rtBuffer<int3> index_buffer;

// A grid of rays along +z, 0.5 apart, from x = -7.75 and y = -1.75: ray type 0 for the closest
// hit, ray type 1 for the any-hit count.
RT_PROGRAM void camera() {
  const float3 origin =
      make_float3(launch_index.x * 0.5f - 7.75f, launch_index.y * 0.5f - 1.75f, -20.f);
  Seen s;
  s.hit = make_float4(-1.f, -1.f, -1.f, 0.f);
  s.point = s.matrix = s.intersect = make_float4(0.f);
  rtTrace(top_object, make_Ray(origin, make_float3(0.f, 0.f, 1.f), 0, 0.f, RT_DEFAULT_MAX), s);
  Seen count;
  count.hit = make_float4(0.f);
  count.point = count.matrix = count.intersect = make_float4(0.f);
  rtTrace(top_object, make_Ray(origin, make_float3(0.f, 0.f, 1.f), 1, 0.f, RT_DEFAULT_MAX), count);
  s.hit.w = count.hit.w;
  out_hit[launch_index] = s.hit;
  out_point[launch_index] = s.point;
  out_matrix[launch_index] = s.matrix;
  out_intersect[launch_index] = s.intersect;
}

RT_PROGRAM void miss() {}

RT_PROGRAM void closest_hit() {
  const float3 p = rtTransformPoint(RT_OBJECT_TO_WORLD, make_float3(0.f));
  float m[16], inv[16];
  rtGetTransform(RT_OBJECT_TO_WORLD, m);
  rtGetTransform(RT_WORLD_TO_OBJECT, inv);
  seen.hit = make_float4(t_hit, tag, primitive, 0.f);
  seen.point = make_float4(p, m[0]);
  seen.matrix = make_float4(m[3], m[7], m[11], inv[11]);
  seen.intersect =
      make_float4(is_point, rtTransformNormal(RT_OBJECT_TO_WORLD, make_float3(0.f, 0.f, 1.f)).z);
}

// Counts every candidate and keeps none: the count does not depend on traversal order.
RT_PROGRAM void count_any_hit() {
  seen.hit.w += 1.f;
  rtIgnoreIntersection();
}

RT_PROGRAM void sphere_intersect(int prim) {
  const float3 o = ray.origin - make_float3(sphere);
  const float b = dot(o, ray.direction), c = dot(o, o) - sphere.w * sphere.w;
  const float a = dot(ray.direction, ray.direction);
  const float disc = b * b - a * c;
  if (disc < 0.f) return;
  const float root = sqrtf(disc);
  for (float t : {(-b - root) / a, (-b + root) / a}) {
    if (rtPotentialIntersection(t)) {
      is_point = rtTransformPoint(RT_OBJECT_TO_WORLD, make_float3(1.f, 2.f, 3.f));
      primitive = float(prim);
      rtReportIntersection(0);
    }
  }
}

RT_PROGRAM void sphere_bounds(int, float result[6]) {
  const float r = sphere.w;
  result[0] = sphere.x - r;
  result[1] = sphere.y - r;
  result[2] = sphere.z - r;
  result[3] = sphere.x + r;
  result[4] = sphere.y + r;
  result[5] = sphere.z + r;
}

RT_PROGRAM void mesh_intersect(int prim) {
  const int3 v = index_buffer[prim];
  const float3 p0 = vertex_buffer[v.x], p1 = vertex_buffer[v.y], p2 = vertex_buffer[v.z];
  float3 n;
  float t, beta, gamma;
  if (intersect_triangle(ray, p0, p1, p2, n, t, beta, gamma) && rtPotentialIntersection(t)) {
    is_point = rtTransformPoint(RT_OBJECT_TO_WORLD, make_float3(1.f, 2.f, 3.f));
    primitive = float(prim);
    rtReportIntersection(0);
  }
}

// mesh_intersect with the half x < 0 (object space) cut out: Embree's triangles find hits there
// that the program rejects, and the ray is traced again with every candidate put to it.
RT_PROGRAM void cutout_intersect(int prim) {
  const int3 v = index_buffer[prim];
  const float3 p0 = vertex_buffer[v.x], p1 = vertex_buffer[v.y], p2 = vertex_buffer[v.z];
  float3 n;
  float t, beta, gamma;
  if (!intersect_triangle(ray, p0, p1, p2, n, t, beta, gamma)) return;
  if (ray.origin.x + t * ray.direction.x < 0.f) return;
  if (rtPotentialIntersection(t)) {
    is_point = rtTransformPoint(RT_OBJECT_TO_WORLD, make_float3(1.f, 2.f, 3.f));
    primitive = float(prim);
    rtReportIntersection(0);
  }
}

RT_PROGRAM void mesh_bounds(int prim, float result[6]) {
  const int3 v = index_buffer[prim];
  const float3 p0 = vertex_buffer[v.x], p1 = vertex_buffer[v.y], p2 = vertex_buffer[v.z];
  const float3 lo = fminf(fminf(p0, p1), p2), hi = fmaxf(fmaxf(p0, p1), p2);
  result[0] = lo.x;
  result[1] = lo.y;
  result[2] = lo.z;
  result[3] = hi.x;
  result[4] = hi.y;
  result[5] = hi.z;
}

RT_PROGRAM void visit_first() { rtIntersectChild(0); }

// Programs of triangles_test.cc and triangles_probe_test.cc: built-in triangles (OptiX 6
// GeometryTriangles) seen by orthographic rays along -z, one per launch index; misused, and
// combined with transforms, nested traces and any-hit programs.
#include <optix.h>
#include <optixu/optixu_math_namespace.h>

using namespace optix;

rtDeclareVariable(uint2, launch_index, rtLaunchIndex, );
rtDeclareVariable(uint2, launch_dim, rtLaunchDim, );
rtDeclareVariable(rtObject, top_object, , );
rtDeclareVariable(float4, result, rtPayload, );
rtDeclareVariable(optix::Ray, ray, rtCurrentRay, );
rtDeclareVariable(float, hit_t, rtIntersectionDistance, );
rtDeclareVariable(float2, barycentrics, attribute rtTriangleBarycentrics, );
rtDeclareVariable(float4, tri_info, attribute tri_info, );
rtDeclareVariable(float, material_tag, , );
rtBuffer<float4, 2> output;
rtBuffer<unsigned char, 1> material_of;

// Rays start off the grid's lines, so none meets the diagonal the two triangles share.
RT_PROGRAM void ortho() {
  float2 p = (make_float2(launch_index) + 0.3f) / make_float2(launch_dim);
  Ray r = make_Ray(make_float3(p.x, p.y, 1.f), make_float3(0.f, 0.f, -1.f), 0, 0.f, RT_DEFAULT_MAX);
  float4 value = make_float4(-1.f, -1.f, -1.f, -1.f);
  rtTrace(top_object, r, value);
  output[launch_index] = value;
}

RT_PROGRAM void miss() { result = make_float4(-1.f, -1.f, -1.f, -1.f); }

// (primitive, face code: 1 front, 2 back, barycentrics) from the built-in attribute.
RT_PROGRAM void closest_barycentrics() {
  float face = rtIsTriangleHit() ? (rtIsTriangleHitFrontFace() ? 1.f : 2.f) : 0.f;
  if (rtIsTriangleHitFrontFace() == rtIsTriangleHitBackFace()) face = -2.f;
  result =
      make_float4(static_cast<float>(rtGetPrimitiveIndex()), face, barycentrics.x, barycentrics.y);
}

// What the attribute program computed, plus the material's tag and the distance.
RT_PROGRAM void closest_info() {
  result = make_float4(tri_info.x, tri_info.y + material_tag, tri_info.z, hit_t);
}

RT_PROGRAM void attributes() {
  float2 b = rtGetTriangleBarycentrics();
  tri_info = make_float4(static_cast<float>(rtGetPrimitiveIndex()),
                         rtIsTriangleHitFrontFace() ? 1.f : 2.f, b.x + b.y, 0.f);
}

// Ignores the hits on triangle 0 (so rays there miss) and counts the others.
RT_PROGRAM void any_hit_skip_first() {
  if (rtGetPrimitiveIndex() == 0) rtIgnoreIntersection();
}

// rtGetTriangleBarycentrics belongs to attribute programs only.
RT_PROGRAM void closest_wrong_call() {
  float2 b = rtGetTriangleBarycentrics();
  result = make_float4(b.x, b.y, 0.f, 0.f);
}

// (primitive, face code, material tag, distance).
RT_PROGRAM void closest_tag() {
  float face = rtIsTriangleHit() ? (rtIsTriangleHitFrontFace() ? 1.f : 2.f) : 0.f;
  result = make_float4(static_cast<float>(rtGetPrimitiveIndex()), face, material_tag, hit_t);
}

// Traces again from the hit, straight on down; then reports its own hit again: the nested trace
// must not change this hit's primitive, face, barycentrics.
RT_PROGRAM void closest_nested() {
  float2 b = barycentrics;
  unsigned prim = rtGetPrimitiveIndex();
  float face = rtIsTriangleHitFrontFace() ? 1.f : 2.f;
  float4 inner = make_float4(-1.f, -1.f, -1.f, -1.f);
  if (ray.origin.z > 0.9f) {
    float3 p = ray.origin + hit_t * ray.direction;
    Ray r = make_Ray(p, ray.direction, 0, 1e-3f, RT_DEFAULT_MAX);
    rtTrace(top_object, r, inner);
  }
  float again = rtIsTriangleHitFrontFace() ? 1.f : 2.f;
  if (again != face || rtGetPrimitiveIndex() != prim || barycentrics.x != b.x ||
      barycentrics.y != b.y) {
    result = make_float4(-100.f, -100.f, -100.f, -100.f);
    return;
  }
  result = make_float4(static_cast<float>(prim) * 10.f + (inner.x + 1.f), face, b.x, b.y);
}

RT_PROGRAM void any_hit_terminate() { rtTerminateRay(); }
RT_PROGRAM void any_hit_ignore_all() { rtIgnoreIntersection(); }

// Attribute programs that break the rules.
RT_PROGRAM void attribute_traces() {
  float4 v = make_float4(0.f, 0.f, 0.f, 0.f);
  Ray r = make_Ray(make_float3(0.f, 0.f, 5.f), make_float3(0.f, 0.f, -1.f), 0, 0.f, RT_DEFAULT_MAX);
  rtTrace(top_object, r, v);
  tri_info = v;
}
RT_PROGRAM void attribute_potential() {
  if (rtPotentialIntersection(1.f)) rtReportIntersection(0);
}
RT_PROGRAM void attribute_ignores() { rtIgnoreIntersection(); }
RT_PROGRAM void attribute_terminates() { rtTerminateRay(); }
RT_PROGRAM void attribute_like_bounds(int primitive, float result_box[6]) {
  for (int i = 0; i < 6; ++i) result_box[i] = static_cast<float>(primitive);
}
RT_PROGRAM void attribute_info() {
  float2 b = rtGetTriangleBarycentrics();
  tri_info = make_float4(static_cast<float>(rtGetPrimitiveIndex()), b.x, b.y, 7.f);
}
RT_PROGRAM void closest_info_raw() { result = tri_info; }

// Writes tri_info on triangle 0 only: elsewhere the closest-hit program reads zeros, whatever the
// thread's previous launch index left in the module.
RT_PROGRAM void attribute_first_only() {
  if (rtGetPrimitiveIndex() == 0) tri_info = make_float4(1.f, 2.f, 3.f, 4.f);
}

// The attributes before and after a nested trace whose hit runs this module's attribute program
// again: (primitive, tag, the inner hit's primitive, the inner hit's own inner result), or -100s
// when the nested trace changed this hit's attributes.
RT_PROGRAM void closest_info_nested() {
  const float4 before = tri_info;
  float4 inner = make_float4(-1.f, -1.f, -1.f, -1.f);
  if (ray.origin.z > 0.9f) {
    float3 p = ray.origin + hit_t * ray.direction;
    Ray r = make_Ray(p, ray.direction, 0, 1e-3f, RT_DEFAULT_MAX);
    rtTrace(top_object, r, inner);
  }
  if (tri_info.x != before.x || tri_info.y != before.y || tri_info.z != before.z ||
      tri_info.w != before.w) {
    result = make_float4(-100.f, -100.f, -100.f, -100.f);
    return;
  }
  result = make_float4(before.x, before.w, inner.x, inner.z);
}

// Hit queries where there is no hit.
RT_PROGRAM void raygen_primitive_index() {
  output[launch_index] = make_float4(static_cast<float>(rtGetPrimitiveIndex()), 0.f, 0.f, 0.f);
}
RT_PROGRAM void miss_triangle_hit() { result = make_float4(rtIsTriangleHit() ? 1.f : 0.f); }

// Writes material index 5 for every triangle (entry point of its own).
RT_PROGRAM void write_material_indices() {
  if (launch_index.x < material_of.size()) material_of[launch_index.x] = 5;
}

// Reads a variable of the GeometryTriangles' scope.
rtDeclareVariable(float, mesh_tag, , );
RT_PROGRAM void attribute_mesh_tag() { tri_info = make_float4(mesh_tag, 0.f, 0.f, 0.f); }

// Moves the unit square's four vertices by `shift` along x: a mesh animated by a launch.
rtBuffer<float3, 1> animated;
rtDeclareVariable(unsigned int, vertex_index, rtLaunchIndex, );
rtDeclareVariable(float, shift, , );
RT_PROGRAM void animate_vertices() {
  const float3 square[4] = {make_float3(0.f, 0.f, 0.f), make_float3(1.f, 0.f, 0.f),
                            make_float3(0.f, 1.f, 0.f), make_float3(1.f, 1.f, 0.f)};
  animated[vertex_index] = square[vertex_index] + make_float3(shift, 0.f, 0.f);
}

// A shadow ray from the hit along (0, 0, shadow_dz), of ray type shadow_type with ray flags
// shadow_flags, asking only whether anything is there: (1 blocked or 0 open, this hit's
// primitive, read again after the trace).
rtDeclareVariable(float, shadow_dz, , );
rtDeclareVariable(unsigned int, shadow_type, , );
rtDeclareVariable(unsigned int, shadow_flags, , );
RT_PROGRAM void closest_shadow() {
  const unsigned prim = rtGetPrimitiveIndex();
  const float3 p = ray.origin + hit_t * ray.direction;
  const Ray r = make_Ray(p, make_float3(0.f, 0.f, shadow_dz), shadow_type, 1e-3f, RT_DEFAULT_MAX);
  float4 probe = make_float4(5.f, 5.f, 5.f, 5.f);  // the miss program overwrites it
  rtTrace(top_object, r, probe, RT_VISIBILITY_ALL, static_cast<RTrayflags>(shadow_flags));
  const bool same = rtGetPrimitiveIndex() == prim;
  result = make_float4(probe.x == 5.f ? 1.f : 0.f, same ? static_cast<float>(prim) : -100.f, 0.f,
                       0.f);
}

// Programs of triangles_test.cc: built-in triangles (OptiX 6 GeometryTriangles) seen by
// orthographic rays along -z, one per launch index.
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

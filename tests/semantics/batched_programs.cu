// Programs of batched_test.cc: orthographic rays along -z at two built-in triangles, whose ray
// generation programs do things before their first rtTrace that a batched launch must not do
// twice (docs/programs.md, "Batched tracing").
#include <optix.h>
#include <optixu/optixu_math_namespace.h>

using namespace optix;

rtDeclareVariable(uint2, launch_index, rtLaunchIndex, );
rtDeclareVariable(uint2, launch_dim, rtLaunchDim, );
rtDeclareVariable(rtObject, top_object, , );
rtDeclareVariable(float4, result, rtPayload, );
rtDeclareVariable(float, hit_t, rtIntersectionDistance, );
rtDeclareVariable(float2, barycentrics, attribute rtTriangleBarycentrics, );
rtDeclareVariable(optix::Ray, ray, rtCurrentRay, );
rtBuffer<float4, 2> output;
rtBuffer<unsigned, 2> counts;
typedef rtBufferId<unsigned, 2> UnsignedImage;
rtDeclareVariable(UnsignedImage, counts_by_id, , );

namespace {
// A ray at a point of the unit square that is on neither triangle's edge.
Ray GridRay() {
  const float2 p = (make_float2(launch_index) + 0.3f) / make_float2(launch_dim);
  return make_Ray(make_float3(p.x, p.y, 1.f), make_float3(0.f, 0.f, -1.f), 0, 0.f, RT_DEFAULT_MAX);
}
float4 Traced() {
  float4 value = make_float4(-1.f, -1.f, -1.f, -1.f);
  rtTrace(top_object, GridRay(), value);
  return value;
}
}  // namespace

RT_PROGRAM void plain() { output[launch_index] = Traced(); }

// Counts each launch index's runs before it traces: one per launch, batched or not.
RT_PROGRAM void count_then_trace() {
  counts[launch_index] += 1u;
  output[launch_index] = Traced();
}

// The same through a buffer id, which programs read from a table without a call.
RT_PROGRAM void count_by_id_then_trace() {
  counts_by_id[launch_index] += 1u;
  output[launch_index] = Traced();
}

RT_PROGRAM void print_then_trace() {
  rtPrintf("index %u %u\n", launch_index.x, launch_index.y);
  output[launch_index] = Traced();
}

// Column 2 raises a user exception before it traces; the exception program marks it.
RT_PROGRAM void throw_then_trace() {
  if (launch_index.x == 2) rtThrow(RT_EXCEPTION_USER);
  output[launch_index] = Traced();
}

RT_PROGRAM void mark_exception() {
  output[launch_index] = make_float4(-7.f, static_cast<float>(rtGetExceptionCode()), 0.f, 0.f);
}

// Two traces: only the first can come from a packet; the second sees the first's result.
RT_PROGRAM void trace_twice() {
  const float4 first = Traced();
  const float4 second = Traced();
  output[launch_index] = make_float4(first.x, first.w, second.x, second.w);
}

RT_PROGRAM void miss() { result = make_float4(-1.f, -1.f, -1.f, -1.f); }

// (primitive, face code, barycentrics' sum, distance).
RT_PROGRAM void closest() {
  const float face = rtIsTriangleHitFrontFace() ? 1.f : 2.f;
  result = make_float4(static_cast<float>(rtGetPrimitiveIndex()), face,
                       barycentrics.x + barycentrics.y, hit_t);
}

// Traces on from the hit with a nested ray, which batches never take.
RT_PROGRAM void closest_nested() {
  float4 inner = make_float4(-1.f, -1.f, -1.f, -1.f);
  if (ray.origin.z > 0.9f) {
    const float3 p = ray.origin + hit_t * ray.direction;
    rtTrace(top_object, make_Ray(p, ray.direction, 0, 1e-3f, RT_DEFAULT_MAX), inner);
  }
  result = make_float4(static_cast<float>(rtGetPrimitiveIndex()), inner.x, barycentrics.x, hit_t);
}

// Programs for the semantics tests: each records what it sees into buffers indexed by launch
// index, so a test can check the OptiX guide's Tables 4, 5 and 6 row by row.
#include <optix_world.h>

using namespace optix;

struct Payload {
  float4 value;
  int hits;
};

rtDeclareVariable(uint2, launch_index, rtLaunchIndex, );
rtDeclareVariable(uint2, launch_dim, rtLaunchDim, );
rtDeclareVariable(optix::Ray, ray, rtCurrentRay, );
rtDeclareVariable(Payload, payload, rtPayload, );
rtDeclareVariable(float, t_hit, rtIntersectionDistance, );
rtDeclareVariable(float3, hit_origin, attribute hit_origin, );
rtDeclareVariable(float, hit_id, attribute hit_id, );
rtDeclareVariable(rtObject, top_object, , );
rtDeclareVariable(float, value, , ) = -1.f;
rtDeclareVariable(float4, sphere, , );
rtDeclareVariable(float3, ray_origin, , );
rtDeclareVariable(float3, ray_dir, , );
rtDeclareVariable(float2, pair, , );  // 8 bytes, like an rtObject: binding tests

// Per launch index: [0] result, [1] what the intersection program saw, [2] any hit, [3] misc.
rtBuffer<float4, 2> result;
rtBuffer<float4, 2> is_log;
rtBuffer<float4, 2> ah_log;

RT_PROGRAM void trace_camera() {
  Payload p;
  p.value = make_float4(0.f);
  p.hits = 0;
  float3 o = ray_origin + make_float3(float(launch_index.x), float(launch_index.y), 0.f);
  Ray r = make_Ray(o, ray_dir, 0, 0.01f, RT_DEFAULT_MAX);
  rtTrace(top_object, r, p);
  result[launch_index] = p.value;
}

// Ray generation that reads the variable `value` through its scopes (Program, Context).
RT_PROGRAM void raygen_value() { result[launch_index] = make_float4(value, 0.f, 0.f, 0.f); }
RT_PROGRAM void raygen_launch_semantics() {
  result[launch_index] = make_float4(float(launch_index.x), float(launch_index.y),
                                     float(launch_dim.x), float(launch_dim.y));
}

RT_PROGRAM void miss_value() { payload.value = make_float4(value, 1.f, 0.f, 0.f); }
RT_PROGRAM void miss_ray() { payload.value = make_float4(ray.origin, ray.tmax); }

RT_PROGRAM void closest_hit_value() { payload.value = make_float4(value, 2.f, 0.f, 0.f); }
RT_PROGRAM void closest_hit_ray() { payload.value = make_float4(ray.origin, t_hit); }
RT_PROGRAM void closest_hit_attributes() { payload.value = make_float4(hit_origin, hit_id); }
// rtTransform* with no transform above the geometry: values come back as they are, -0 and
// infinities included (an identity matrix would make +0 and NaN of them).
RT_PROGRAM void closest_hit_transform_specials() {
  const float inf = __builtin_inff();
  const float3 n = rtTransformNormal(RT_OBJECT_TO_WORLD, make_float3(-0.f, inf, -2.5f));
  const float3 p = rtTransformPoint(RT_WORLD_TO_OBJECT, make_float3(1.f, -0.f, -inf));
  payload.value = make_float4(n.x, n.y, p.y, p.z);
}
RT_PROGRAM void closest_hit_count() {
  payload.value = make_float4(float(payload.hits), t_hit, hit_id, 0.f);
}

// Any-hit programs.
RT_PROGRAM void any_hit_ray() { ah_log[launch_index] = make_float4(ray.origin, t_hit); }
RT_PROGRAM void any_hit_count() { payload.hits += 1; }
RT_PROGRAM void any_hit_ignore() {
  payload.hits += 1;
  rtIgnoreIntersection();
}
RT_PROGRAM void any_hit_terminate() {
  payload.hits += 1;
  rtTerminateRay();
}
// Ignores hits on the primitive whose hit_id attribute is 0.
RT_PROGRAM void any_hit_ignore_first() {
  if (hit_id == 0.f) rtIgnoreIntersection();
}
// Code after rtIgnoreIntersection or rtTerminateRay never runs: both end the program, as in OptiX.
static void IgnoreHere() { rtIgnoreIntersection(); }
RT_PROGRAM void any_hit_ignore_first_then_count() {
  if (hit_id == 0.f) {
    IgnoreHere();
    payload.hits += 100;
  }
  payload.hits += 1;
}
RT_PROGRAM void any_hit_terminate_then_count() {
  payload.hits += 1;
  rtTerminateRay();
  payload.hits += 100;
}

// A sphere (center sphere.xyz, radius sphere.w) reporting its entry point in object space.
RT_PROGRAM void sphere_bounds(int, float result_box[6]) {
  result_box[0] = sphere.x - sphere.w;
  result_box[1] = sphere.y - sphere.w;
  result_box[2] = sphere.z - sphere.w;
  result_box[3] = sphere.x + sphere.w;
  result_box[4] = sphere.y + sphere.w;
  result_box[5] = sphere.z + sphere.w;
}

RT_PROGRAM void sphere_intersect(int prim) {
  float3 c = make_float3(sphere);
  float3 o = ray.origin - c;
  float a = dot(ray.direction, ray.direction);
  float b = dot(o, ray.direction);
  float disc = b * b - a * (dot(o, o) - sphere.w * sphere.w);
  is_log[launch_index] = make_float4(ray.origin, value);
  if (disc <= 0.f) return;
  float t = (-b - sqrtf(disc)) / a;
  if (rtPotentialIntersection(t)) {
    hit_origin = ray.origin;
    hit_id = float(prim);
    rtReportIntersection(0);
  }
}

// Two stacked slabs (primitives 0 and 1) perpendicular to z at z = 1 and z = 2, for any-hit tests.
RT_PROGRAM void slabs_bounds(int prim, float result_box[6]) {
  float z = 1.f + float(prim);
  result_box[0] = -1000.f;
  result_box[1] = -1000.f;
  result_box[2] = z - 0.01f;
  result_box[3] = 1000.f;
  result_box[4] = 1000.f;
  result_box[5] = z + 0.01f;
}

RT_PROGRAM void slabs_intersect(int prim) {
  float z = 1.f + float(prim);
  if (ray.direction.z == 0.f) return;
  float t = (z - ray.origin.z) / ray.direction.z;
  if (rtPotentialIntersection(t)) {
    hit_origin = ray.origin;
    hit_id = float(prim);
    rtReportIntersection(0);
  }
}

// The loosest conservative box there is, as programs write for "infinite" geometry.
RT_PROGRAM void unbounded_bounds(int, float result_box[6]) {
  result_box[0] = result_box[1] = result_box[2] = -3.402823466e38f;
  result_box[3] = result_box[4] = result_box[5] = 3.402823466e38f;
}

// A triangle mesh (vertex_buffer, index_buffer) in the z = 0 plane; the intersection program
// reports where the object-space origin lies in world space, through rtTransformPoint.
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
RT_PROGRAM void mesh_intersect(int prim) {
  const int3 v = index_buffer[prim];
  const float3 p0 = vertex_buffer[v.x], e1 = vertex_buffer[v.y] - p0, e2 = vertex_buffer[v.z] - p0;
  const float3 pv = cross(ray.direction, e2);
  const float det = dot(e1, pv);
  if (fabsf(det) < 1e-12f) return;
  const float3 tv = ray.origin - p0;
  const float u = dot(tv, pv) / det;
  const float3 qv = cross(tv, e1);
  const float w = dot(ray.direction, qv) / det;
  if (u < 0.f || w < 0.f || u + w > 1.f) return;
  if (rtPotentialIntersection(dot(e2, qv) / det)) {
    hit_origin = rtTransformPoint(RT_OBJECT_TO_WORLD, make_float3(0.f));
    hit_id = float(prim);
    rtReportIntersection(0);
  }
}

// rtPrintf where no launch index is running (while accelerations are built).
RT_PROGRAM void printing_sphere_bounds(int prim, float result_box[6]) {
  rtPrintf("bounds of %d\n", prim);
  sphere_bounds(prim, result_box);
}

// Counts bounding-box program runs (one per primitive per acceleration build).
rtBuffer<unsigned int, 1> bounds_calls;
RT_PROGRAM void counted_sphere_bounds(int prim, float result_box[6]) {
  atomicAdd(&bounds_calls[0], 1u);
  sphere_bounds(prim, result_box);
}
// mesh_bounds, counted likewise.
RT_PROGRAM void counted_mesh_bounds(int prim, float result_box[6]) {
  atomicAdd(&bounds_calls[0], 1u);
  mesh_bounds(prim, result_box);
}
// The same, counting in element `bounds_slot` (a geometry's variable): one counter per geometry.
rtDeclareVariable(unsigned int, bounds_slot, , );
RT_PROGRAM void slot_counted_sphere_bounds(int prim, float result_box[6]) {
  atomicAdd(&bounds_calls[bounds_slot], 1u);
  sphere_bounds(prim, result_box);
}

// ---- Exceptions ------------------------------------------------------------------------------
rtDeclareVariable(int, mode, , );

// Records the exception code and the launch index it ran at.
RT_PROGRAM void exception_record() {
  result[launch_index] =
      make_float4(float(rtGetExceptionCode()), float(launch_index.x), float(launch_index.y), 0.f);
}

// mode 0: NaN origin, 1: infinite direction, 2: tmin > tmax, 3: negative tmin.
RT_PROGRAM void raygen_invalid_ray() {
  Payload p;
  p.value = make_float4(0.f);
  p.hits = 0;
  float nan = __int_as_float(0x7fc00000);
  float inf = __int_as_float(0x7f800000);
  Ray r = make_Ray(make_float3(0.f, 0.f, -10.f), make_float3(0.f, 0.f, 1.f), 0, 0.01f, 100.f);
  if (mode == 0) r.origin.x = nan;
  if (mode == 1) r.direction.y = inf;
  if (mode == 2) r.tmin = 200.f;
  if (mode == 3) r.tmin = -1.f;
  rtTrace(top_object, r, p);
  result[launch_index] = make_float4(1.f, 0.f, 0.f, 0.f);  // reached only if not raised
}

// An exception program that raises an exception itself (an index out of bounds).
RT_PROGRAM void exception_out_of_bounds() {
  result[make_uint2(launch_index.x, launch_index.y + 100000u)] = make_float4(1.f);
}

RT_PROGRAM void raygen_throw() {
  if (launch_index.x == 1) rtThrow(RT_EXCEPTION_USER + 7);
  result[launch_index] = make_float4(1.f, 0.f, 0.f, 0.f);
}

RT_PROGRAM void raygen_out_of_bounds() {
  result[make_uint2(launch_dim.x + 5, 0)] = make_float4(9.f);
  result[launch_index] = make_float4(1.f, 0.f, 0.f, 0.f);
}

// Closest hit that traces the same ray again: recursion until the stack runs out.
RT_PROGRAM void closest_hit_recurse() {
  Payload p = payload;
  rtTrace(top_object, make_Ray(ray.origin, ray.direction, 0, ray.tmin, ray.tmax), p);
  payload.value = make_float4(1.f, 0.f, 0.f, 0.f);
}

// The same with 16 KiB of locals live across the nested trace: the native stack runs out long
// before the largest stack size's 1024 levels.
RT_PROGRAM void closest_hit_recurse_heavy() {
  volatile char locals[16384];
  for (int i = 0; i < 16384; i += 512) locals[i] = char(i);
  Payload p = payload;
  rtTrace(top_object, make_Ray(ray.origin, ray.direction, 0, ray.tmin, ray.tmax), p);
  payload.value = make_float4(1.f + float(locals[0]), 0.f, 0.f, 0.f);
}

RT_PROGRAM void print_hello() { rtPrintf("hello from %u\n", launch_index.x); }
// One print of 3002 bytes: longer than the 2 KiB the engine formats on the stack.
RT_PROGRAM void print_wide() { rtPrintf("%3000u|\n", launch_index.x); }

// Traces `iterations` rays per launch index: a launch long enough to cancel.
rtDeclareVariable(int, iterations, , );
RT_PROGRAM void raygen_slow() {
  float sum = 0.f;
  for (int i = 0; i < iterations; ++i) {
    Payload p;
    p.value = make_float4(0.f);
    p.hits = 0;
    rtTrace(top_object, make_Ray(ray_origin, ray_dir, 0, 0.01f, RT_DEFAULT_MAX), p);
    sum += p.value.w;
  }
  result[launch_index] = make_float4(sum, 0.f, 0.f, 0.f);
}

// ---- Variables in namespaces: the host names them with their namespaces (OptiX guide 4.1) ------
rtDeclareVariable(float, ns_probe, , ) = 1.f;
namespace outer {
rtDeclareVariable(float, ns_probe, , ) = 2.f;
namespace inner {
rtDeclareVariable(float, ns_probe, , ) = 3.f;
}  // namespace inner
rtBuffer<float4, 2> ns_result;
}  // namespace outer
namespace {
rtDeclareVariable(float, ns_hidden, , ) = 4.f;  // anonymous namespaces are not part of the name
}  // namespace
RT_PROGRAM void write_namespaced() {
  outer::ns_result[launch_index] =
      make_float4(ns_probe, outer::ns_probe, outer::inner::ns_probe, ns_hidden);
}

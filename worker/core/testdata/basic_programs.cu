// Programs for worker/core tests: a sphere, a camera, shading and exceptions.
#include <optix.h>
#include <optixu/optixu_math_namespace.h>
#include <unistd.h>

using namespace optix;

struct Payload {
  float3 color;
  int depth;
};

rtDeclareVariable(uint2, launch_index, rtLaunchIndex, );
rtDeclareVariable(uint2, launch_dim, rtLaunchDim, );
rtDeclareVariable(rtObject, top_object, , );
rtDeclareVariable(float, scale, , ) = 2.0f;
rtDeclareVariable(Payload, payload, rtPayload, );
rtDeclareVariable(optix::Ray, ray, rtCurrentRay, );
rtDeclareVariable(float, t_hit, rtIntersectionDistance, );
rtDeclareVariable(float3, normal, attribute normal, );
rtDeclareVariable(float4, sphere, , );
rtDeclareVariable(float3, tint, , );
rtDeclareVariable(int, max_depth, , ) = 1;
rtBuffer<float4, 2> output;

RT_PROGRAM void write_index() {
  output[launch_index] = make_float4(launch_index.x, launch_index.y, scale, 1.f);
}

RT_PROGRAM void camera() {
  float2 d = (make_float2(launch_index) + 0.5f) / make_float2(launch_dim) * 2.f - 1.f;
  Ray r = make_Ray(make_float3(d.x * 2.f, d.y * 2.f, -5.f), make_float3(0.f, 0.f, 1.f), 0, 0.001f,
                   RT_DEFAULT_MAX);
  Payload p;
  p.color = make_float3(0.f);
  p.depth = 0;
  rtTrace(top_object, r, p);
  output[launch_index] = make_float4(p.color, 1.f);
}

// An any-hit program that does nothing: the plan leaves it out (plan_test.cc).
RT_PROGRAM void any_hit_nothing() {}

RT_PROGRAM void miss() { payload.color = make_float3(0.f, 0.f, 1.f); }

RT_PROGRAM void closest_hit() {
  float3 n = normalize(rtTransformNormal(RT_OBJECT_TO_WORLD, normal));
  payload.color = (n * 0.5f + 0.5f) * tint;
}

// Traces again from the hit point until max_depth, to exercise nesting and the stack limit.
RT_PROGRAM void recursive_hit() {
  if (payload.depth < max_depth) {
    Payload p;
    p.color = make_float3(0.f);
    p.depth = payload.depth + 1;
    Ray r = make_Ray(ray.origin + t_hit * ray.direction, ray.direction, 0, 0.001f, RT_DEFAULT_MAX);
    rtTrace(top_object, r, p);
    payload.color = p.color + make_float3(1.f, 0.f, 0.f);
  } else {
    payload.color = make_float3(float(payload.depth), 0.f, 0.f);
  }
}

RT_PROGRAM void sphere_bounds(int, float result[6]) {
  float3 c = make_float3(sphere);
  float r = sphere.w;
  result[0] = c.x - r;
  result[1] = c.y - r;
  result[2] = c.z - r;
  result[3] = c.x + r;
  result[4] = c.y + r;
  result[5] = c.z + r;
}

// sphere_bounds, slowly: `bounds_delay_us` microseconds for every primitive, or only for the last
// one of `primitive_count` when `slow_last_only` is set.
rtDeclareVariable(unsigned, bounds_delay_us, , ) = 0;
rtDeclareVariable(int, slow_last_only, , ) = 0;
rtDeclareVariable(int, primitive_count, , ) = 0;
RT_PROGRAM void slow_sphere_bounds(int primitive, float result[6]) {
  if (!slow_last_only || primitive == primitive_count - 1) usleep(bounds_delay_us);
  sphere_bounds(primitive, result);
}

RT_PROGRAM void sphere_intersect(int) {
  float3 c = make_float3(sphere);
  float r = sphere.w;
  float3 o = ray.origin - c;
  float b = dot(o, ray.direction);
  float a = dot(ray.direction, ray.direction);
  float disc = b * b - a * (dot(o, o) - r * r);
  if (disc <= 0.f) return;
  float s = sqrtf(disc);
  float t0 = (-b - s) / a;
  float t1 = (-b + s) / a;
  if (rtPotentialIntersection(t0)) {
    normal = (o + t0 * ray.direction) / r;
    if (rtReportIntersection(0)) return;
  }
  if (rtPotentialIntersection(t1)) {
    normal = (o + t1 * ray.direction) / r;
    rtReportIntersection(0);
  }
}

RT_PROGRAM void throw_user() { rtThrow(RT_EXCEPTION_USER + 5); }
RT_PROGRAM void read_out_of_bounds() { output[make_uint2(launch_dim.x + 3, 0)] = make_float4(1.f); }
RT_PROGRAM void print_index() { rtPrintf("index %u %u\n", launch_index.x, launch_index.y); }

RT_PROGRAM void exception() {
  output[launch_index] = make_float4(float(rtGetExceptionCode()), 0.f, 0.f, -1.f);
  rtPrintExceptionDetails();
}

// Not allowed: rtTrace from an intersection program.
RT_PROGRAM void bad_intersect(int) {
  Payload p;
  rtTrace(top_object, ray, p);
}

// Scatter across pieces (write epochs): every launch index counts itself into a bin far from its
// own row; the first index to run sets a flag that the last one to run puts back.
rtBuffer<unsigned int, 1> counts;
rtBuffer<unsigned int, 1> tickets;
rtBuffer<int, 1> flags;
RT_PROGRAM void scatter_counts() {
  atomicAdd(&counts[(launch_index.x * 7u + launch_index.y * 13u) % counts.size()], 1u);
  const unsigned ticket = atomicAdd(&tickets[0], 1u);
  if (ticket == 0) flags[0] = 7;
  if (ticket + 1 == launch_dim.x * launch_dim.y) flags[0] = 0;
}

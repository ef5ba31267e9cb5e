// Programs for the end-to-end tests: a field of spheres seen through a pinhole camera, with an
// INPUT buffer large enough to travel in several chunks, an OUTPUT image and an INPUT_OUTPUT
// accumulator, so that every buffer path of a launch crosses the process boundary.
#include <optix_world.h>

#include <cstdlib>

using namespace optix;

struct Payload {
  float3 color;
};

rtDeclareVariable(uint2, launch_index, rtLaunchIndex, );
rtDeclareVariable(uint2, launch_dim, rtLaunchDim, );
rtDeclareVariable(optix::Ray, ray, rtCurrentRay, );
rtDeclareVariable(Payload, payload, rtPayload, );
rtDeclareVariable(float, t_hit, rtIntersectionDistance, );
rtDeclareVariable(float3, normal, attribute normal, );
rtDeclareVariable(rtObject, top_object, , );
rtDeclareVariable(float3, eye, , );
rtDeclareVariable(int, iterations, , ) = 1;

rtBuffer<float4, 1> spheres;  // INPUT: center, radius
rtBuffer<float4, 2> noise;    // INPUT: per-pixel host data
rtBuffer<float4, 2> image;    // OUTPUT
rtBuffer<float4, 2> accum;    // INPUT_OUTPUT: sums the images of every launch

RT_PROGRAM void render() {
  float2 d = (make_float2(launch_index) + 0.5f) / make_float2(launch_dim) * 2.f - 1.f;
  Ray r = make_Ray(eye, normalize(make_float3(d.x, d.y, 1.5f)), 0, 1e-3f, RT_DEFAULT_MAX);
  Payload p;
  p.color = make_float3(0.f);
  rtTrace(top_object, r, p);
  float4 c = make_float4(p.color, 1.f) + 0.001f * noise[launch_index];
  image[launch_index] = c;
  accum[launch_index] = accum[launch_index] + c;
}

RT_PROGRAM void miss() { payload.color = make_float3(0.1f, 0.2f, 0.3f); }

RT_PROGRAM void shade() {
  payload.color = (normalize(normal) * 0.5f + 0.5f) * (1.f / (1.f + 0.05f * t_hit));
}

RT_PROGRAM void sphere_bounds(int prim, float result[6]) {
  float4 s = spheres[prim];
  result[0] = s.x - s.w;
  result[1] = s.y - s.w;
  result[2] = s.z - s.w;
  result[3] = s.x + s.w;
  result[4] = s.y + s.w;
  result[5] = s.z + s.w;
}

RT_PROGRAM void sphere_intersect(int prim) {
  float4 s = spheres[prim];
  float3 o = ray.origin - make_float3(s);
  float b = dot(o, ray.direction);
  float a = dot(ray.direction, ray.direction);
  float disc = b * b - a * (dot(o, o) - s.w * s.w);
  if (disc <= 0.f) return;
  float root = sqrtf(disc);
  float t0 = (-b - root) / a;
  float t1 = (-b + root) / a;
  if (rtPotentialIntersection(t0)) {
    normal = (o + t0 * ray.direction) / s.w;
    if (rtReportIntersection(0)) return;
  }
  if (rtPotentialIntersection(t1)) {
    normal = (o + t1 * ray.direction) / s.w;
    rtReportIntersection(0);
  }
}

// Traces `iterations` rays per launch index: long enough to be cancelled.
RT_PROGRAM void render_slow() {
  float sum = 0.f;
  for (int i = 0; i < iterations; ++i) {
    Payload p;
    p.color = make_float3(0.f);
    rtTrace(top_object, make_Ray(eye, make_float3(0.f, 0.f, 1.f), 0, 1e-3f, RT_DEFAULT_MAX), p);
    sum += p.color.x;
  }
  image[launch_index] = make_float4(sum, 0.f, 0.f, 1.f);
}

// Writes through `bad_address` (0 unless the host sets it) at launch index (5, 5): a program
// that crashes the process running it.
rtDeclareVariable(unsigned long long, bad_address, , ) = 0;
// no_sanitize: built with UBSan (tools/sanitize.sh), the null store would end the worker with
// UBSan's report and SIGABRT; the fault tests want the SIGSEGV a program's bug causes.
RT_PROGRAM __attribute__((no_sanitize("undefined"))) void render_crash() {
  if (launch_index.x == 5 && launch_index.y == 5) {
    *reinterpret_cast<volatile int*>(bad_address) = 1;
  }
  image[launch_index] = make_float4(1.f);
}

// Ends the process running it at launch index (5, 5), as a program's own error path might.
RT_PROGRAM void render_exit() {
  if (launch_index.x == 5 && launch_index.y == 5) exit(3);
  image[launch_index] = make_float4(1.f);
}

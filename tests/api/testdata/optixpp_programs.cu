// Programs for tests/api/optixpp_test.cc: a pinhole camera over spheres under a Transform, with
// diffuse shading from a light given as user data. The scene is built twice, through OptiXpp and
// through the C API, and the two images must match bit for bit.
#include <optix.h>
#include <optixu/optixu_math_namespace.h>

using namespace optix;

struct PerRayData {
  float3 color;
  float depth;
};

// A struct the host sets with setUserData.
struct Light {
  float3 direction;
  float ambient;
};

rtDeclareVariable(uint2, launch_index, rtLaunchIndex, );
rtDeclareVariable(uint2, launch_dim, rtLaunchDim, );
rtDeclareVariable(Ray, ray, rtCurrentRay, );
rtDeclareVariable(PerRayData, prd, rtPayload, );
rtDeclareVariable(float, t_hit, rtIntersectionDistance, );
rtDeclareVariable(float3, shading_normal, attribute shading_normal, );

rtDeclareVariable(rtObject, top_object, , );
rtDeclareVariable(float3, eye, , );
rtDeclareVariable(float3, U, , );
rtDeclareVariable(float3, V, , );
rtDeclareVariable(float3, W, , );
rtDeclareVariable(float3, bg_color, , );
rtDeclareVariable(float4, sphere, , );
rtDeclareVariable(float3, Kd, , );
rtDeclareVariable(int, sample_scale, , ) = 1;
rtDeclareVariable(Light, light, , );
rtBuffer<float4, 2> output_buffer;

RT_PROGRAM void pinhole_camera() {
  const float2 d = make_float2(float(launch_index.x) / float(launch_dim.x),
                               float(launch_index.y) / float(launch_dim.y)) *
                       2.f -
                   1.f;
  const float3 direction = normalize(d.x * U + d.y * V + W);
  PerRayData p;
  p.color = make_float3(0.f);
  p.depth = 0.f;
  rtTrace(top_object, make_Ray(eye, direction, 0, 1e-3f, RT_DEFAULT_MAX), p);
  output_buffer[launch_index] = make_float4(p.color * float(sample_scale), p.depth);
}

RT_PROGRAM void miss() {
  prd.color = bg_color;
  prd.depth = -1.f;
}

RT_PROGRAM void closest_hit_diffuse() {
  const float3 n = normalize(rtTransformNormal(RT_OBJECT_TO_WORLD, shading_normal));
  const float lambert = fmaxf(dot(n, light.direction), 0.f);
  prd.color = Kd * (light.ambient + (1.f - light.ambient) * lambert);
  prd.depth = t_hit;
}

RT_PROGRAM void exception() {
  output_buffer[launch_index] = make_float4(1.f, 0.f, 1.f, float(rtGetExceptionCode()));
}

RT_PROGRAM void sphere_bounds(int, float result[6]) {
  result[0] = sphere.x - sphere.w;
  result[1] = sphere.y - sphere.w;
  result[2] = sphere.z - sphere.w;
  result[3] = sphere.x + sphere.w;
  result[4] = sphere.y + sphere.w;
  result[5] = sphere.z + sphere.w;
}

RT_PROGRAM void sphere_intersect(int) {
  const float3 center = make_float3(sphere);
  const float3 o = ray.origin - center;
  const float b = dot(o, ray.direction);
  const float c = dot(o, o) - sphere.w * sphere.w;
  const float a = dot(ray.direction, ray.direction);
  const float disc = b * b - a * c;
  if (disc <= 0.f) return;
  const float root = sqrtf(disc);
  const float t0 = (-b - root) / a;
  if (rtPotentialIntersection(t0)) {
    shading_normal = (o + t0 * ray.direction) / sphere.w;
    if (rtReportIntersection(0)) return;
  }
  const float t1 = (-b + root) / a;
  if (rtPotentialIntersection(t1)) {
    shading_normal = (o + t1 * ray.direction) / sphere.w;
    rtReportIntersection(0);
  }
}

// For selectors (set, never run: Tessera does not run visit programs yet).
RT_PROGRAM void visit() {}

// Program code in the style of OptiX 3's guide and SDK samples (sphere intersection and bounds,
// Whitted shading, pinhole camera, convex hull, the "rusty metal" shader's math), compiled as a
// program module by g++ with -Wall -Wextra -Werror. Only the math and CUDA compatibility headers
// are included: the rt* calls are not the subject here, so their results come in as arguments.
// Each extern "C" entry point lets program_module_test.cc check the numbers.
#include <float.h>
#include <internal/optix_datatypes.h>
#include <optixu/optixu_aabb_namespace.h>
#include <optixu/optixu_math_namespace.h>
#include <optixu/optixu_matrix_namespace.h>
#include <tessera/cuda_compat.h>

using namespace optix;

struct PerRayData_radiance {
  float3 result;
  float importance;
  int depth;
};

struct BasicLight {
  float3 pos;
  float3 color;
  int casts_shadow;
  int padding;
};

// Variables as rtDeclareVariable would leave them, including a braced initializer of doubles.
static float4 sphere = {0.0f, 0.0f, 0.0f, 1.0f};
static float3 rustcolor = {.437, .084, 0};
static float3 Ka = {0.2f, 0.2f, 0.2f};
static float3 Kd = {0.5f, 0.5f, 0.5f};
static float3 Ks = {0.2f, 0.2f, 0.2f};
static float3 ambient_light_color = {0.5f, 0.5f, 0.5f};
static float phong_exp = 88.0f;
static float scene_epsilon = 1.e-3f;
__constant__ float kHalf = 0.5f;

struct __align__(16) AlignedPayload {
  float value;
};

static __device__ __forceinline__ float3 schlick(float nDi, const float3& rgb) {
  const float r = powf(1.0f - nDi, 5.0f);
  return rgb * (1.0f - r) + make_float3(r);
}

static __device__ __noinline__ float turbulence(float3 PP) {
  float a = 1;
  float sum = 0;
  for (int i = 0; i < 6; i++) {
    sum += a * fabs(dot(PP, make_float3(0.1f, 0.2f, 0.3f)));
    PP *= 2;
    a *= 0.5;
  }
  return sum;
}

// The guide's sphere intersection program, reporting the nearer root instead of calling
// rtPotentialIntersection; returns -1 for a miss.
extern "C" float program_intersect_sphere(float ox, float oy, float oz, float dx, float dy,
                                          float dz) {
  const Ray ray =
      make_Ray(make_float3(ox, oy, oz), make_float3(dx, dy, dz), 0, scene_epsilon, RT_DEFAULT_MAX);
  float3 center = make_float3(sphere.x, sphere.y, sphere.z);
  float3 O = ray.origin - center;
  float3 D = ray.direction;
  float radius = sphere.w;
  float b = dot(O, D);
  float c = dot(O, O) - radius * radius;
  float disc = b * b - c;
  if (disc > 0.0f) {
    float sdisc = sqrtf(disc);
    float root1 = (-b - sdisc);
    float3 normal = (O + root1 * D) / radius;
    if (fabsf(length(normal) - 1.0f) > 1e-4f) return -2.0f;  // The hit must lie on the sphere.
    return root1;
  }
  return -1.0f;
}

// The guide's bounding box program.
extern "C" void program_bound_sphere(int, float result[6]) {
  float3 cen = make_float3(sphere);
  float3 rad = make_float3(sphere.w, sphere.w, sphere.w);
  float3 min = cen - rad;
  float3 max = cen + rad;
  Aabb* aabb = reinterpret_cast<Aabb*>(result);
  aabb->set(min, max);
}

// Whitted closest hit shading with one light, returning the color and the reflection ray.
extern "C" void program_shade(const float hit[3], const float dir[3], const float n[3],
                              float color_out[3], float reflect_out[3], float* importance) {
  Ray ray(make_float3(0.0f), make_float3(dir[0], dir[1], dir[2]), 0, scene_epsilon);
  const float3 hit_point = make_float3(hit[0], hit[1], hit[2]);
  const float3 world_geo_normal = normalize(make_float3(n[0], n[1], n[2]));
  const float3 world_shade_normal = world_geo_normal;
  const float3 ffnormal = faceforward(world_shade_normal, -ray.direction, world_geo_normal);
  float3 color = Ka * ambient_light_color;
  BasicLight lights[1] = {{make_float3(0.0f, 10.0f, 0.0f), make_float3(1.0f), 1, 0}};
  for (int i = 0; i < 1; ++i) {
    BasicLight light = lights[i];
    float3 L = normalize(light.pos - hit_point);
    float nDl = dot(ffnormal, L);
    if (nDl > 0.0f) {
      float Ldist = length(light.pos - hit_point);
      Ray shadow_ray = make_Ray(hit_point, L, 1, scene_epsilon, Ldist);
      float light_attenuation = shadow_ray.tmax > shadow_ray.tmin ? 1.0f : 0.0f;
      float3 Lc = light.color * light_attenuation;
      color += Kd * nDl * Lc;
      float3 H = normalize(L - ray.direction);
      float nDh = dot(ffnormal, H);
      if (nDh > 0) color += Ks * Lc * pow(nDh, phong_exp);
    }
  }
  float3 r = schlick(-dot(ffnormal, ray.direction), make_float3(0.1f));
  *importance = kHalf * luminance(r);
  const float3 R = reflect(ray.direction, ffnormal);
  color_out[0] = color.x;
  color_out[1] = color.y;
  color_out[2] = color.z;
  reflect_out[0] = R.x;
  reflect_out[1] = R.y;
  reflect_out[2] = R.z;
}

// Glass: refraction with OptiX's signature; returns false on total internal reflection.
extern "C" int program_refract(float ior, const float i[3], const float n[3], float out[3]) {
  float3 t;
  const bool ok =
      refract(t, normalize(make_float3(i[0], i[1], i[2])), make_float3(n[0], n[1], n[2]), ior);
  out[0] = t.x;
  out[1] = t.y;
  out[2] = t.z;
  return ok ? 1 : 0;
}

// The tutorial's pinhole camera ray direction for a pixel.
extern "C" void program_pinhole(unsigned int x, unsigned int y, unsigned int width,
                                unsigned int height, float out[3]) {
  const float3 U = make_float3(1.0f, 0.0f, 0.0f);
  const float3 V = make_float3(0.0f, 1.0f, 0.0f);
  const float3 W = make_float3(0.0f, 0.0f, -1.0f);
  uint2 screen = make_uint2(width, height);
  uint2 index = make_uint2(x, y);
  float2 d = make_float2(index) / make_float2(screen) * 2.f - 1.f;
  float3 ray_direction = normalize(d.x * U + d.y * V + W);
  out[0] = ray_direction.x;
  out[1] = ray_direction.y;
  out[2] = ray_direction.z;
}

// The tutorial's environment map lookup coordinates.
extern "C" void program_env_uv(float dx, float dy, float dz, float out[2]) {
  float theta = atan2f(dx, dz);
  theta = (theta + M_PIf) * (0.5f * M_1_PIf);
  float phi = dy * 0.5f + 0.5f;
  out[0] = theta;
  out[1] = phi;
}

// The tutorial's convex hull intersection over a unit cube's six planes; returns t0 or -1.
extern "C" float program_chull(float ox, float oy, float oz, float dx, float dy, float dz) {
  const float4 planes[6] = {{1, 0, 0, -1},  {-1, 0, 0, -1}, {0, 1, 0, -1},
                            {0, -1, 0, -1}, {0, 0, 1, -1},  {0, 0, -1, -1}};
  const Ray ray(make_float3(ox, oy, oz), make_float3(dx, dy, dz), 0, 0.0f);
  float t0 = -FLT_MAX;
  float t1 = FLT_MAX;
  float3 t0_normal = make_float3(0);
  for (int i = 0; i < 6; ++i) {
    float4 plane = planes[i];
    float3 n = make_float3(plane);
    float d = plane.w;
    float denom = dot(n, ray.direction);
    float t = -(d + dot(n, ray.origin)) / denom;
    if (denom < 0) {
      if (t > t0) {
        t0 = t;
        t0_normal = n;
      }
    } else if (t < t1) {
      t1 = t;
    }
  }
  if (t0 > t1 || t0_normal.z == 0.0f) return -1.0f;
  return t0;
}

// The rusty metal shader's scalar math, and a procedural tile coordinate.
extern "C" float program_rust(float x, float y, float z) {
  float3 PP = 0.02f * make_float3(x, y, z);
  float sum = turbulence(PP);
  float rustiness = clamp(sum, 0.0f, 1.0f);
  rustiness *= clamp(fabs(sum), 0.0f, .08f) / 0.08f;
  float nrDl = max(rustiness * -1.0f, 0.0f);
  float v0 = dot(make_float3(1.0f, 0.0f, 0.0f), make_float3(x, y, z));
  v0 = v0 - floor(v0);
  float3 color = lerp(rustcolor, make_float3(0.7f), rustiness);
  return v0 + nrDl + 0.0f * color.x;
}

// A transform as rtGetTransform would hand it out, applied to a point.
extern "C" void program_transform(float out[4]) {
  Matrix4x4 m = Matrix4x4::translate(make_float3(1.0f, 2.0f, 3.0f)) *
                Matrix4x4::rotate(M_PI_2f, make_float3(0.0f, 0.0f, 1.0f));
  float4 p = m * make_float4(1.0f, 0.0f, 0.0f, 1.0f);
  out[0] = p.x;
  out[1] = p.y;
  out[2] = p.z;
  out[3] = p.w;
}

// Intrinsics and atomics as a program would use them to count and tag work.
static unsigned int g_counter = 0;
extern "C" unsigned int program_count(unsigned int n) {
  for (unsigned int i = 0; i < n; ++i) atomicAdd(&g_counter, 1u);
  return g_counter;
}
extern "C" int program_bits(float x) { return __float_as_int(x) ^ __popc(__float_as_uint(x)); }
extern "C" float program_fast_math(float x) {
  float s, c;
  __sincosf(x, &s, &c);
  return __expf(x) + __logf(x) + __powf(x, 2.0f) + s * s + c * c + __saturatef(x) + rsqrtf(x) +
         __fdividef(x, 2.0f);
}
extern "C" int program_payload_alignment() { return static_cast<int>(alignof(AlignedPayload)); }

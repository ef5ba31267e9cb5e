// tessera-bench-tradeoff's path tracer for the interior scene: diffuse bounces, emission per
// triangle, a fixed random sequence per pixel and sample. Secondary rays start at the hit point
// with tmin scene_epsilon, as OptiX 3 applications write them; TESSERA_ACCURACY_OFFSET_RAYS moves
// them past the hit's error bound instead.
#include <optix.h>
#include <optixu/optixu_math_namespace.h>

using namespace optix;

rtDeclareVariable(rtObject, top_object, , );
rtDeclareVariable(float, scene_epsilon, , );
rtDeclareVariable(optix::Ray, ray, rtCurrentRay, );
rtDeclareVariable(float, t_hit, rtIntersectionDistance, );

rtBuffer<float3> vertex_buffer;
rtBuffer<uint3> index_buffer;
rtBuffer<float3> albedo;    // per triangle (interior scene)
rtBuffer<float3> emission;  // per triangle (interior scene)

// ---- Path tracer (interior) -------------------------------------------------------------------
rtBuffer<float4, 2> image;
rtBuffer<unsigned int, 2> ray_counts;
rtDeclareVariable(uint2, pixel, rtLaunchIndex, );
rtDeclareVariable(uint2, image_size, rtLaunchDim, );
rtDeclareVariable(unsigned int, samples, , );
rtDeclareVariable(unsigned int, max_depth, , );
rtDeclareVariable(float3, eye, , );

struct PathPayload {
  float3 radiance;
  float3 throughput;
  float3 origin;
  float3 direction;
  unsigned int seed;
  unsigned int done;
};
rtDeclareVariable(PathPayload, path, rtPayload, );

static __device__ __inline__ unsigned int Lcg(unsigned int& s) {
  s = 1664525u * s + 1013904223u;
  return s;
}
static __device__ __inline__ float Rnd(unsigned int& s) {
  return static_cast<float>(Lcg(s) >> 8) * (1.f / 16777216.f);
}

RT_PROGRAM void render() {
  float3 sum = make_float3(0.f);
  unsigned int traced = 0;
  for (unsigned int s = 0; s < samples; ++s) {
    PathPayload p;
    p.seed = (pixel.y * image_size.x + pixel.x) * 9781u + s * 6271u + 1u;
    const float u = (pixel.x + Rnd(p.seed)) / image_size.x * 2.f - 1.f;
    const float v = (pixel.y + Rnd(p.seed)) / image_size.y * 2.f - 1.f;
    p.radiance = make_float3(0.f);
    p.throughput = make_float3(1.f);
    p.origin = eye;
    p.direction = normalize(make_float3(u * 0.8f, v * 0.6f, -1.f));
    p.done = 0;
    float tmin = 0.f;
    for (unsigned int depth = 0; depth < max_depth && !p.done; ++depth) {
      ++traced;
      rtTrace(top_object, make_Ray(p.origin, p.direction, 0, tmin, RT_DEFAULT_MAX), p);
      tmin = scene_epsilon;
    }
    sum += p.radiance;
  }
  image[pixel] = make_float4(sum / static_cast<float>(samples), 1.f);
  ray_counts[pixel] = traced;
}

RT_PROGRAM void path_closest_hit() {
  const unsigned int prim = rtGetPrimitiveIndex();
  const uint3 tri = index_buffer[prim];
  const float3 a = vertex_buffer[tri.x], b = vertex_buffer[tri.y], c = vertex_buffer[tri.z];
  float3 n = normalize(cross(b - a, c - a));
  if (dot(n, ray.direction) > 0.f) n = -n;
  path.radiance += path.throughput * emission[prim];
  path.throughput *= albedo[prim];
  // A cosine-weighted direction about n.
  const float r1 = Rnd(path.seed), r2 = Rnd(path.seed);
  const float phi = 6.2831853f * r1, r = sqrtf(r2);
  const float3 w = n;
  const float3 helper = fabsf(w.x) > 0.5f ? make_float3(0.f, 1.f, 0.f) : make_float3(1.f, 0.f, 0.f);
  const float3 uu = normalize(cross(helper, w));
  const float3 vv = cross(w, uu);
  path.origin = ray.origin + t_hit * ray.direction;
  path.direction = normalize(uu * (r * cosf(phi)) + vv * (r * sinf(phi)) + w * sqrtf(1.f - r2));
}

RT_PROGRAM void path_miss() { path.done = 1; }

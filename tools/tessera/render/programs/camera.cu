// Ray generation: a pinhole or orthographic camera, paths traced segment by segment, and their
// radiance added into the accumulation buffer one sample at a time.
#include "common.h"

rtDeclareVariable(uint2, launch_index, rtLaunchIndex, );
rtDeclareVariable(uint2, launch_dim, rtLaunchDim, );
rtDeclareVariable(rtObject, top_object, , );

// The camera: `eye` and, for a pinhole camera, U, V (right and up, scaled to the half extents of
// the image plane at distance 1) and W (unit, forward); for an orthographic camera U and V are
// the half extents of the view itself.
rtDeclareVariable(float3, eye, , );
rtDeclareVariable(float3, U, , );
rtDeclareVariable(float3, V, , );
rtDeclareVariable(float3, W, , );
rtDeclareVariable(int, orthographic, , );
rtDeclareVariable(float, near_distance, , );  // along W; rays start there

// This launch's samples: indices sample_begin .. sample_begin + sample_count - 1.
rtDeclareVariable(unsigned int, sample_begin, , );
rtDeclareVariable(unsigned int, sample_count, , );
rtDeclareVariable(unsigned int, seed, , );
rtDeclareVariable(unsigned int, aov_samples, , );

// Row 0 is the bottom of the image, as in OptiX; the host flips rows when it writes a file.
// accum_buffer (INPUT_OUTPUT | GPU_LOCAL): xyz the sum of the samples' radiance, w how many
// samples were added. Each device keeps its own copy and never ships it, as progressive renderers
// on multi-GPU OptiX do: a pixel stays on the same device from launch to launch (docs/devices.md,
// "Stable ownership"). output_buffer (OUTPUT) receives the sums after every launch, for the host;
// ray_count_buffer the rays this launch traced per pixel.
rtBuffer<float4, 2> accum_buffer;
rtBuffer<float4, 2> output_buffer;
rtBuffer<unsigned int, 2> ray_count_buffer;
// The `aovs` entry's outputs: albedo (rgb) and coverage; world normal (xyz) and depth along W.
rtBuffer<float4, 2> albedo_buffer;
rtBuffer<float4, 2> normal_depth_buffer;

// The camera ray through the point `jitter` (in [0, 1)^2) of this launch index's pixel.
static __device__ __inline__ optix::Ray CameraRay(const float2& jitter) {
  const float2 d = (make_float2(launch_index) + jitter) / make_float2(launch_dim) * 2.0f - 1.0f;
  float3 origin, direction;
  if (orthographic) {
    origin = eye + d.x * U + d.y * V;
    direction = W;
  } else {
    origin = eye;
    direction = normalize(d.x * U + d.y * V + W);
  }
  const float tmin = near_distance / dot(direction, W);
  return optix::make_Ray(origin, direction, kRadianceRay, tmin, RT_DEFAULT_MAX);
}

static __device__ __inline__ RadiancePayload NewPath(const Rng& rng) {
  RadiancePayload prd;
  prd.radiance = make_float3(0.0f);
  prd.throughput = make_float3(1.0f);
  prd.origin = prd.direction = make_float3(0.0f);
  prd.rng = rng;
  prd.bsdf_pdf = 0.0f;
  prd.depth = 0;
  prd.specular = 0;
  prd.done = 0;
  prd.rays = 0;
  prd.aov_only = 0;
  prd.albedo = prd.normal = make_float3(0.0f);
  prd.hit_distance = 0.0f;
  return prd;
}

RT_PROGRAM void path_trace() {
  const unsigned int pixel = launch_index.y * launch_dim.x + launch_index.x;
  float4 sum = accum_buffer[launch_index];
  unsigned int rays = 0;
  // One sample at a time, in sample order: the sum comes out the same however the samples are
  // split into launches, which is what lets a resumed render match an uninterrupted one.
  for (unsigned int s = sample_begin; s != sample_begin + sample_count; ++s) {
    Rng rng = MakeRng(pixel, s, seed);
    const float2 jitter = make_float2(Rnd(rng), Rnd(rng));
    optix::Ray ray = CameraRay(jitter);
    RadiancePayload prd = NewPath(rng);
    for (;;) {
      rtTrace(top_object, ray, prd);
      ++rays;
      if (prd.done) break;
      ray = optix::make_Ray(prd.origin, prd.direction, kRadianceRay, 0.0f, RT_DEFAULT_MAX);
    }
    // A sample that went wrong numerically counts as black rather than as a speckle.
    const float3 radiance = IsFinite(prd.radiance) ? prd.radiance : make_float3(0.0f);
    sum += make_float4(radiance, 1.0f);
    rays += prd.rays;
  }
  accum_buffer[launch_index] = sum;
  output_buffer[launch_index] = sum;
  ray_count_buffer[launch_index] = rays;
}

// First-hit albedo, normal and depth, averaged over `aov_samples` jittered rays (a stream of
// their own, so they do not depend on how many samples the beauty image has).
RT_PROGRAM void aovs() {
  const unsigned int pixel = launch_index.y * launch_dim.x + launch_index.x;
  float3 albedo = make_float3(0.0f), normal = make_float3(0.0f);
  float depth = 0.0f;
  unsigned int hits = 0;
  for (unsigned int s = 0; s != aov_samples; ++s) {
    Rng rng = MakeRng(pixel, s, ~seed);
    const float2 jitter = make_float2(Rnd(rng), Rnd(rng));
    const optix::Ray ray = CameraRay(jitter);
    RadiancePayload prd = NewPath(rng);
    prd.aov_only = 1;
    rtTrace(top_object, ray, prd);
    albedo += prd.albedo;
    normal += prd.normal;
    if (prd.hit_distance > 0.0f) {
      depth += prd.hit_distance * dot(ray.direction, W);
      ++hits;
    }
  }
  const float n = static_cast<float>(aov_samples);
  if (dot(normal, normal) > 0.0f) normal = normalize(normal);
  albedo_buffer[launch_index] = make_float4(albedo / n, static_cast<float>(hits) / n);
  // No hit: infinitely far, as OpenEXR depth channels say it.
  normal_depth_buffer[launch_index] =
      make_float4(normal, hits != 0 ? depth / static_cast<float>(hits) : INFINITY);
}

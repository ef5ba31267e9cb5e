// The path tracer's programs: paths iterated in raygen (the per-ray state travels as a pointer
// split over two payload values, as the SDK's optixPathTracer does), next-event estimation
// towards a parallelogram light with occlusion rays, materials that sample their next direction
// in direct callables, and accumulation across launches.
#include <optix.h>

#include "../common/vec_math.h"
#include "path_tracer.h"

extern "C" {
__constant__ Params params;
}

namespace {

struct PathState {
  float3 radiance;
  float3 attenuation;
  float3 origin;
  float3 direction;
  unsigned int seed;
  int count_emitted;
  int done;
};

// Tiny Encryption Algorithm: a per-pixel, per-launch seed.
__forceinline__ __device__ unsigned int Tea(unsigned int v0, unsigned int v1) {
  unsigned int s0 = 0;
  for (int n = 0; n < 4; n++) {
    s0 += 0x9e3779b9;
    v0 += ((v1 << 4) + 0xa341316c) ^ (v1 + s0) ^ ((v1 >> 5) + 0xc8013ea4);
    v1 += ((v0 << 4) + 0xad90777d) ^ (v0 + s0) ^ ((v0 >> 5) + 0x7e95761e);
  }
  return v0;
}
__forceinline__ __device__ float Rnd(unsigned int& prev) {
  prev = 1664525u * prev + 1013904223u;
  return static_cast<float>(prev & 0x00FFFFFFu) / static_cast<float>(0x01000000u);
}

__forceinline__ __device__ PathState* State() {
  const unsigned long long p =
      (static_cast<unsigned long long>(optixGetPayload_0()) << 32) | optixGetPayload_1();
  return reinterpret_cast<PathState*>(p);
}

// An orthonormal frame around n, and a cosine-weighted direction in it.
__forceinline__ __device__ float3 CosineSample(float3 n, float u1, float u2) {
  const float r = sqrtf(u1), phi = 2.0f * 3.14159265f * u2;
  const float3 t = fabsf(n.x) > 0.5f ? normalize(cross(make_float3(0, 1, 0), n))
                                     : normalize(cross(make_float3(1, 0, 0), n));
  const float3 b = cross(n, t);
  return normalize(r * cosf(phi) * t + r * sinf(phi) * b + sqrtf(fmaxf(0.0f, 1.0f - u1)) * n);
}

}  // namespace

// Scatter functions: from the normal, the incoming direction and the state's seed, the next
// direction; they return the weight the path's attenuation is multiplied by (besides albedo).
extern "C" __device__ float3 __direct_callable__lambert(float3 n, float3 in, unsigned int* seed) {
  (void)in;
  const float u1 = Rnd(*seed), u2 = Rnd(*seed);
  return CosineSample(n, u1, u2);
}

extern "C" __device__ float3 __direct_callable__glossy(float3 n, float3 in, unsigned int* seed) {
  const float3 mirror = in - 2.0f * dot(in, n) * n;
  const float u1 = Rnd(*seed), u2 = Rnd(*seed);
  float3 d = normalize(mirror + 0.2f * CosineSample(n, u1, u2));
  if (dot(d, n) <= 0.0f) d = mirror;
  return d;
}

extern "C" __global__ void __raygen__rg() {
  const uint3 idx = optixGetLaunchIndex();
  const unsigned int pixel = idx.y * params.width + idx.x;
  unsigned int seed = Tea(pixel, params.subframe_index);
  float3 sum = make_float3(0.0f, 0.0f, 0.0f);
  for (unsigned int s = 0; s < params.samples_per_launch; ++s) {
    const float dx = 2.0f * (idx.x + Rnd(seed)) / params.width - 1.0f;
    const float dy = 2.0f * (idx.y + Rnd(seed)) / params.height - 1.0f;
    PathState state;
    state.radiance = make_float3(0.0f, 0.0f, 0.0f);
    state.attenuation = make_float3(1.0f, 1.0f, 1.0f);
    state.origin = params.eye;
    state.direction = normalize(dx * params.u + dy * params.v + params.w);
    state.seed = seed;
    state.count_emitted = 1;
    state.done = 0;
    const unsigned long long p = reinterpret_cast<unsigned long long>(&state);
    unsigned int hi = static_cast<unsigned int>(p >> 32), lo = static_cast<unsigned int>(p);
    for (unsigned int depth = 0; depth < params.max_depth && !state.done; ++depth) {
      optixTrace(params.handle, state.origin, state.direction, 0.01f, 1e16f, 0.0f,
                 OptixVisibilityMask(1), OPTIX_RAY_FLAG_NONE, kRadiance, kRayTypeCount, kRadiance,
                 hi, lo);
    }
    seed = state.seed;
    sum += state.radiance;
  }
  const float3 color = sum / static_cast<float>(params.samples_per_launch);
  float4 accum = make_float4(color.x, color.y, color.z, 1.0f);
  if (params.subframe_index > 0) {
    const float a = 1.0f / static_cast<float>(params.subframe_index + 1);
    const float4 old = params.accum[pixel];
    accum = make_float4(old.x + a * (color.x - old.x), old.y + a * (color.y - old.y),
                        old.z + a * (color.z - old.z), 1.0f);
  }
  params.accum[pixel] = accum;
  params.image[pixel] = make_color(make_float3(accum.x, accum.y, accum.z));
}

extern "C" __global__ void __miss__radiance() { State()->done = 1; }

extern "C" __global__ void __miss__occlusion() { optixSetPayload_0(1u); }  // visible

extern "C" __global__ void __closesthit__radiance() {
  const HitData* data = reinterpret_cast<const HitData*>(optixGetSbtDataPointer());
  PathState* state = State();
  const unsigned int prim = optixGetPrimitiveIndex();
  const float3 v0 = data->vertices[3 * prim], v1 = data->vertices[3 * prim + 1],
               v2 = data->vertices[3 * prim + 2];
  float3 n = normalize(cross(v1 - v0, v2 - v0));
  const float3 in = optixGetWorldRayDirection();
  if (dot(n, in) > 0.0f) n = -n;
  const float3 p = optixGetWorldRayOrigin() + optixGetRayTmax() * in;

  if (state->count_emitted) state->radiance += state->attenuation * data->emission;
  // Next event: a point on the light, seen or not.
  const Light& light = params.light;
  const float3 on_light = light.corner + Rnd(state->seed) * light.v1 + Rnd(state->seed) * light.v2;
  const float dist = length(on_light - p);
  const float3 to_light = (on_light - p) / dist;
  const float n_dot_l = dot(n, to_light), ln_dot_l = -dot(light.normal, to_light);
  if (n_dot_l > 0.0f && ln_dot_l > 0.0f) {
    unsigned int visible = 0;
    optixTrace(params.handle, p, to_light, 0.01f, dist - 0.01f, 0.0f, OptixVisibilityMask(1),
               OPTIX_RAY_FLAG_TERMINATE_ON_FIRST_HIT | OPTIX_RAY_FLAG_DISABLE_CLOSESTHIT,
               kOcclusion, kRayTypeCount, kOcclusion, visible);
    if (visible) {
      const float area = length(cross(light.v1, light.v2));
      const float weight = n_dot_l * ln_dot_l * area / (3.14159265f * dist * dist);
      state->radiance += state->attenuation * data->albedo * light.emission * weight;
    }
  }
  state->attenuation *= data->albedo;
  state->direction =
      optixDirectCall<float3, float3, float3, unsigned int*>(data->bsdf, n, in, &state->seed);
  state->origin = p;
  state->count_emitted = 0;
}

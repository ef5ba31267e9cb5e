// The eyelight benchmark's programs for OptiX 7: the same camera and shader as bench/eyelight's
// OptiX 3 programs (Embree viewer's eyelight: |dot(normalize(Ng), dir)|, converted with
// 255.01 * clamp), over built-in triangles, and the bytes benchmark's writer.
#include <optix.h>

#include "eyelight7.h"

extern "C" {
__constant__ EyelightParams params;
__constant__ WriteParams write_params;
}

namespace {

__forceinline__ __device__ float3 Sub(float3 a, float3 b) {
  return make_float3(a.x - b.x, a.y - b.y, a.z - b.z);
}
__forceinline__ __device__ float3 Cross(float3 a, float3 b) {
  return make_float3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
__forceinline__ __device__ float Dot(float3 a, float3 b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}

}  // namespace

extern "C" __global__ void __raygen__pinhole() {
  const uint3 idx = optixGetLaunchIndex();
  const float dx = (idx.x + 0.5f) / params.width * 2.f - 1.f;
  const float dy = (idx.y + 0.5f) / params.height * 2.f - 1.f;
  float3 d = make_float3(dx * params.u.x + dy * params.v.x + params.w.x,
                         dx * params.u.y + dy * params.v.y + params.w.y,
                         dx * params.u.z + dy * params.v.z + params.w.z);
  const float inv = 1.0f / sqrtf(Dot(d, d));
  d = make_float3(d.x * inv, d.y * inv, d.z * inv);
  unsigned int result = 0, hit = 0;
  optixTrace(params.handle, params.eye, d, 0.0f, 1e16f, 0.0f, OptixVisibilityMask(255),
             OPTIX_RAY_FLAG_DISABLE_ANYHIT, 0, 1, 0, result, hit);
  const float c = __uint_as_float(result);
  const unsigned char v =
      static_cast<unsigned char>(255.01f * (c < 0.f ? 0.f : (c > 1.f ? 1.f : c)));
  params.image[idx.y * params.width + idx.x] = make_uchar4(v, v, v, hit ? 255 : 0);
}

extern "C" __global__ void __miss__none() {
  optixSetPayload_0(__float_as_uint(0.0f));
  optixSetPayload_1(0);
}

extern "C" __global__ void __closesthit__eyelight() {
  const int3 t = params.indices[optixGetPrimitiveIndex()];
  const float3 p0 = params.vertices[t.x], p1 = params.vertices[t.y], p2 = params.vertices[t.z];
  const float3 n = Cross(Sub(p0, p2), Sub(p1, p0));
  const float3 d = optixGetWorldRayDirection();
  const float result = fabsf(Dot(n, d)) / sqrtf(Dot(n, n));
  optixSetPayload_0(__float_as_uint(result));
  optixSetPayload_1(1);
}

// Writes every stride-th word of write_params.words: a launch that writes a known share of a
// buffer (the bytes benchmark).
extern "C" __global__ void __raygen__write() {
  const uint3 idx = optixGetLaunchIndex();
  write_params.words[idx.x * write_params.stride] = write_params.value + idx.x;
}

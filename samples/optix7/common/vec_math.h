// float3 arithmetic for host and programs, as the OptiX SDK's sutil/vec_math.h gives it (CUDA's
// headers declare the types and make_* only).
#ifndef TESSERA_SAMPLES_OPTIX7_COMMON_VEC_MATH_H_
#define TESSERA_SAMPLES_OPTIX7_COMMON_VEC_MATH_H_

#include <math.h>
#include <vector_functions.h>
#include <vector_types.h>

#ifndef __CUDACC__
#define __host__
#define __device__
#define __forceinline__ inline
#endif

__host__ __device__ __forceinline__ float3 operator+(float3 a, float3 b) {
  return make_float3(a.x + b.x, a.y + b.y, a.z + b.z);
}
__host__ __device__ __forceinline__ float3 operator-(float3 a, float3 b) {
  return make_float3(a.x - b.x, a.y - b.y, a.z - b.z);
}
__host__ __device__ __forceinline__ float3 operator-(float3 a) {
  return make_float3(-a.x, -a.y, -a.z);
}
__host__ __device__ __forceinline__ float3 operator*(float3 a, float3 b) {
  return make_float3(a.x * b.x, a.y * b.y, a.z * b.z);
}
__host__ __device__ __forceinline__ float3 operator*(float3 a, float s) {
  return make_float3(a.x * s, a.y * s, a.z * s);
}
__host__ __device__ __forceinline__ float3 operator*(float s, float3 a) { return a * s; }
__host__ __device__ __forceinline__ float3 operator/(float3 a, float s) { return a * (1.0f / s); }
__host__ __device__ __forceinline__ float3& operator+=(float3& a, float3 b) { return a = a + b; }
__host__ __device__ __forceinline__ float3& operator*=(float3& a, float3 b) { return a = a * b; }
__host__ __device__ __forceinline__ float dot(float3 a, float3 b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
__host__ __device__ __forceinline__ float3 cross(float3 a, float3 b) {
  return make_float3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
__host__ __device__ __forceinline__ float length(float3 a) { return sqrtf(dot(a, a)); }
__host__ __device__ __forceinline__ float3 normalize(float3 a) { return a / length(a); }
__host__ __device__ __forceinline__ float clampf(float x, float lo, float hi) {
  return x < lo ? lo : (x > hi ? hi : x);
}
// 8-bit sRGB-ish (gamma 2.2 approximated by sqrt) colour from linear [0, 1].
__host__ __device__ __forceinline__ uchar4 make_color(float3 c) {
  return make_uchar4(static_cast<unsigned char>(clampf(sqrtf(c.x), 0.f, 1.f) * 255.99f),
                     static_cast<unsigned char>(clampf(sqrtf(c.y), 0.f, 1.f) * 255.99f),
                     static_cast<unsigned char>(clampf(sqrtf(c.z), 0.f, 1.f) * 255.99f), 255);
}

#endif  // TESSERA_SAMPLES_OPTIX7_COMMON_VEC_MATH_H_

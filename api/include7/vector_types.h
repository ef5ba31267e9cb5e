/* CUDA's vector types (float2, float3, float4, int2, uint3, uchar4, ... and dim3) as
 * vector_types.h of the CUDA toolkit declares them, for OptiX 7 host and program code: aggregates
 * in the global namespace, C and C++ alike, with CUDA's sizes and alignments (two- and
 * four-component types over-aligned as CUDA does, float2 to 8 and float4 to 16; three-component
 * types not: float3 is 12 bytes aligned to 4). The layouts matter: launch parameters, SBT records
 * and vertex buffers that hold these types travel between host and programs as raw bytes.
 *
 * The OptiX 3 include root (api/include) declares the same types in optixu/optixu_vector_types.h,
 * identical in layout. An application uses one root, never both, but a translation unit that
 * has read the OptiX 3 header first gets its types here instead of a redefinition (the guard
 * below); the other order, this header first and then OptiX 3's, is a redefinition error. */
#ifndef TESSERA_OPTIX7_VECTOR_TYPES_H_
#define TESSERA_OPTIX7_VECTOR_TYPES_H_

#include "tessera/optix7_cuda_defines.h"

#if !defined(OPTIXU_OPTIXU_VECTOR_TYPES_H_)

/* char1..char4: signed char components. */
struct char1 {
  signed char x;
};
typedef struct char1 char1;
struct __builtin_align__(2) char2 {
  signed char x, y;
};
typedef struct char2 char2;
struct char3 {
  signed char x, y, z;
};
typedef struct char3 char3;
struct __builtin_align__(4) char4 {
  signed char x, y, z, w;
};
typedef struct char4 char4;
/* uchar1..uchar4: unsigned char components. */
struct uchar1 {
  unsigned char x;
};
typedef struct uchar1 uchar1;
struct __builtin_align__(2) uchar2 {
  unsigned char x, y;
};
typedef struct uchar2 uchar2;
struct uchar3 {
  unsigned char x, y, z;
};
typedef struct uchar3 uchar3;
struct __builtin_align__(4) uchar4 {
  unsigned char x, y, z, w;
};
typedef struct uchar4 uchar4;
/* short1..short4: short components. */
struct short1 {
  short x;
};
typedef struct short1 short1;
struct __builtin_align__(4) short2 {
  short x, y;
};
typedef struct short2 short2;
struct short3 {
  short x, y, z;
};
typedef struct short3 short3;
struct __builtin_align__(8) short4 {
  short x, y, z, w;
};
typedef struct short4 short4;
/* ushort1..ushort4: unsigned short components. */
struct ushort1 {
  unsigned short x;
};
typedef struct ushort1 ushort1;
struct __builtin_align__(4) ushort2 {
  unsigned short x, y;
};
typedef struct ushort2 ushort2;
struct ushort3 {
  unsigned short x, y, z;
};
typedef struct ushort3 ushort3;
struct __builtin_align__(8) ushort4 {
  unsigned short x, y, z, w;
};
typedef struct ushort4 ushort4;
/* int1..int4: int components. */
struct int1 {
  int x;
};
typedef struct int1 int1;
struct __builtin_align__(8) int2 {
  int x, y;
};
typedef struct int2 int2;
struct int3 {
  int x, y, z;
};
typedef struct int3 int3;
struct __builtin_align__(16) int4 {
  int x, y, z, w;
};
typedef struct int4 int4;
/* uint1..uint4: unsigned int components. */
struct uint1 {
  unsigned int x;
};
typedef struct uint1 uint1;
struct __builtin_align__(8) uint2 {
  unsigned int x, y;
};
typedef struct uint2 uint2;
struct uint3 {
  unsigned int x, y, z;
};
typedef struct uint3 uint3;
struct __builtin_align__(16) uint4 {
  unsigned int x, y, z, w;
};
typedef struct uint4 uint4;
/* long1..long4: long int components. */
struct long1 {
  long int x;
};
typedef struct long1 long1;
struct __builtin_align__(16) long2 {
  long int x, y;
};
typedef struct long2 long2;
struct long3 {
  long int x, y, z;
};
typedef struct long3 long3;
struct __builtin_align__(16) long4 {
  long int x, y, z, w;
};
typedef struct long4 long4;
/* ulong1..ulong4: unsigned long int components. */
struct ulong1 {
  unsigned long int x;
};
typedef struct ulong1 ulong1;
struct __builtin_align__(16) ulong2 {
  unsigned long int x, y;
};
typedef struct ulong2 ulong2;
struct ulong3 {
  unsigned long int x, y, z;
};
typedef struct ulong3 ulong3;
struct __builtin_align__(16) ulong4 {
  unsigned long int x, y, z, w;
};
typedef struct ulong4 ulong4;
/* longlong1..longlong4: long long int components. */
struct longlong1 {
  long long int x;
};
typedef struct longlong1 longlong1;
struct __builtin_align__(16) longlong2 {
  long long int x, y;
};
typedef struct longlong2 longlong2;
struct longlong3 {
  long long int x, y, z;
};
typedef struct longlong3 longlong3;
struct __builtin_align__(16) longlong4 {
  long long int x, y, z, w;
};
typedef struct longlong4 longlong4;
/* ulonglong1..ulonglong4: unsigned long long int components. */
struct ulonglong1 {
  unsigned long long int x;
};
typedef struct ulonglong1 ulonglong1;
struct __builtin_align__(16) ulonglong2 {
  unsigned long long int x, y;
};
typedef struct ulonglong2 ulonglong2;
struct ulonglong3 {
  unsigned long long int x, y, z;
};
typedef struct ulonglong3 ulonglong3;
struct __builtin_align__(16) ulonglong4 {
  unsigned long long int x, y, z, w;
};
typedef struct ulonglong4 ulonglong4;
/* float1..float4: float components. */
struct float1 {
  float x;
};
typedef struct float1 float1;
struct __builtin_align__(8) float2 {
  float x, y;
};
typedef struct float2 float2;
struct float3 {
  float x, y, z;
};
typedef struct float3 float3;
struct __builtin_align__(16) float4 {
  float x, y, z, w;
};
typedef struct float4 float4;
/* double1..double4: double components. */
struct double1 {
  double x;
};
typedef struct double1 double1;
struct __builtin_align__(16) double2 {
  double x, y;
};
typedef struct double2 double2;
struct double3 {
  double x, y, z;
};
typedef struct double3 double3;
struct __builtin_align__(16) double4 {
  double x, y, z, w;
};
typedef struct double4 double4;

/* Launch and block extents. In C++ unspecified extents default to 1 and dim3 converts to and
 * from uint3, as in CUDA; in C it is a plain struct. */
struct dim3 {
  unsigned int x, y, z;
#ifdef __cplusplus
  __host__ __device__ constexpr dim3(unsigned int vx = 1, unsigned int vy = 1,  // NOLINT
                                     unsigned int vz = 1)
      : x(vx), y(vy), z(vz) {}
  __host__ __device__ constexpr dim3(uint3 v) : x(v.x), y(v.y), z(v.z) {}  // NOLINT: as CUDA
  __host__ __device__ constexpr operator uint3() const {                   // NOLINT: as CUDA
    return uint3{x, y, z};
  }
#endif
};
typedef struct dim3 dim3;

#endif /* !OPTIXU_OPTIXU_VECTOR_TYPES_H_ */

#endif /* TESSERA_OPTIX7_VECTOR_TYPES_H_ */

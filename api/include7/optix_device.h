/* The OptiX 7.7 device API for program modules: what OptiX 7 programs call (optixTrace,
 * optixGetPayload_0, optixReportIntersection, optixGetTriangleBarycentrics, ...), with OptiX
 * 7.7's names and signatures. A program module is compiled as C++ by the system compiler:
 *
 *   g++ -std=c++17 -O2 -shared -fPIC -x c++ -D__CUDACC__ -I<include7> prog.cu -o prog.so
 *
 * and optix.h includes this header when __CUDACC__ is defined, as with nvcc. Entry points keep
 * OptiX's spelling (`extern "C" __global__ void __raygen__rg()`) and the launch parameters are an
 * ordinary global (`extern "C" __constant__ Params params;`): the qualifiers are empty
 * (tessera/optix7_cuda_defines.h) and the engine finds both by symbol name.
 *
 * Every function here is an inline call through the engine's table (TesseraOptix7Runtime,
 * tessera/optix7_device_abi.h), which the engine hands the module when it loads it
 * (worker/core/optix7_engine.h; what it runs and what it does not: docs/optix7_engine.md).
 *
 * Differences from nvcc that programs can see: __CUDA_ARCH__ is undefined (GPU-only code under it
 * is not compiled), and of the CUDA device intrinsics only the bit casts that OptiX programs use
 * for payloads and attributes are here (__float_as_uint and friends). */
#ifndef TESSERA_OPTIX7_OPTIX_DEVICE_H_
#define TESSERA_OPTIX7_OPTIX_DEVICE_H_

#ifndef __cplusplus
#error "optix_device.h: OptiX 7 programs are C++ (compile the .cu file with g++ -x c++)"
#endif

/* nvcc makes the C math library (sqrtf, fminf, ...) visible in every .cu file. */
#include <math.h>
#include <string.h>

#include <type_traits>

#include "device_atomic_functions.h" /* nvcc's implicit CUDA headers give atomicAdd & co. */
#include "optix_types.h"
#include "tessera/optix7_cuda_defines.h"
#include "tessera/optix7_device_abi.h"
#include "tessera/optix7_module.h"
#include "texture_indirect_functions.h" /* nvcc's implicit CUDA headers give tex2D<T> & co. */
#include "vector_functions.h"
#include "vector_types.h"

namespace tessera_optix7 {
inline const TesseraOptix7Runtime* rt() { return tessera_optix7_runtime; }
inline float3 ToFloat3(const float v[3]) { return make_float3(v[0], v[1], v[2]); }
}  // namespace tessera_optix7

/* ---- CUDA device intrinsics OptiX programs use ----------------------------------------------- */
/* nvcc provides these to every .cu file (__float_as_uint, rsqrtf, __saturatef, __popc, min/max,
 * ...): the OptiX 3 layer's definitions, shared through api/include_common. */
#include "tessera/detail/cuda_intrinsics.h"

/* ---- Exception details ----------------------------------------------------------------------- */
typedef struct OptixInvalidRayExceptionDetails {
  float3 origin;
  float3 direction;
  float tmin;
  float tmax;
  float time;
} OptixInvalidRayExceptionDetails;

typedef struct OptixParameterMismatchExceptionDetails {
  unsigned int expectedParameterCount;
  unsigned int passedArgumentCount;
  unsigned int sbtIndex;
  char* callableName;
} OptixParameterMismatchExceptionDetails;

/* ---- Tracing --------------------------------------------------------------------------------- */
namespace tessera_optix7 {
template <typename... Payload>
inline void Trace(unsigned int type, OptixTraversableHandle handle, float3 rayOrigin,
                  float3 rayDirection, float tmin, float tmax, float rayTime,
                  OptixVisibilityMask visibilityMask, unsigned int rayFlags, unsigned int SBToffset,
                  unsigned int SBTstride, unsigned int missSBTIndex, Payload&... payload) {
  static_assert(sizeof...(Payload) <= 32, "optixTrace takes at most 32 payload values");
  static_assert((std::is_same<Payload, unsigned int>::value && ...),
                "optixTrace payload values are unsigned int variables");
  const TesseraOptix7Trace ray = {handle,
                                  {rayOrigin.x, rayOrigin.y, rayOrigin.z},
                                  {rayDirection.x, rayDirection.y, rayDirection.z},
                                  tmin,
                                  tmax,
                                  rayTime,
                                  visibilityMask,
                                  rayFlags,
                                  SBToffset,
                                  SBTstride,
                                  missSBTIndex,
                                  type};
  // The engine reads and writes the caller's variables itself: SDK programs pass payload
  // variables they never initialized (closest-hit and miss programs set them), which a copy here
  // would read.
  unsigned int* const values[sizeof...(Payload) + 1] = {&payload..., nullptr};
  rt()->trace(&ray, sizeof...(Payload), values);
}
}  // namespace tessera_optix7

/* Traces a ray; 0 to 32 payload values travel in and out by reference. */
template <typename... Payload>
static __forceinline__ __device__ void optixTrace(OptixTraversableHandle handle, float3 rayOrigin,
                                                  float3 rayDirection, float tmin, float tmax,
                                                  float rayTime, OptixVisibilityMask visibilityMask,
                                                  unsigned int rayFlags, unsigned int SBToffset,
                                                  unsigned int SBTstride, unsigned int missSBTIndex,
                                                  Payload&... payload) {
  tessera_optix7::Trace(OPTIX_PAYLOAD_TYPE_DEFAULT, handle, rayOrigin, rayDirection, tmin, tmax,
                        rayTime, visibilityMask, rayFlags, SBToffset, SBTstride, missSBTIndex,
                        payload...);
}

/* As above, for one of the module's payload types (OptixModuleCompileOptions::payloadTypes). */
template <typename... Payload>
static __forceinline__ __device__ void optixTrace(OptixPayloadTypeID type,
                                                  OptixTraversableHandle handle, float3 rayOrigin,
                                                  float3 rayDirection, float tmin, float tmax,
                                                  float rayTime, OptixVisibilityMask visibilityMask,
                                                  unsigned int rayFlags, unsigned int SBToffset,
                                                  unsigned int SBTstride, unsigned int missSBTIndex,
                                                  Payload&... payload) {
  tessera_optix7::Trace(type, handle, rayOrigin, rayDirection, tmin, tmax, rayTime, visibilityMask,
                        rayFlags, SBToffset, SBTstride, missSBTIndex, payload...);
}

/* Payload values of the ray the running program serves. */
static __forceinline__ __device__ unsigned int optixGetPayload_0() {
  return tessera_optix7::rt()->get_payload(0);
}
static __forceinline__ __device__ unsigned int optixGetPayload_1() {
  return tessera_optix7::rt()->get_payload(1);
}
static __forceinline__ __device__ unsigned int optixGetPayload_2() {
  return tessera_optix7::rt()->get_payload(2);
}
static __forceinline__ __device__ unsigned int optixGetPayload_3() {
  return tessera_optix7::rt()->get_payload(3);
}
static __forceinline__ __device__ unsigned int optixGetPayload_4() {
  return tessera_optix7::rt()->get_payload(4);
}
static __forceinline__ __device__ unsigned int optixGetPayload_5() {
  return tessera_optix7::rt()->get_payload(5);
}
static __forceinline__ __device__ unsigned int optixGetPayload_6() {
  return tessera_optix7::rt()->get_payload(6);
}
static __forceinline__ __device__ unsigned int optixGetPayload_7() {
  return tessera_optix7::rt()->get_payload(7);
}
static __forceinline__ __device__ unsigned int optixGetPayload_8() {
  return tessera_optix7::rt()->get_payload(8);
}
static __forceinline__ __device__ unsigned int optixGetPayload_9() {
  return tessera_optix7::rt()->get_payload(9);
}
static __forceinline__ __device__ unsigned int optixGetPayload_10() {
  return tessera_optix7::rt()->get_payload(10);
}
static __forceinline__ __device__ unsigned int optixGetPayload_11() {
  return tessera_optix7::rt()->get_payload(11);
}
static __forceinline__ __device__ unsigned int optixGetPayload_12() {
  return tessera_optix7::rt()->get_payload(12);
}
static __forceinline__ __device__ unsigned int optixGetPayload_13() {
  return tessera_optix7::rt()->get_payload(13);
}
static __forceinline__ __device__ unsigned int optixGetPayload_14() {
  return tessera_optix7::rt()->get_payload(14);
}
static __forceinline__ __device__ unsigned int optixGetPayload_15() {
  return tessera_optix7::rt()->get_payload(15);
}
static __forceinline__ __device__ unsigned int optixGetPayload_16() {
  return tessera_optix7::rt()->get_payload(16);
}
static __forceinline__ __device__ unsigned int optixGetPayload_17() {
  return tessera_optix7::rt()->get_payload(17);
}
static __forceinline__ __device__ unsigned int optixGetPayload_18() {
  return tessera_optix7::rt()->get_payload(18);
}
static __forceinline__ __device__ unsigned int optixGetPayload_19() {
  return tessera_optix7::rt()->get_payload(19);
}
static __forceinline__ __device__ unsigned int optixGetPayload_20() {
  return tessera_optix7::rt()->get_payload(20);
}
static __forceinline__ __device__ unsigned int optixGetPayload_21() {
  return tessera_optix7::rt()->get_payload(21);
}
static __forceinline__ __device__ unsigned int optixGetPayload_22() {
  return tessera_optix7::rt()->get_payload(22);
}
static __forceinline__ __device__ unsigned int optixGetPayload_23() {
  return tessera_optix7::rt()->get_payload(23);
}
static __forceinline__ __device__ unsigned int optixGetPayload_24() {
  return tessera_optix7::rt()->get_payload(24);
}
static __forceinline__ __device__ unsigned int optixGetPayload_25() {
  return tessera_optix7::rt()->get_payload(25);
}
static __forceinline__ __device__ unsigned int optixGetPayload_26() {
  return tessera_optix7::rt()->get_payload(26);
}
static __forceinline__ __device__ unsigned int optixGetPayload_27() {
  return tessera_optix7::rt()->get_payload(27);
}
static __forceinline__ __device__ unsigned int optixGetPayload_28() {
  return tessera_optix7::rt()->get_payload(28);
}
static __forceinline__ __device__ unsigned int optixGetPayload_29() {
  return tessera_optix7::rt()->get_payload(29);
}
static __forceinline__ __device__ unsigned int optixGetPayload_30() {
  return tessera_optix7::rt()->get_payload(30);
}
static __forceinline__ __device__ unsigned int optixGetPayload_31() {
  return tessera_optix7::rt()->get_payload(31);
}
static __forceinline__ __device__ void optixSetPayload_0(unsigned int p) {
  tessera_optix7::rt()->set_payload(0, p);
}
static __forceinline__ __device__ void optixSetPayload_1(unsigned int p) {
  tessera_optix7::rt()->set_payload(1, p);
}
static __forceinline__ __device__ void optixSetPayload_2(unsigned int p) {
  tessera_optix7::rt()->set_payload(2, p);
}
static __forceinline__ __device__ void optixSetPayload_3(unsigned int p) {
  tessera_optix7::rt()->set_payload(3, p);
}
static __forceinline__ __device__ void optixSetPayload_4(unsigned int p) {
  tessera_optix7::rt()->set_payload(4, p);
}
static __forceinline__ __device__ void optixSetPayload_5(unsigned int p) {
  tessera_optix7::rt()->set_payload(5, p);
}
static __forceinline__ __device__ void optixSetPayload_6(unsigned int p) {
  tessera_optix7::rt()->set_payload(6, p);
}
static __forceinline__ __device__ void optixSetPayload_7(unsigned int p) {
  tessera_optix7::rt()->set_payload(7, p);
}
static __forceinline__ __device__ void optixSetPayload_8(unsigned int p) {
  tessera_optix7::rt()->set_payload(8, p);
}
static __forceinline__ __device__ void optixSetPayload_9(unsigned int p) {
  tessera_optix7::rt()->set_payload(9, p);
}
static __forceinline__ __device__ void optixSetPayload_10(unsigned int p) {
  tessera_optix7::rt()->set_payload(10, p);
}
static __forceinline__ __device__ void optixSetPayload_11(unsigned int p) {
  tessera_optix7::rt()->set_payload(11, p);
}
static __forceinline__ __device__ void optixSetPayload_12(unsigned int p) {
  tessera_optix7::rt()->set_payload(12, p);
}
static __forceinline__ __device__ void optixSetPayload_13(unsigned int p) {
  tessera_optix7::rt()->set_payload(13, p);
}
static __forceinline__ __device__ void optixSetPayload_14(unsigned int p) {
  tessera_optix7::rt()->set_payload(14, p);
}
static __forceinline__ __device__ void optixSetPayload_15(unsigned int p) {
  tessera_optix7::rt()->set_payload(15, p);
}
static __forceinline__ __device__ void optixSetPayload_16(unsigned int p) {
  tessera_optix7::rt()->set_payload(16, p);
}
static __forceinline__ __device__ void optixSetPayload_17(unsigned int p) {
  tessera_optix7::rt()->set_payload(17, p);
}
static __forceinline__ __device__ void optixSetPayload_18(unsigned int p) {
  tessera_optix7::rt()->set_payload(18, p);
}
static __forceinline__ __device__ void optixSetPayload_19(unsigned int p) {
  tessera_optix7::rt()->set_payload(19, p);
}
static __forceinline__ __device__ void optixSetPayload_20(unsigned int p) {
  tessera_optix7::rt()->set_payload(20, p);
}
static __forceinline__ __device__ void optixSetPayload_21(unsigned int p) {
  tessera_optix7::rt()->set_payload(21, p);
}
static __forceinline__ __device__ void optixSetPayload_22(unsigned int p) {
  tessera_optix7::rt()->set_payload(22, p);
}
static __forceinline__ __device__ void optixSetPayload_23(unsigned int p) {
  tessera_optix7::rt()->set_payload(23, p);
}
static __forceinline__ __device__ void optixSetPayload_24(unsigned int p) {
  tessera_optix7::rt()->set_payload(24, p);
}
static __forceinline__ __device__ void optixSetPayload_25(unsigned int p) {
  tessera_optix7::rt()->set_payload(25, p);
}
static __forceinline__ __device__ void optixSetPayload_26(unsigned int p) {
  tessera_optix7::rt()->set_payload(26, p);
}
static __forceinline__ __device__ void optixSetPayload_27(unsigned int p) {
  tessera_optix7::rt()->set_payload(27, p);
}
static __forceinline__ __device__ void optixSetPayload_28(unsigned int p) {
  tessera_optix7::rt()->set_payload(28, p);
}
static __forceinline__ __device__ void optixSetPayload_29(unsigned int p) {
  tessera_optix7::rt()->set_payload(29, p);
}
static __forceinline__ __device__ void optixSetPayload_30(unsigned int p) {
  tessera_optix7::rt()->set_payload(30, p);
}
static __forceinline__ __device__ void optixSetPayload_31(unsigned int p) {
  tessera_optix7::rt()->set_payload(31, p);
}

/* The payload types (OptixPayloadTypeID bits) the running program accepts. */
static __forceinline__ __device__ void optixSetPayloadTypes(unsigned int typeMask) {
  tessera_optix7::rt()->set_payload_types(typeMask);
}

/* A value the compiler may treat as anything (for payloads a program does not set). */
static __forceinline__ __device__ unsigned int optixUndefinedValue() {
  return tessera_optix7::rt()->undefined_value();
}

/* ---- Launch ---------------------------------------------------------------------------------- */
static __forceinline__ __device__ uint3 optixGetLaunchIndex() {
  unsigned int v[3];
  tessera_optix7::rt()->launch_index(v);
  return make_uint3(v[0], v[1], v[2]);
}

static __forceinline__ __device__ uint3 optixGetLaunchDimensions() {
  unsigned int v[3];
  tessera_optix7::rt()->launch_dimensions(v);
  return make_uint3(v[0], v[1], v[2]);
}

/* The data block of the running program's SBT record (after the header). */
static __forceinline__ __device__ CUdeviceptr optixGetSbtDataPointer() {
  return tessera_optix7::rt()->sbt_data_pointer();
}

/* ---- Ray state ------------------------------------------------------------------------------- */
static __forceinline__ __device__ float3 optixGetWorldRayOrigin() {
  float v[3];
  tessera_optix7::rt()->ray_vector(TESSERA_OPTIX7_WORLD_RAY_ORIGIN, v);
  return tessera_optix7::ToFloat3(v);
}
static __forceinline__ __device__ float3 optixGetWorldRayDirection() {
  float v[3];
  tessera_optix7::rt()->ray_vector(TESSERA_OPTIX7_WORLD_RAY_DIRECTION, v);
  return tessera_optix7::ToFloat3(v);
}
static __forceinline__ __device__ float3 optixGetObjectRayOrigin() {
  float v[3];
  tessera_optix7::rt()->ray_vector(TESSERA_OPTIX7_OBJECT_RAY_ORIGIN, v);
  return tessera_optix7::ToFloat3(v);
}
static __forceinline__ __device__ float3 optixGetObjectRayDirection() {
  float v[3];
  tessera_optix7::rt()->ray_vector(TESSERA_OPTIX7_OBJECT_RAY_DIRECTION, v);
  return tessera_optix7::ToFloat3(v);
}
static __forceinline__ __device__ float optixGetRayTmin() {
  return tessera_optix7::rt()->ray_float(TESSERA_OPTIX7_RAY_TMIN);
}
static __forceinline__ __device__ float optixGetRayTmax() {
  return tessera_optix7::rt()->ray_float(TESSERA_OPTIX7_RAY_TMAX);
}
static __forceinline__ __device__ float optixGetRayTime() {
  return tessera_optix7::rt()->ray_float(TESSERA_OPTIX7_RAY_TIME);
}
static __forceinline__ __device__ unsigned int optixGetRayFlags() {
  return tessera_optix7::rt()->state_uint(TESSERA_OPTIX7_RAY_FLAGS);
}
static __forceinline__ __device__ unsigned int optixGetRayVisibilityMask() {
  return tessera_optix7::rt()->state_uint(TESSERA_OPTIX7_RAY_VISIBILITY_MASK);
}
static __forceinline__ __device__ unsigned int optixGetPrimitiveIndex() {
  return tessera_optix7::rt()->state_uint(TESSERA_OPTIX7_PRIMITIVE_INDEX);
}
static __forceinline__ __device__ unsigned int optixGetInstanceId() {
  return tessera_optix7::rt()->state_uint(TESSERA_OPTIX7_INSTANCE_ID);
}
static __forceinline__ __device__ unsigned int optixGetInstanceIndex() {
  return tessera_optix7::rt()->state_uint(TESSERA_OPTIX7_INSTANCE_INDEX);
}
static __forceinline__ __device__ unsigned int optixGetSbtGASIndex() {
  return tessera_optix7::rt()->state_uint(TESSERA_OPTIX7_SBT_GAS_INDEX);
}
static __forceinline__ __device__ unsigned int optixGetHitKind() {
  return tessera_optix7::rt()->state_uint(TESSERA_OPTIX7_HIT_KIND);
}
static __forceinline__ __device__ unsigned int optixGetTransformListSize() {
  return tessera_optix7::rt()->state_uint(TESSERA_OPTIX7_TRANSFORM_LIST_SIZE);
}

/* ---- Hit kinds and primitive types ----------------------------------------------------------- */
static __forceinline__ __device__ OptixPrimitiveType optixGetPrimitiveType(unsigned int hitKind) {
  return static_cast<OptixPrimitiveType>(
      tessera_optix7::rt()->hit_kind_query(hitKind, TESSERA_OPTIX7_HIT_KIND_PRIMITIVE_TYPE));
}
static __forceinline__ __device__ OptixPrimitiveType optixGetPrimitiveType() {
  return optixGetPrimitiveType(optixGetHitKind());
}
static __forceinline__ __device__ bool optixIsFrontFaceHit(unsigned int hitKind) {
  return tessera_optix7::rt()->hit_kind_query(hitKind, TESSERA_OPTIX7_HIT_KIND_IS_FRONT_FACE) != 0;
}
static __forceinline__ __device__ bool optixIsBackFaceHit(unsigned int hitKind) {
  return !optixIsFrontFaceHit(hitKind);
}
static __forceinline__ __device__ bool optixIsFrontFaceHit() {
  return optixIsFrontFaceHit(optixGetHitKind());
}
static __forceinline__ __device__ bool optixIsBackFaceHit() {
  return optixIsBackFaceHit(optixGetHitKind());
}
static __forceinline__ __device__ bool optixIsTriangleHit() {
  return optixGetPrimitiveType() == OPTIX_PRIMITIVE_TYPE_TRIANGLE;
}
static __forceinline__ __device__ bool optixIsTriangleFrontFaceHit() {
  return optixIsTriangleHit() && optixIsFrontFaceHit();
}
static __forceinline__ __device__ bool optixIsTriangleBackFaceHit() {
  return optixIsTriangleHit() && optixIsBackFaceHit();
}
static __forceinline__ __device__ bool optixIsDisplacedMicromeshTriangleHit() {
  return optixGetPrimitiveType() == OPTIX_PRIMITIVE_TYPE_DISPLACED_MICROMESH_TRIANGLE;
}
static __forceinline__ __device__ bool optixIsDisplacedMicromeshTriangleFrontFaceHit() {
  return optixIsDisplacedMicromeshTriangleHit() && optixIsFrontFaceHit();
}
static __forceinline__ __device__ bool optixIsDisplacedMicromeshTriangleBackFaceHit() {
  return optixIsDisplacedMicromeshTriangleHit() && optixIsBackFaceHit();
}

/* ---- Hit attributes -------------------------------------------------------------------------- */
/* Weights of vertices 1 and 2 of the hit triangle. */
static __forceinline__ __device__ float2 optixGetTriangleBarycentrics() {
  float v[2];
  tessera_optix7::rt()->triangle_barycentrics(v);
  return make_float2(v[0], v[1]);
}
static __forceinline__ __device__ float optixGetCurveParameter() {
  return tessera_optix7::rt()->curve_parameter();
}
static __forceinline__ __device__ float2 optixGetRibbonParameters() {
  float v[2];
  tessera_optix7::rt()->ribbon_parameters(v);
  return make_float2(v[0], v[1]);
}

/* Attribute values reported by the intersection that produced the hit. */
static __forceinline__ __device__ unsigned int optixGetAttribute_0() {
  return tessera_optix7::rt()->get_attribute(0);
}
static __forceinline__ __device__ unsigned int optixGetAttribute_1() {
  return tessera_optix7::rt()->get_attribute(1);
}
static __forceinline__ __device__ unsigned int optixGetAttribute_2() {
  return tessera_optix7::rt()->get_attribute(2);
}
static __forceinline__ __device__ unsigned int optixGetAttribute_3() {
  return tessera_optix7::rt()->get_attribute(3);
}
static __forceinline__ __device__ unsigned int optixGetAttribute_4() {
  return tessera_optix7::rt()->get_attribute(4);
}
static __forceinline__ __device__ unsigned int optixGetAttribute_5() {
  return tessera_optix7::rt()->get_attribute(5);
}
static __forceinline__ __device__ unsigned int optixGetAttribute_6() {
  return tessera_optix7::rt()->get_attribute(6);
}
static __forceinline__ __device__ unsigned int optixGetAttribute_7() {
  return tessera_optix7::rt()->get_attribute(7);
}

/* ---- Intersection and any-hit programs ------------------------------------------------------- */
namespace tessera_optix7 {
template <typename... A>
inline bool Report(float hitT, unsigned int hitKind, A... a) {
  const unsigned int values[sizeof...(A) + 1] = {a..., 0u};
  return rt()->report_intersection(hitT, hitKind, sizeof...(A), values) != 0;
}
template <typename... D>
inline void Throw(int code, D... d) {
  const unsigned int values[sizeof...(D) + 1] = {d..., 0u};
  rt()->throw_exception(code, sizeof...(D), values);
}
}  // namespace tessera_optix7

/* Reports a hit at distance hitT with hitKind 0..127 and 0 to 8 attribute values; returns
 * whether it was accepted (any-hit programs may ignore it). */
static __forceinline__ __device__ bool optixReportIntersection(float hitT, unsigned int hitKind) {
  return tessera_optix7::Report(hitT, hitKind);
}
static __forceinline__ __device__ bool optixReportIntersection(float hitT, unsigned int hitKind,
                                                               unsigned int a0) {
  return tessera_optix7::Report(hitT, hitKind, a0);
}
static __forceinline__ __device__ bool optixReportIntersection(float hitT, unsigned int hitKind,
                                                               unsigned int a0, unsigned int a1) {
  return tessera_optix7::Report(hitT, hitKind, a0, a1);
}
static __forceinline__ __device__ bool optixReportIntersection(float hitT, unsigned int hitKind,
                                                               unsigned int a0, unsigned int a1,
                                                               unsigned int a2) {
  return tessera_optix7::Report(hitT, hitKind, a0, a1, a2);
}
static __forceinline__ __device__ bool optixReportIntersection(float hitT, unsigned int hitKind,
                                                               unsigned int a0, unsigned int a1,
                                                               unsigned int a2, unsigned int a3) {
  return tessera_optix7::Report(hitT, hitKind, a0, a1, a2, a3);
}
static __forceinline__ __device__ bool optixReportIntersection(float hitT, unsigned int hitKind,
                                                               unsigned int a0, unsigned int a1,
                                                               unsigned int a2, unsigned int a3,
                                                               unsigned int a4) {
  return tessera_optix7::Report(hitT, hitKind, a0, a1, a2, a3, a4);
}
static __forceinline__ __device__ bool optixReportIntersection(float hitT, unsigned int hitKind,
                                                               unsigned int a0, unsigned int a1,
                                                               unsigned int a2, unsigned int a3,
                                                               unsigned int a4, unsigned int a5) {
  return tessera_optix7::Report(hitT, hitKind, a0, a1, a2, a3, a4, a5);
}
static __forceinline__ __device__ bool optixReportIntersection(float hitT, unsigned int hitKind,
                                                               unsigned int a0, unsigned int a1,
                                                               unsigned int a2, unsigned int a3,
                                                               unsigned int a4, unsigned int a5,
                                                               unsigned int a6) {
  return tessera_optix7::Report(hitT, hitKind, a0, a1, a2, a3, a4, a5, a6);
}
static __forceinline__ __device__ bool optixReportIntersection(float hitT, unsigned int hitKind,
                                                               unsigned int a0, unsigned int a1,
                                                               unsigned int a2, unsigned int a3,
                                                               unsigned int a4, unsigned int a5,
                                                               unsigned int a6, unsigned int a7) {
  return tessera_optix7::Report(hitT, hitKind, a0, a1, a2, a3, a4, a5, a6, a7);
}

static __forceinline__ __device__ void optixIgnoreIntersection() {
  tessera_optix7::rt()->ignore_intersection();
}
static __forceinline__ __device__ void optixTerminateRay() {
  tessera_optix7::rt()->terminate_ray();
}

/* ---- Primitive data -------------------------------------------------------------------------- */
static __forceinline__ __device__ void optixGetTriangleVertexData(OptixTraversableHandle gas,
                                                                  unsigned int primIdx,
                                                                  unsigned int sbtGASIndex,
                                                                  float time, float3 data[3]) {
  float v[9];
  tessera_optix7::rt()->primitive_data(OPTIX_PRIMITIVE_TYPE_TRIANGLE, gas, primIdx, sbtGASIndex,
                                       time, v);
  for (int i = 0; i < 3; ++i) data[i] = make_float3(v[3 * i], v[3 * i + 1], v[3 * i + 2]);
}

static __forceinline__ __device__ void optixGetMicroTriangleVertexData(float3 data[3]) {
  float v[9];
  tessera_optix7::rt()->micro_triangle_vertex_data(v);
  for (int i = 0; i < 3; ++i) data[i] = make_float3(v[3 * i], v[3 * i + 1], v[3 * i + 2]);
}

static __forceinline__ __device__ void optixGetMicroTriangleBarycentricsData(float2 data[3]) {
  float v[6];
  tessera_optix7::rt()->micro_triangle_barycentrics_data(v);
  for (int i = 0; i < 3; ++i) data[i] = make_float2(v[2 * i], v[2 * i + 1]);
}

namespace tessera_optix7 {
template <int N>
inline void ControlPoints(OptixPrimitiveType type, OptixTraversableHandle gas, unsigned int primIdx,
                          unsigned int sbtGASIndex, float time, float4 data[N]) {
  float v[4 * N];
  rt()->primitive_data(type, gas, primIdx, sbtGASIndex, time, v);
  for (int i = 0; i < N; ++i)
    data[i] = make_float4(v[4 * i], v[4 * i + 1], v[4 * i + 2], v[4 * i + 3]);
}
}  // namespace tessera_optix7

/* Curve control points (x, y, z, width) and spheres (center, radius). */
static __forceinline__ __device__ void optixGetLinearCurveVertexData(OptixTraversableHandle gas,
                                                                     unsigned int primIdx,
                                                                     unsigned int sbtGASIndex,
                                                                     float time, float4 data[2]) {
  tessera_optix7::ControlPoints<2>(OPTIX_PRIMITIVE_TYPE_ROUND_LINEAR, gas, primIdx, sbtGASIndex,
                                   time, data);
}
static __forceinline__ __device__ void optixGetQuadraticBSplineVertexData(
    OptixTraversableHandle gas, unsigned int primIdx, unsigned int sbtGASIndex, float time,
    float4 data[3]) {
  tessera_optix7::ControlPoints<3>(OPTIX_PRIMITIVE_TYPE_ROUND_QUADRATIC_BSPLINE, gas, primIdx,
                                   sbtGASIndex, time, data);
}
static __forceinline__ __device__ void optixGetCubicBSplineVertexData(OptixTraversableHandle gas,
                                                                      unsigned int primIdx,
                                                                      unsigned int sbtGASIndex,
                                                                      float time, float4 data[4]) {
  tessera_optix7::ControlPoints<4>(OPTIX_PRIMITIVE_TYPE_ROUND_CUBIC_BSPLINE, gas, primIdx,
                                   sbtGASIndex, time, data);
}
static __forceinline__ __device__ void optixGetCatmullRomVertexData(OptixTraversableHandle gas,
                                                                    unsigned int primIdx,
                                                                    unsigned int sbtGASIndex,
                                                                    float time, float4 data[4]) {
  tessera_optix7::ControlPoints<4>(OPTIX_PRIMITIVE_TYPE_ROUND_CATMULLROM, gas, primIdx, sbtGASIndex,
                                   time, data);
}
static __forceinline__ __device__ void optixGetCubicBezierVertexData(OptixTraversableHandle gas,
                                                                     unsigned int primIdx,
                                                                     unsigned int sbtGASIndex,
                                                                     float time, float4 data[4]) {
  tessera_optix7::ControlPoints<4>(OPTIX_PRIMITIVE_TYPE_ROUND_CUBIC_BEZIER, gas, primIdx,
                                   sbtGASIndex, time, data);
}
static __forceinline__ __device__ void optixGetRibbonVertexData(OptixTraversableHandle gas,
                                                                unsigned int primIdx,
                                                                unsigned int sbtGASIndex,
                                                                float time, float4 data[3]) {
  tessera_optix7::ControlPoints<3>(OPTIX_PRIMITIVE_TYPE_FLAT_QUADRATIC_BSPLINE, gas, primIdx,
                                   sbtGASIndex, time, data);
}
static __forceinline__ __device__ void optixGetSphereData(OptixTraversableHandle gas,
                                                          unsigned int primIdx,
                                                          unsigned int sbtGASIndex, float time,
                                                          float4 data[1]) {
  tessera_optix7::ControlPoints<1>(OPTIX_PRIMITIVE_TYPE_SPHERE, gas, primIdx, sbtGASIndex, time,
                                   data);
}

static __forceinline__ __device__ float3 optixGetRibbonNormal(OptixTraversableHandle gas,
                                                              unsigned int primIdx,
                                                              unsigned int sbtGASIndex, float time,
                                                              float2 ribbonParameters) {
  const float uv[2] = {ribbonParameters.x, ribbonParameters.y};
  float v[3];
  tessera_optix7::rt()->ribbon_normal(gas, primIdx, sbtGASIndex, time, uv, v);
  return tessera_optix7::ToFloat3(v);
}

/* ---- Traversables and transforms ------------------------------------------------------------- */
static __forceinline__ __device__ OptixTraversableHandle optixGetGASTraversableHandle() {
  return tessera_optix7::rt()->gas_traversable_handle();
}
static __forceinline__ __device__ float optixGetGASMotionTimeBegin(OptixTraversableHandle gas) {
  return tessera_optix7::rt()->gas_motion_time(gas, 0);
}
static __forceinline__ __device__ float optixGetGASMotionTimeEnd(OptixTraversableHandle gas) {
  return tessera_optix7::rt()->gas_motion_time(gas, 1);
}
static __forceinline__ __device__ unsigned int optixGetGASMotionStepCount(
    OptixTraversableHandle gas) {
  return tessera_optix7::rt()->gas_motion_step_count(gas);
}
static __forceinline__ __device__ OptixTraversableHandle
optixGetTransformListHandle(unsigned int index) {
  return tessera_optix7::rt()->transform_list_handle(index);
}
static __forceinline__ __device__ OptixTransformType
optixGetTransformTypeFromHandle(OptixTraversableHandle handle) {
  return tessera_optix7::rt()->transform_type_from_handle(handle);
}
static __forceinline__ __device__ const OptixStaticTransform* optixGetStaticTransformFromHandle(
    OptixTraversableHandle handle) {
  return static_cast<const OptixStaticTransform*>(
      tessera_optix7::rt()->transform_data_from_handle(handle, TESSERA_OPTIX7_STATIC_TRANSFORM));
}
static __forceinline__ __device__ const OptixSRTMotionTransform*
optixGetSRTMotionTransformFromHandle(OptixTraversableHandle handle) {
  return static_cast<const OptixSRTMotionTransform*>(
      tessera_optix7::rt()->transform_data_from_handle(handle,
                                                       TESSERA_OPTIX7_SRT_MOTION_TRANSFORM));
}
static __forceinline__ __device__ const OptixMatrixMotionTransform*
optixGetMatrixMotionTransformFromHandle(OptixTraversableHandle handle) {
  return static_cast<const OptixMatrixMotionTransform*>(
      tessera_optix7::rt()->transform_data_from_handle(handle,
                                                       TESSERA_OPTIX7_MATRIX_MOTION_TRANSFORM));
}
static __forceinline__ __device__ unsigned int optixGetInstanceIdFromHandle(
    OptixTraversableHandle handle) {
  return tessera_optix7::rt()->instance_id_from_handle(handle);
}
static __forceinline__ __device__ OptixTraversableHandle
optixGetInstanceChildFromHandle(OptixTraversableHandle handle) {
  return tessera_optix7::rt()->instance_child_from_handle(handle);
}
static __forceinline__ __device__ const float4* optixGetInstanceTransformFromHandle(
    OptixTraversableHandle handle) {
  return static_cast<const float4*>(
      tessera_optix7::rt()->transform_data_from_handle(handle, TESSERA_OPTIX7_INSTANCE_TRANSFORM));
}
static __forceinline__ __device__ const float4* optixGetInstanceInverseTransformFromHandle(
    OptixTraversableHandle handle) {
  return static_cast<const float4*>(tessera_optix7::rt()->transform_data_from_handle(
      handle, TESSERA_OPTIX7_INSTANCE_INVERSE_TRANSFORM));
}
static __forceinline__ __device__ OptixTraversableHandle
optixGetInstanceTraversableFromIAS(OptixTraversableHandle ias, unsigned int instIdx) {
  return tessera_optix7::rt()->instance_traversable_from_ias(ias, instIdx);
}

/* The current hit's transforms (all transforms from the root to the GAS, at the ray's time),
 * 3x4 row-major. */
static __forceinline__ __device__ void optixGetWorldToObjectTransformMatrix(float m[12]) {
  tessera_optix7::rt()->current_transform(TESSERA_OPTIX7_WORLD_TO_OBJECT, m);
}
static __forceinline__ __device__ void optixGetObjectToWorldTransformMatrix(float m[12]) {
  tessera_optix7::rt()->current_transform(TESSERA_OPTIX7_OBJECT_TO_WORLD, m);
}

namespace tessera_optix7 {
inline float3 Transform(unsigned int kind, unsigned int direction, float3 p) {
  const float in[3] = {p.x, p.y, p.z};
  float out[3];
  rt()->transform(kind, direction, in, out);
  return ToFloat3(out);
}
}  // namespace tessera_optix7

static __forceinline__ __device__ float3 optixTransformPointFromWorldToObjectSpace(float3 point) {
  return tessera_optix7::Transform(TESSERA_OPTIX7_TRANSFORM_POINT, TESSERA_OPTIX7_WORLD_TO_OBJECT,
                                   point);
}
static __forceinline__ __device__ float3 optixTransformPointFromObjectToWorldSpace(float3 point) {
  return tessera_optix7::Transform(TESSERA_OPTIX7_TRANSFORM_POINT, TESSERA_OPTIX7_OBJECT_TO_WORLD,
                                   point);
}
static __forceinline__ __device__ float3 optixTransformVectorFromWorldToObjectSpace(float3 vector) {
  return tessera_optix7::Transform(TESSERA_OPTIX7_TRANSFORM_VECTOR, TESSERA_OPTIX7_WORLD_TO_OBJECT,
                                   vector);
}
static __forceinline__ __device__ float3 optixTransformVectorFromObjectToWorldSpace(float3 vector) {
  return tessera_optix7::Transform(TESSERA_OPTIX7_TRANSFORM_VECTOR, TESSERA_OPTIX7_OBJECT_TO_WORLD,
                                   vector);
}
static __forceinline__ __device__ float3 optixTransformNormalFromWorldToObjectSpace(float3 normal) {
  return tessera_optix7::Transform(TESSERA_OPTIX7_TRANSFORM_NORMAL, TESSERA_OPTIX7_WORLD_TO_OBJECT,
                                   normal);
}
static __forceinline__ __device__ float3 optixTransformNormalFromObjectToWorldSpace(float3 normal) {
  return tessera_optix7::Transform(TESSERA_OPTIX7_TRANSFORM_NORMAL, TESSERA_OPTIX7_OBJECT_TO_WORLD,
                                   normal);
}

/* ---- Exceptions ------------------------------------------------------------------------------ */
/* Throws user exception `exceptionCode` (0..2^30-1) with 0 to 8 detail values; the exception
 * program of the pipeline runs next. */
static __forceinline__ __device__ void optixThrowException(int exceptionCode) {
  tessera_optix7::Throw(exceptionCode);
}
static __forceinline__ __device__ void optixThrowException(int exceptionCode,
                                                           unsigned int exceptionDetail0) {
  tessera_optix7::Throw(exceptionCode, exceptionDetail0);
}
static __forceinline__ __device__ void optixThrowException(int exceptionCode,
                                                           unsigned int exceptionDetail0,
                                                           unsigned int exceptionDetail1) {
  tessera_optix7::Throw(exceptionCode, exceptionDetail0, exceptionDetail1);
}
static __forceinline__ __device__ void optixThrowException(int exceptionCode,
                                                           unsigned int exceptionDetail0,
                                                           unsigned int exceptionDetail1,
                                                           unsigned int exceptionDetail2) {
  tessera_optix7::Throw(exceptionCode, exceptionDetail0, exceptionDetail1, exceptionDetail2);
}
static __forceinline__ __device__ void optixThrowException(int exceptionCode,
                                                           unsigned int exceptionDetail0,
                                                           unsigned int exceptionDetail1,
                                                           unsigned int exceptionDetail2,
                                                           unsigned int exceptionDetail3) {
  tessera_optix7::Throw(exceptionCode, exceptionDetail0, exceptionDetail1, exceptionDetail2,
                        exceptionDetail3);
}
static __forceinline__ __device__ void optixThrowException(
    int exceptionCode, unsigned int exceptionDetail0, unsigned int exceptionDetail1,
    unsigned int exceptionDetail2, unsigned int exceptionDetail3, unsigned int exceptionDetail4) {
  tessera_optix7::Throw(exceptionCode, exceptionDetail0, exceptionDetail1, exceptionDetail2,
                        exceptionDetail3, exceptionDetail4);
}
static __forceinline__ __device__ void optixThrowException(
    int exceptionCode, unsigned int exceptionDetail0, unsigned int exceptionDetail1,
    unsigned int exceptionDetail2, unsigned int exceptionDetail3, unsigned int exceptionDetail4,
    unsigned int exceptionDetail5) {
  tessera_optix7::Throw(exceptionCode, exceptionDetail0, exceptionDetail1, exceptionDetail2,
                        exceptionDetail3, exceptionDetail4, exceptionDetail5);
}
static __forceinline__ __device__ void optixThrowException(
    int exceptionCode, unsigned int exceptionDetail0, unsigned int exceptionDetail1,
    unsigned int exceptionDetail2, unsigned int exceptionDetail3, unsigned int exceptionDetail4,
    unsigned int exceptionDetail5, unsigned int exceptionDetail6) {
  tessera_optix7::Throw(exceptionCode, exceptionDetail0, exceptionDetail1, exceptionDetail2,
                        exceptionDetail3, exceptionDetail4, exceptionDetail5, exceptionDetail6);
}
static __forceinline__ __device__ void optixThrowException(
    int exceptionCode, unsigned int exceptionDetail0, unsigned int exceptionDetail1,
    unsigned int exceptionDetail2, unsigned int exceptionDetail3, unsigned int exceptionDetail4,
    unsigned int exceptionDetail5, unsigned int exceptionDetail6, unsigned int exceptionDetail7) {
  tessera_optix7::Throw(exceptionCode, exceptionDetail0, exceptionDetail1, exceptionDetail2,
                        exceptionDetail3, exceptionDetail4, exceptionDetail5, exceptionDetail6,
                        exceptionDetail7);
}
static __forceinline__ __device__ int optixGetExceptionCode() {
  return tessera_optix7::rt()->exception_code();
}
static __forceinline__ __device__ unsigned int optixGetExceptionDetail_0() {
  return tessera_optix7::rt()->exception_detail(0);
}
static __forceinline__ __device__ unsigned int optixGetExceptionDetail_1() {
  return tessera_optix7::rt()->exception_detail(1);
}
static __forceinline__ __device__ unsigned int optixGetExceptionDetail_2() {
  return tessera_optix7::rt()->exception_detail(2);
}
static __forceinline__ __device__ unsigned int optixGetExceptionDetail_3() {
  return tessera_optix7::rt()->exception_detail(3);
}
static __forceinline__ __device__ unsigned int optixGetExceptionDetail_4() {
  return tessera_optix7::rt()->exception_detail(4);
}
static __forceinline__ __device__ unsigned int optixGetExceptionDetail_5() {
  return tessera_optix7::rt()->exception_detail(5);
}
static __forceinline__ __device__ unsigned int optixGetExceptionDetail_6() {
  return tessera_optix7::rt()->exception_detail(6);
}
static __forceinline__ __device__ unsigned int optixGetExceptionDetail_7() {
  return tessera_optix7::rt()->exception_detail(7);
}
static __forceinline__ __device__ OptixTraversableHandle optixGetExceptionInvalidTraversable() {
  return tessera_optix7::rt()->exception_invalid_traversable();
}
static __forceinline__ __device__ int optixGetExceptionInvalidSbtOffset() {
  return tessera_optix7::rt()->exception_invalid_sbt_offset();
}
static __forceinline__ __device__ OptixInvalidRayExceptionDetails optixGetExceptionInvalidRay() {
  float v[9];
  tessera_optix7::rt()->exception_invalid_ray(v);
  OptixInvalidRayExceptionDetails d;
  d.origin = make_float3(v[0], v[1], v[2]);
  d.direction = make_float3(v[3], v[4], v[5]);
  d.tmin = v[6];
  d.tmax = v[7];
  d.time = v[8];
  return d;
}
static __forceinline__ __device__ OptixParameterMismatchExceptionDetails
optixGetExceptionParameterMismatch() {
  TesseraOptix7ParameterMismatch m;
  tessera_optix7::rt()->exception_parameter_mismatch(&m);
  OptixParameterMismatchExceptionDetails d;
  d.expectedParameterCount = m.expected_parameter_count;
  d.passedArgumentCount = m.passed_argument_count;
  d.sbtIndex = m.sbt_index;
  d.callableName = m.callable_name;
  return d;
}
static __forceinline__ __device__ char* optixGetExceptionLineInfo() {
  return tessera_optix7::rt()->exception_line_info();
}

/* ---- Callables ------------------------------------------------------------------------------- */
namespace tessera_optix7 {
/* Restores the caller as the running program when the callable returns (or unwinds). */
struct CallableScope {
  TesseraOptix7CallFrame frame;
  ~CallableScope() { rt()->callable_leave(&frame); }
};

template <typename ReturnT, typename... ArgTypes>
inline ReturnT Call(unsigned int kind, unsigned int sbtIndex, ArgTypes... args) {
  CallableScope scope;
  using Fn = ReturnT (*)(ArgTypes...);
  const Fn fn = reinterpret_cast<Fn>(rt()->callable_enter(kind, sbtIndex, &scope.frame));
  return fn(args...);
}
}  // namespace tessera_optix7

/* Calls the direct callable of SBT callable record sbtIndex: `__direct_callable__name(args...)`
 * with the argument and return types given here, which must be the entry point's. */
template <typename ReturnT, typename... ArgTypes>
static __forceinline__ __device__ ReturnT optixDirectCall(unsigned int sbtIndex, ArgTypes... args) {
  return tessera_optix7::Call<ReturnT, ArgTypes...>(TESSERA_OPTIX7_DIRECT_CALLABLE, sbtIndex,
                                                    args...);
}

/* As optixDirectCall, for a continuation callable (which may call optixTrace). */
template <typename ReturnT, typename... ArgTypes>
static __forceinline__ __device__ ReturnT optixContinuationCall(unsigned int sbtIndex,
                                                                ArgTypes... args) {
  return tessera_optix7::Call<ReturnT, ArgTypes...>(TESSERA_OPTIX7_CONTINUATION_CALLABLE, sbtIndex,
                                                    args...);
}

/* ---- Texture footprints ---------------------------------------------------------------------- */
static __forceinline__ __device__ uint4 optixTexFootprint2D(unsigned long long tex,
                                                            unsigned int texInfo, float x, float y,
                                                            unsigned int* singleMipLevel) {
  unsigned int v[4];
  tessera_optix7::rt()->tex_footprint_2d(tex, texInfo, x, y, singleMipLevel, v);
  return make_uint4(v[0], v[1], v[2], v[3]);
}
static __forceinline__ __device__ uint4 optixTexFootprint2DGrad(
    unsigned long long tex, unsigned int texInfo, float x, float y, float dPdx_x, float dPdx_y,
    float dPdy_x, float dPdy_y, bool coarse, unsigned int* singleMipLevel) {
  unsigned int v[4];
  tessera_optix7::rt()->tex_footprint_2d_grad(tex, texInfo, x, y, dPdx_x, dPdx_y, dPdy_x, dPdy_y,
                                              coarse ? 1 : 0, singleMipLevel, v);
  return make_uint4(v[0], v[1], v[2], v[3]);
}
static __forceinline__ __device__ uint4 optixTexFootprint2DLod(unsigned long long tex,
                                                               unsigned int texInfo, float x,
                                                               float y, float level, bool coarse,
                                                               unsigned int* singleMipLevel) {
  unsigned int v[4];
  tessera_optix7::rt()->tex_footprint_2d_lod(tex, texInfo, x, y, level, coarse ? 1 : 0,
                                             singleMipLevel, v);
  return make_uint4(v[0], v[1], v[2], v[3]);
}

/* ---- Tessera's additions ------------------------------------------------------------------- */
#include "tessera/optix7_accuracy.h"

#endif /* TESSERA_OPTIX7_OPTIX_DEVICE_H_ */

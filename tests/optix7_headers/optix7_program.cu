// An OptiX 7 program module in the SDK's style (optixTriangle, optixSphere, optixCallablePrograms),
// compiled by g++ as Tessera compiles program modules:
//   g++ -std=c++17 -O2 -shared -fPIC -x c++ -D__CUDACC__ -Wall -Wextra -Werror -I<include7>
// It only has to compile and export its entry points and `params`: the engine that would run it is
// the next part of issue 25.
#include <optix.h>

struct Params {
  uchar4* image;
  unsigned int image_width;
  unsigned int image_height;
  float3 cam_eye;
  float3 cam_u, cam_v, cam_w;
  OptixTraversableHandle handle;
};

struct MissData {
  float3 bg_color;
};

struct HitGroupData {
  float3 color;
  float3 center;
  float radius;
};

extern "C" {
__constant__ Params params;
}

static __forceinline__ __device__ void setPayload(float3 p) {
  optixSetPayload_0(__float_as_uint(p.x));
  optixSetPayload_1(__float_as_uint(p.y));
  optixSetPayload_2(__float_as_uint(p.z));
}

static __forceinline__ __device__ float3 scale(float3 v, float s) {
  return make_float3(v.x * s, v.y * s, v.z * s);
}

static __forceinline__ __device__ float3 add(float3 a, float3 b) {
  return make_float3(a.x + b.x, a.y + b.y, a.z + b.z);
}

static __forceinline__ __device__ float dot(float3 a, float3 b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}

extern "C" __global__ void __raygen__rg() {
  const uint3 idx = optixGetLaunchIndex();
  const uint3 dim = optixGetLaunchDimensions();
  const float u = 2.0f * static_cast<float>(idx.x) / static_cast<float>(dim.x) - 1.0f;
  const float v = 2.0f * static_cast<float>(idx.y) / static_cast<float>(dim.y) - 1.0f;
  const float3 direction = add(add(scale(params.cam_u, u), scale(params.cam_v, v)), params.cam_w);

  unsigned int p0, p1, p2;
  optixTrace(params.handle, params.cam_eye, direction, 0.0f, 1e16f, 0.0f, OptixVisibilityMask(255),
             OPTIX_RAY_FLAG_NONE, 0, 1, 0, p0, p1, p2);
  // A shadow-style ray without payload, and one with a payload type.
  optixTrace(params.handle, params.cam_eye, direction, 0.0f, 1e16f, 0.0f, OptixVisibilityMask(1),
             OPTIX_RAY_FLAG_TERMINATE_ON_FIRST_HIT | OPTIX_RAY_FLAG_DISABLE_CLOSESTHIT, 1, 2, 1);
  optixTrace(OPTIX_PAYLOAD_TYPE_ID_0, params.handle, params.cam_eye, direction, 0.0f, 1e16f, 0.0f,
             OptixVisibilityMask(255), OPTIX_RAY_FLAG_NONE, 0, 1, 0, p0);

  const float3 color = make_float3(__uint_as_float(p0), __uint_as_float(p1), __uint_as_float(p2));
  const float scaled = optixDirectCall<float, float>(0, color.x);
  params.image[idx.y * params.image_width + idx.x] = make_uchar4(
      static_cast<unsigned char>(scaled * 255.0f), static_cast<unsigned char>(color.y * 255.0f),
      static_cast<unsigned char>(color.z * 255.0f), 255u);
}

extern "C" __global__ void __miss__ms() {
  const MissData* miss_data = reinterpret_cast<MissData*>(optixGetSbtDataPointer());
  setPayload(miss_data->bg_color);
}

extern "C" __global__ void __closesthit__ch() {
  const float2 barycentrics = optixGetTriangleBarycentrics();
  float3 vertices[3];
  optixGetTriangleVertexData(optixGetGASTraversableHandle(), optixGetPrimitiveIndex(),
                             optixGetSbtGASIndex(), optixGetRayTime(), vertices);
  const float3 object_normal = optixTransformNormalFromObjectToWorldSpace(vertices[0]);
  const float facing = optixIsTriangleFrontFaceHit() ? 1.0f : 0.5f;
  (void)object_normal;
  setPayload(make_float3(barycentrics.x * facing, barycentrics.y, 1.0f));
}

// A custom-primitive sphere (optixSphere's intersection program, simplified).
extern "C" __global__ void __intersection__sphere() {
  const HitGroupData* data = reinterpret_cast<HitGroupData*>(optixGetSbtDataPointer());
  const float3 origin = optixGetObjectRayOrigin();
  const float3 direction = optixGetObjectRayDirection();
  const float3 o =
      make_float3(origin.x - data->center.x, origin.y - data->center.y, origin.z - data->center.z);
  const float b = dot(o, direction);
  const float c = dot(o, o) - data->radius * data->radius;
  const float disc = b * b - c;
  if (disc > 0.0f) {
    const float t = -b - sqrtf(disc);
    if (t > optixGetRayTmin() && t < optixGetRayTmax()) {
      const float3 n = add(o, scale(direction, t));
      optixReportIntersection(t, 0, __float_as_uint(n.x), __float_as_uint(n.y),
                              __float_as_uint(n.z), __float_as_uint(data->radius));
    }
  }
}

extern "C" __global__ void __closesthit__sphere() {
  const float3 n =
      make_float3(__uint_as_float(optixGetAttribute_0()), __uint_as_float(optixGetAttribute_1()),
                  __uint_as_float(optixGetAttribute_2()));
  float m[12];
  optixGetObjectToWorldTransformMatrix(m);
  const float3 world_n = optixTransformNormalFromObjectToWorldSpace(n);
  setPayload(make_float3(world_n.x * m[0], world_n.y, world_n.z * 0.5f + 0.5f));
}

extern "C" __global__ void __anyhit__cutout() {
  if (optixGetPrimitiveIndex() % 2 == 1 && optixGetHitKind() == 0) optixIgnoreIntersection();
  if (optixGetInstanceId() == 7) optixTerminateRay();
}

extern "C" __device__ float __direct_callable__scale(float x) { return 0.5f * x; }

extern "C" __global__ void __exception__all() {
  const int code = optixGetExceptionCode();
  if (code == OPTIX_EXCEPTION_CODE_STACK_OVERFLOW) {
    setPayload(make_float3(1.0f, 0.0f, 1.0f));
  } else if (code >= 0) {
    const unsigned int detail = optixGetExceptionDetail_0();
    setPayload(make_float3(static_cast<float>(detail), 0.0f, 0.0f));
  }
}

extern "C" __global__ void __raygen__throws() {
  if (optixGetLaunchIndex().x == 0) optixThrowException(42, 1u, 2u);
  if (optixGetLaunchIndex().x == 1) optixThrowException(43);
}

// The CUDA intrinsics nvcc gives every .cu file, as SDK helpers (sutil's vec_math.h) and course
// code use them: reinterpretation, fast math, rounding conversions, integer bit counts, min/max.
extern "C" __global__ void __raygen__intrinsics() {
  const uint3 idx = optixGetLaunchIndex();
  float a = rsqrtf(2.0f) + __saturatef(1.5f) + __fdividef(1.f, 3.f) + __expf(1.f);
  a += __sinf(a) + __cosf(a) + __logf(a) + __powf(a, 2.f) + __frcp_rn(a) + __fsqrt_rn(a);
  a += __int_as_float(__float2int_rn(a) & 0) + copysignf(1.f, -2.f) + fminf(a, 2.f);
  const int bits = __popc(idx.x) + __clz(static_cast<int>(idx.y) + 1) + __ffs(8) + max(1, 2) +
                   min(3, static_cast<int>(idx.x));
  params.image[idx.x] =
      make_uchar4(static_cast<unsigned char>(a), static_cast<unsigned char>(bits), 0, 255);
}

// Programs of the engine tests (engine_test.cc) that trace: each reports what it saw through its
// payload, and the raygen program writes the payload out, so that the test reads every query's
// answer from device memory.
#include <optix.h>

#include "engine_params.h"

extern "C" {
__constant__ EngineParams params;
}

static __forceinline__ __device__ float3 Add(float3 a, float3 b) {
  return make_float3(a.x + b.x, a.y + b.y, a.z + b.z);
}
static __forceinline__ __device__ float3 Scale(float3 a, float s) {
  return make_float3(a.x * s, a.y * s, a.z * s);
}
static __forceinline__ __device__ unsigned int RecordValue() {
  return reinterpret_cast<const RecordData*>(optixGetSbtDataPointer())->value;
}
static __forceinline__ __device__ unsigned int* Out() {
  const uint3 idx = optixGetLaunchIndex();
  const uint3 dim = optixGetLaunchDimensions();
  return params.out + (idx.y * dim.x + idx.x) * ENGINE_WORDS;
}

// Traces one ray per launch index with 12 payload values: 0..9 and 11 start as ~0 (what no program
// set), 10 at 0 (any-hit programs count their calls in it).
extern "C" __global__ void __raygen__trace() {
  const uint3 idx = optixGetLaunchIndex();
  const float3 origin = Add(params.origin, Scale(params.step, static_cast<float>(idx.x)));
  unsigned int p0 = ~0u, p1 = ~0u, p2 = ~0u, p3 = ~0u, p4 = ~0u, p5 = ~0u, p6 = ~0u, p7 = ~0u,
               p8 = ~0u, p9 = ~0u, p10 = 0, p11 = ~0u;
  optixTrace(params.handle, origin, params.direction, params.tmin, params.tmax, params.time,
             OptixVisibilityMask(params.visibility_mask), params.ray_flags, params.sbt_offset,
             params.sbt_stride, params.miss_index, p0, p1, p2, p3, p4, p5, p6, p7, p8, p9, p10,
             p11);
  const unsigned int p[12] = {p0, p1, p2, p3, p4, p5, p6, p7, p8, p9, p10, p11};
  unsigned int* out = Out();
  for (int i = 0; i < 12; ++i) out[i] = p[i];
}

// What a hit looks like from its closest-hit program.
extern "C" __global__ void __closesthit__probe() {
  const float t = optixGetRayTmax();
  optixSetPayload_0(RecordValue());
  optixSetPayload_1(optixGetPrimitiveIndex());
  optixSetPayload_2(optixGetHitKind());
  optixSetPayload_3(optixGetAttribute_0());
  optixSetPayload_4(optixGetAttribute_1());
  optixSetPayload_5(optixGetInstanceId());
  optixSetPayload_6(optixGetSbtGASIndex());
  optixSetPayload_7(__float_as_uint(t));
  optixSetPayload_8(optixGetInstanceIndex());
  optixSetPayload_9(optixIsFrontFaceHit() ? 1u : 0u);
  // The hit point in object space, and back to world space.
  const float3 object = Add(optixGetObjectRayOrigin(), Scale(optixGetObjectRayDirection(), t));
  const float3 world = optixTransformPointFromObjectToWorldSpace(object);
  optixSetPayload_11(__float_as_uint(object.x));
  unsigned int* out = Out();
  out[12] = __float_as_uint(world.x);
  out[13] = static_cast<unsigned int>(optixGetGASTraversableHandle());
  if (optixIsTriangleHit()) {
    float3 v[3];
    optixGetTriangleVertexData(optixGetGASTraversableHandle(), optixGetPrimitiveIndex(),
                               optixGetSbtGASIndex(), 0.0f, v);
    const float2 b = optixGetTriangleBarycentrics();
    out[14] = __float_as_uint(v[1].x);
    out[15] = b.x == __uint_as_float(optixGetAttribute_0()) &&
                      b.y == __uint_as_float(optixGetAttribute_1())
                  ? 1u
                  : 0u;
  }
}

extern "C" __global__ void __miss__probe() {
  optixSetPayload_0(RecordValue());
  optixSetPayload_7(__float_as_uint(optixGetRayTmax()));
  optixSetPayload_8(optixGetRayFlags());
  optixSetPayload_9(optixGetRayVisibilityMask());
}

// Spheres (params.spheres) as custom primitives: the nearer root within the ray's interval,
// reported with hit kind 5 and attributes (primitive * 10, 77, t).
extern "C" __global__ void __intersection__sphere() {
  const unsigned int prim = optixGetPrimitiveIndex();
  const float4 s = params.spheres[prim];
  const float3 o = optixGetObjectRayOrigin();
  const float3 d = optixGetObjectRayDirection();
  const float3 oc = make_float3(o.x - s.x, o.y - s.y, o.z - s.z);
  const float a = d.x * d.x + d.y * d.y + d.z * d.z;
  const float b = oc.x * d.x + oc.y * d.y + oc.z * d.z;
  const float c = oc.x * oc.x + oc.y * oc.y + oc.z * oc.z - s.w * s.w;
  const float disc = b * b - a * c;
  if (disc < 0.0f) return;
  const float t = (-b - sqrtf(disc)) / a;
  if (t >= optixGetRayTmin() && t <= optixGetRayTmax()) {
    optixReportIntersection(t, 5, prim * 10, 77u, __float_as_uint(t));
  }
}

static __forceinline__ __device__ void CountAnyHit() {
  optixSetPayload_10(optixGetPayload_10() + 1);
}

extern "C" __global__ void __anyhit__ignore_even() {
  CountAnyHit();
  if ((optixGetPrimitiveIndex() & 1u) == 0) optixIgnoreIntersection();
}

extern "C" __global__ void __anyhit__ignore_all() {
  CountAnyHit();
  optixIgnoreIntersection();
  optixSetPayload_10(0xDEAD);  // never runs: optixIgnoreIntersection does not return
}

extern "C" __global__ void __anyhit__terminate() {
  CountAnyHit();
  optixTerminateRay();
}

extern "C" __global__ void __anyhit__count() { CountAnyHit(); }

// Traces again from the hit until payload 0 (the depth) reaches params.recursion.
extern "C" __global__ void __closesthit__recurse() {
  unsigned int depth = optixGetPayload_0() + 1;
  if (depth < params.recursion) {
    optixTrace(params.handle, params.origin, params.direction, params.tmin, params.tmax, 0.0f,
               OptixVisibilityMask(255), OPTIX_RAY_FLAG_NONE, 0, 1, 0, depth);
  }
  optixSetPayload_0(depth);
}

extern "C" __global__ void __raygen__recurse() {
  unsigned int depth = 0;
  optixTrace(params.handle, params.origin, params.direction, params.tmin, params.tmax, 0.0f,
             OptixVisibilityMask(255), OPTIX_RAY_FLAG_NONE, 0, 1, 0, depth);
  Out()[0] = depth;
}

// The transform queries of an instanced hit, with the normal and vector transforms, in payloads
// 0 to 10.
extern "C" __global__ void __closesthit__transforms() {
  optixSetPayload_0(optixGetTransformListSize());
  const OptixTraversableHandle h = optixGetTransformListHandle(0);
  optixSetPayload_1(optixGetInstanceIdFromHandle(h));
  optixSetPayload_2(__float_as_uint(optixGetInstanceTransformFromHandle(h)[0].x));
  optixSetPayload_3(__float_as_uint(optixGetInstanceInverseTransformFromHandle(h)[0].w));
  float m[12];
  optixGetObjectToWorldTransformMatrix(m);
  optixSetPayload_4(__float_as_uint(m[3]));
  optixSetPayload_5(optixGetTransformTypeFromHandle(h) == OPTIX_TRANSFORM_TYPE_INSTANCE ? 1u : 0u);
  optixSetPayload_6(static_cast<unsigned int>(optixGetInstanceChildFromHandle(h)));
  optixSetPayload_7(
      __float_as_uint(optixTransformNormalFromObjectToWorldSpace(make_float3(1, 0, 0)).x));
  optixSetPayload_8(
      __float_as_uint(optixTransformVectorFromWorldToObjectSpace(make_float3(1, 0, 0)).x));
  optixSetPayload_9(static_cast<unsigned int>(
      optixGetInstanceTraversableFromIAS(params.handle, optixGetInstanceIndex())));
  optixGetWorldToObjectTransformMatrix(m);
  optixSetPayload_10(__float_as_uint(m[0]));
}

// What a hit in a traversable graph with motion sees (engine_motion_test.cc): the transform list
// and its types, the transforms at the ray's time, instance, GAS motion and primitive data.
extern "C" __global__ void __closesthit__graph() {
  const float t = optixGetRayTmax();
  const unsigned int size = optixGetTransformListSize();
  unsigned int types = 0;
  for (unsigned int i = 0; i < size && i < 8; ++i) {
    types |=
        static_cast<unsigned int>(optixGetTransformTypeFromHandle(optixGetTransformListHandle(i)))
        << (4 * i);
  }
  const float3 object = Add(optixGetObjectRayOrigin(), Scale(optixGetObjectRayDirection(), t));
  float m[12];
  optixGetWorldToObjectTransformMatrix(m);
  const OptixTraversableHandle gas = optixGetGASTraversableHandle();
  optixSetPayload_0(RecordValue());
  optixSetPayload_1(size);
  optixSetPayload_2(types);
  optixSetPayload_3(__float_as_uint(t));
  optixSetPayload_4(__float_as_uint(object.x));
  optixSetPayload_5(__float_as_uint(m[3]));
  optixSetPayload_6(optixGetInstanceId());
  optixSetPayload_7(optixGetInstanceIndex());
  optixSetPayload_8(optixGetGASMotionStepCount(gas));
  optixSetPayload_9(__float_as_uint(optixGetGASMotionTimeEnd(gas)));
  optixSetPayload_11(optixGetHitKind());
  unsigned int* out = Out();
  out[12] = __float_as_uint(optixTransformPointFromObjectToWorldSpace(object).x);
  out[13] = static_cast<unsigned int>(optixGetPrimitiveType());
  if (optixGetPrimitiveType() == OPTIX_PRIMITIVE_TYPE_SPHERE) {
    float4 s[1];
    optixGetSphereData(gas, optixGetPrimitiveIndex(), optixGetSbtGASIndex(), optixGetRayTime(), s);
    out[14] = __float_as_uint(s[0].x);
  } else {
    float3 v[3];
    optixGetTriangleVertexData(gas, optixGetPrimitiveIndex(), optixGetSbtGASIndex(),
                               optixGetRayTime(), v);
    out[14] = __float_as_uint(v[0].x);
  }
  // What the second entry's getter gives: keys of a motion transform, the static transform's x
  // translation, an instance's id.
  out[15] = ~0u;
  if (size > 1) {
    const OptixTraversableHandle h = optixGetTransformListHandle(1);
    switch (optixGetTransformTypeFromHandle(h)) {
      case OPTIX_TRANSFORM_TYPE_MATRIX_MOTION_TRANSFORM:
        out[15] = optixGetMatrixMotionTransformFromHandle(h)->motionOptions.numKeys;
        break;
      case OPTIX_TRANSFORM_TYPE_SRT_MOTION_TRANSFORM:
        out[15] = 100u + optixGetSRTMotionTransformFromHandle(h)->motionOptions.numKeys;
        break;
      case OPTIX_TRANSFORM_TYPE_STATIC_TRANSFORM:
        out[15] = __float_as_uint(optixGetStaticTransformFromHandle(h)->transform[3]);
        break;
      case OPTIX_TRANSFORM_TYPE_INSTANCE:
        out[15] = optixGetInstanceIdFromHandle(h);
        break;
      default:
        break;
    }
  }
}

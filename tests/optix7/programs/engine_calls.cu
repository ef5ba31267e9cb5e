// Programs of the engine tests (engine_test.cc) that call: callables (direct, and a continuation
// callable that traces), user exceptions and the exception program. A second module, so that a
// pipeline's launch parameters reach every module that declares them.
#include <optix.h>

#include "engine_params.h"

extern "C" {
__constant__ EngineParams params;
}

static __forceinline__ __device__ unsigned int* Out() {
  const uint3 idx = optixGetLaunchIndex();
  const uint3 dim = optixGetLaunchDimensions();
  return params.out + (idx.y * dim.x + idx.x) * ENGINE_WORDS;
}
static __forceinline__ __device__ unsigned int RecordValue() {
  return reinterpret_cast<const RecordData*>(optixGetSbtDataPointer())->value;
}

extern "C" __device__ unsigned int __direct_callable__mul_add(unsigned int a, unsigned int b) {
  return a * b + RecordValue();
}

extern "C" __device__ unsigned int __direct_callable__square(unsigned int a, unsigned int b) {
  // A callable calling another: each sees its own record.
  return a * a + b + optixDirectCall<unsigned int>(0, 0u, 0u);
}

extern "C" __device__ unsigned int __continuation_callable__trace(float x) {
  unsigned int p0 = ~0u;
  optixTrace(params.handle, make_float3(x, params.origin.y, params.origin.z), params.direction,
             params.tmin, params.tmax, 0.0f, OptixVisibilityMask(255), OPTIX_RAY_FLAG_NONE, 0, 1, 0,
             p0);
  return p0;
}

extern "C" __global__ void __raygen__callables() {
  const unsigned int x = optixGetLaunchIndex().x;
  unsigned int* out = Out();
  out[0] = optixDirectCall<unsigned int>(0, x, 3u);
  out[1] = optixDirectCall<unsigned int>(1, x, 3u);
  out[2] = optixContinuationCall<unsigned int>(2, params.origin.x + params.step.x * x);
  out[3] = RecordValue();  // the raygen record's again after the calls
  if (x == 2) out[4] = optixDirectCall<unsigned int>(7, 0u, 0u);  // past the records: raises
}

// Calls itself through record `slot` without end, each level with half a kilobyte of stack: the
// engine's stack check must end it (STACK_OVERFLOW) before the stack does.
extern "C" __device__ unsigned int __direct_callable__forever(unsigned int depth,
                                                             unsigned int slot) {
  volatile unsigned char pad[512];
  pad[depth % 512] = static_cast<unsigned char>(depth);
  return optixDirectCall<unsigned int>(slot, depth + 1, slot) + pad[depth % 512];
}

// Writes 1, recurses through callable record 0 without end, then would write 2.
extern "C" __global__ void __raygen__deep() {
  unsigned int* out = Out();
  out[0] = 1u;
  out[1] = optixDirectCall<unsigned int>(0, 0u, 0u);
  out[2] = 2u;
}

// Never returns, and makes no engine call: only a signal can end it.
extern "C" __global__ void __raygen__endless() {
  Out()[0] = 1u;
  volatile unsigned int spin = 0;
  for (;;) spin = spin + 1;
}

// Launch index 1 throws user exception 42 with details 7 and 8; the others write 1.
extern "C" __global__ void __raygen__throw() {
  if (optixGetLaunchIndex().x == 1) optixThrowException(42, 7u, 8u);
  Out()[0] = 1;
}

extern "C" __global__ void __exception__record() {
  unsigned int* out = Out();
  out[0] = static_cast<unsigned int>(optixGetExceptionCode());
  out[1] = optixGetExceptionDetail_0();
  out[2] = optixGetExceptionDetail_1();
  out[3] = RecordValue();
}

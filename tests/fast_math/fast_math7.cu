// OptiX 7 programs of the fast-math tests (fast_math7_test.cc), built as a default module, with
// tessera_add_optix7_program_module(... FAST_MATH), embedded with tessera_embed_program(...
// FAST_MATH), and compiled at run time by contexts with and without TESSERA_ACCURACY_FAST_MATH.
// Every operand comes from the launch parameters, so the compiler cannot fold what is measured.
#include <optix.h>

#include <cmath>

#include "fast_math7_params.h"

extern "C" {
__constant__ FastMathParams params;
}

namespace {
unsigned int Index() {
  const uint3 idx = optixGetLaunchIndex();
  const uint3 dim = optixGetLaunchDimensions();
  return idx.y * dim.x + idx.x;
}
}  // namespace

// [0] a product whose exact value is a denormal (0 when results flush: FTZ), [1] a denormal
// operand times a large number (0 when operands read as zero: DAZ).
extern "C" __global__ void __raygen__denormals() {
  params.out[Index()] =
      make_float4(params.tiny * params.tiny, params.denormal_in * params.big, 0.f, 0.f);
}

// NaN and infinity tests on values computed here.
extern "C" __global__ void __raygen__checks() {
  const float nan = params.zero / params.zero;
  const float inf = params.one / params.zero;
  params.out[Index()] = make_float4(std::isnan(nan) ? 1.f : 0.f, std::isinf(inf) ? 1.f : 0.f,
                                    std::isfinite(inf) ? 1.f : 0.f, nan != nan ? 1.f : 0.f);
}

// A ray this program computes is invalid; with OPTIX_EXCEPTION_FLAG_DEBUG the exception program
// records the code, else the trace misses and [0] is 1.
extern "C" __global__ void __raygen__invalid_ray() {
  float3 origin = make_float3(0.f, 0.f, -10.f);
  float3 direction = make_float3(0.f, 0.f, 1.f);
  if (params.mode == 0) origin.x = params.zero / params.zero;
  if (params.mode == 1) direction.y = params.one / params.zero;
  optixTrace(params.handle, origin, direction, 0.01f, 100.f, 0.f, OptixVisibilityMask(255),
             OPTIX_RAY_FLAG_NONE, 0, 1, 0);
  params.out[Index()] = make_float4(1.f, 0.f, 0.f, 0.f);  // reached only if not raised
}

extern "C" __global__ void __miss__none() {}

extern "C" __global__ void __exception__record() {
  params.out[Index()] = make_float4(float(optixGetExceptionCode()), 0.f, 0.f, 0.f);
}

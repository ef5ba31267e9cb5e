// Launch parameters of fast_math7.cu.
#ifndef TESSERA_TESTS_FAST_MATH_FAST_MATH7_PARAMS_H_
#define TESSERA_TESTS_FAST_MATH_FAST_MATH7_PARAMS_H_

#include <optix.h>

struct FastMathParams {
  float4* out;                    // one per launch index
  OptixTraversableHandle handle;  // 0: every ray misses
  float tiny;                     // 1e-20f: tiny * tiny is a denormal (1e-40)
  float denormal_in;              // 1e-40f
  float big;                      // 1e10f: denormal_in * big is normal (1e-30)
  float zero;
  float one;
  int mode;  // __raygen__invalid_ray: 0 a NaN origin, 1 an infinite direction
};

#endif  // TESSERA_TESTS_FAST_MATH_FAST_MATH7_PARAMS_H_

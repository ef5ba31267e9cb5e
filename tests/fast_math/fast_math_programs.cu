// Programs of the fast-math tests (tests/fast_math), built twice from this one source: as a
// default module and with tessera_add_program_module(... FAST_MATH); fast_math_test.cc also
// compiles it at run time, on a context with and without TESSERA_ACCURACY_FAST_MATH. Every
// operand comes from a variable, so the compiler cannot fold what the tests measure.
#include <optix_world.h>

#include <cmath>

using namespace optix;

struct Payload {
  float value;
};

rtDeclareVariable(uint2, launch_index, rtLaunchIndex, );
rtDeclareVariable(rtObject, top_object, , );
rtDeclareVariable(float, tiny, , );         // 1e-20f: tiny * tiny is a denormal (1e-40)
rtDeclareVariable(float, denormal_in, , );  // 1e-40f, a denormal
rtDeclareVariable(float, big, , );          // 1e10f: denormal_in * big is normal (1e-30)
rtDeclareVariable(float, zero, , );
rtDeclareVariable(float, one, , );
rtDeclareVariable(int, mode, , );

// Per launch index: what the program computed, or the exception program's code.
rtBuffer<float4, 2> result;

// [0] a product whose exact value is a denormal (0 when results flush: FTZ), [1] a denormal
// operand times a large number (0 when operands read as zero: DAZ).
RT_PROGRAM void denormals() {
  result[launch_index] = make_float4(tiny * tiny, denormal_in * big, 0.f, 0.f);
}

// NaN and infinity tests on values computed here: what fast math without finite-math-only keeps.
RT_PROGRAM void checks() {
  const float nan = zero / zero;
  const float inf = one / zero;
  result[launch_index] = make_float4(std::isnan(nan) ? 1.f : 0.f, std::isinf(inf) ? 1.f : 0.f,
                                     std::isfinite(inf) ? 1.f : 0.f, nan != nan ? 1.f : 0.f);
}

// A ray this program computes is invalid: mode 0 a NaN origin, 1 an infinite direction.
RT_PROGRAM void invalid_ray() {
  float3 origin = make_float3(0.f, 0.f, -10.f);
  float3 direction = make_float3(0.f, 0.f, 1.f);
  if (mode == 0) origin.x = zero / zero;
  if (mode == 1) direction.y = one / zero;
  Payload p;
  p.value = 0.f;
  rtTrace(top_object, make_Ray(origin, direction, 0, 0.01f, 100.f), p);
  result[launch_index] = make_float4(1.f, 0.f, 0.f, 0.f);  // reached only if not raised
}

RT_PROGRAM void exception_record() {
  result[launch_index] = make_float4(float(rtGetExceptionCode()), 0.f, 0.f, 0.f);
}

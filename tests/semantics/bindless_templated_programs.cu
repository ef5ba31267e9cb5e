// OptiX 3.6's templated rtCallableProgram (bindless_test.cc): with
// RT_USE_TEMPLATED_RTCALLABLEPROGRAM defined first, rtCallableProgram<R(A...)> is a type, declared
// like any variable.
#define RT_USE_TEMPLATED_RTCALLABLEPROGRAM
#include <optix.h>

rtDeclareVariable(uint2, launch_index, rtLaunchIndex, );
rtBuffer<float, 2> result;
rtDeclareVariable(rtCallableProgram<float(float)>, templated_fn, , );

RT_PROGRAM void call_templated() {
  result[launch_index] = templated_fn(static_cast<float>(launch_index.x));
}

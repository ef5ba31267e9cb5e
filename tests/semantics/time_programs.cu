// Programs of time_test: rtCurrentTime in a launch's own program and in the programs of rays
// traced with a time (rtTrace's OptiX 5 argument), without one, and nested.
#include <optix.h>
#include <optixu/optixu_math_namespace.h>

using namespace optix;

struct Times {
  float outer;  // rtCurrentTime of the first miss program, read after its nested trace returned
  float inner;  // rtCurrentTime of the nested ray's miss program
  int depth;
};

rtDeclareVariable(uint2, launch_index, rtLaunchIndex, );
rtDeclareVariable(float, current_time, rtCurrentTime, );
rtDeclareVariable(Times, ray_times, rtPayload, );
rtDeclareVariable(rtObject, top, , );
rtBuffer<float, 2> result;

namespace {
Ray Probe() { return make_Ray(make_float3(0.f), make_float3(0.f, 0.f, 1.f), 0u, 0.f, 1.f); }
}  // namespace

// Even columns trace at time x / 8, odd ones without a time (their rays take the launch's 0).
RT_PROGRAM void trace_times() {
  Times t{-1.f, -1.f, 0};
  if (launch_index.x % 2 == 0) {
    rtTrace(top, Probe(), launch_index.x * 0.125f, t);
  } else {
    rtTrace(top, Probe(), t);
  }
  result[launch_index] = t.outer + 10.f * t.inner + 100.f * current_time;
}

// Row 0 traces its nested ray at time 0.75, other rows without a time (the nested ray takes this
// ray's).
RT_PROGRAM void miss_times() {
  if (ray_times.depth == 0) {
    Times nested{-1.f, -1.f, 1};
    if (launch_index.y == 0) {
      rtTrace(top, Probe(), 0.75f, nested);
    } else {
      rtTrace(top, Probe(), nested);
    }
    ray_times.inner = nested.outer;
  }
  ray_times.outer = current_time;
}

// Callable programs of another module than their callers' (callable_test.cc): the same semantic
// values under other variable names, which the engine copies in from the caller and back.
#include <optix.h>
#include <optixu/optixu_math_namespace.h>

using namespace optix;

struct Payload {
  float value;
  unsigned depth;
};

rtDeclareVariable(rtObject, top_object, , );
rtDeclareVariable(optix::Ray, current, rtCurrentRay, );
rtDeclareVariable(float, distance, rtIntersectionDistance, );
rtDeclareVariable(Payload, data, rtPayload, );
rtDeclareVariable(float, value, attribute a_value, );
rtDeclareVariable(float, level, , );

// As callable_programs.cu's shade_here.
RT_CALLABLE_PROGRAM void shade_other() {
  data.value = distance * 100.f + value;
  if (data.depth == 0) {
    Payload q = {0.f, 1u};
    rtTrace(top_object, make_Ray(current.origin, current.direction, 0, 0.f, RT_DEFAULT_MAX), q);
    data.value += 1000.f * q.value;
  }
}

RT_CALLABLE_PROGRAM void attributes_other() { value = current.origin.x + 0.5f; }

RT_CALLABLE_PROGRAM float tint_twice(float x) { return 2.f * x + level; }

// Traces from x + 0.5 (callable_programs.cu's ch_values_after checks its own values after).
RT_CALLABLE_PROGRAM void trace_shifted() {
  Payload q = {0.f, 1u};
  rtTrace(top_object,
          make_Ray(current.origin + make_float3(0.5f, 0.f, 0.f), current.direction, 0, 0.f,
                   RT_DEFAULT_MAX),
          q);
  data.value = q.value;
}

// Called from any-hit programs: count the candidate in the payload, then end the program.
RT_CALLABLE_PROGRAM void count_and_ignore() {
  data.value += 100.f + distance;
  rtIgnoreIntersection();
}
RT_CALLABLE_PROGRAM void count_and_terminate() {
  data.value += 100.f + distance;
  rtTerminateRay();
}

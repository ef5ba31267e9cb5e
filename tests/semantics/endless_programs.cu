// Programs that never return at one launch index (x == endless_at), each in another place: in
// its own code, in libm, in a closest-hit, miss or intersection program under rtTrace, and in a
// loop of rtTrace calls. The other indices write 1 to `result`. And a bounding box program that
// never returns while endless_at is not -1.
#include <optix.h>
#include <optixu/optixu_math_namespace.h>

#include <exception>

using namespace optix;

struct Payload {
  float value;
};

rtDeclareVariable(uint2, launch_index, rtLaunchIndex, );
rtDeclareVariable(int, endless_at, , ) = -1;
rtDeclareVariable(rtObject, top_object, , );
rtDeclareVariable(Payload, payload, rtPayload, );
rtBuffer<float, 2> result;

static __device__ bool Endless() { return static_cast<int>(launch_index.x) == endless_at; }

// A volatile counter: the loop has a side effect, so the compiler keeps it (an empty endless
// loop would be undefined behavior it may remove).
static __device__ void LoopInProgramCode() {
  volatile unsigned n = 0;
  for (;;) n = n + 1;
}

static __device__ void LoopInLibm() {
  volatile float x = 0.5f;
  for (;;) x = sinf(x) + cosf(x) + expf(-x);
}

static __device__ float TraceOne() {
  Payload p;
  p.value = 0.f;
  Ray r = make_Ray(make_float3(0.f, 0.f, -5.f), make_float3(0.f, 0.f, 1.f), 0, 0.f, RT_DEFAULT_MAX);
  rtTrace(top_object, r, p);
  return p.value;
}

RT_PROGRAM void loop_raygen() {
  if (Endless()) LoopInProgramCode();
  result[launch_index] = 1.f;
}

RT_PROGRAM void libm_raygen() {
  if (Endless()) LoopInLibm();
  result[launch_index] = 1.f;
}

RT_PROGRAM void trace_raygen() { result[launch_index] = TraceOne() > 0.f ? 1.f : 0.f; }

RT_PROGRAM void trace_loop_raygen() {
  if (Endless()) {
    for (;;) TraceOne();
  }
  result[launch_index] = 1.f;
}

RT_PROGRAM void loop_miss() {
  if (Endless()) LoopInProgramCode();
  payload.value = 1.f;
}

RT_PROGRAM void loop_closest_hit() {
  if (Endless()) LoopInProgramCode();
  payload.value = 1.f;
}

RT_PROGRAM void quick_closest_hit() { payload.value = 1.f; }

RT_PROGRAM void loop_intersect(int) {
  if (Endless()) LoopInProgramCode();
  if (rtPotentialIntersection(5.f)) rtReportIntersection(0);
}

RT_PROGRAM void quick_intersect(int) {
  if (rtPotentialIntersection(5.f)) rtReportIntersection(0);
}

RT_PROGRAM void unit_bounds(int, float box[6]) {
  box[0] = box[1] = box[2] = -1.f;
  box[3] = box[4] = box[5] = 1.f;
}

RT_PROGRAM void loop_bounds(int, float box[6]) {
  if (endless_at != -1) LoopInProgramCode();
  box[0] = box[1] = box[2] = -1.f;
  box[3] = box[4] = box[5] = 1.f;
}

// Prints without end: nearly all its time goes to formatting, in libc and the engine.
RT_PROGRAM void print_loop_raygen() {
  if (Endless()) {
    for (;;) rtPrintf("%100000d\n", 1);
  }
  result[launch_index] = 1.f;
}

// Throws and catches without end: most of its time goes to the C++ unwinder, some to its own
// arithmetic (without that, stopping it is a matter of chance: 0.6-7.6 s).
RT_PROGRAM void throw_loop_raygen() {
  if (Endless()) {
    volatile float x = 1.f;
    for (;;) {
      try {
        throw 1;
      } catch (int) {
      }
      for (int k = 0; k < 200; ++k) x = x * 0.5f + 1.f;
    }
  }
  result[launch_index] = 1.f;
}

// Loops inside a catch block; every index writes 1 only if its thread handles no exception (one
// the interrupted loop was handling must not stay active on the thread).
RT_PROGRAM void catch_loop_raygen() {
  if (Endless()) {
    try {
      throw 1;
    } catch (int) {
      LoopInProgramCode();
    }
  }
  result[launch_index] = std::current_exception() == nullptr ? 1.f : 0.f;
}

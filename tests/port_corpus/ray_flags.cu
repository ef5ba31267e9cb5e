// OptiX 6 ray flags and visibility masks: launch index i traces one ray straight through a row of
// spheres with mode i's (mask, flags), and records what ran.
#include <optix.h>
#include <optixu/optixu_math_namespace.h>

using namespace optix;

struct FlagsPayload {
  int closest_hits;
  int any_hits;
  int misses;
  float t;
};

rtDeclareVariable(rtObject, top_object, , );
rtDeclareVariable(unsigned int, index, rtLaunchIndex, );
rtDeclareVariable(FlagsPayload, payload, rtPayload, );
rtDeclareVariable(float, t_hit, rtIntersectionDistance, );
rtBuffer<int4> flags_result;  // closest hits, any hits, misses, mode
rtBuffer<float> flags_t;      // t of the hit shaded, or -1
rtBuffer<uint2> flags_modes;  // per launch index: mask, flags

RT_PROGRAM void trace_modes() {
  const uint2 mode = flags_modes[index];
  FlagsPayload p = {0, 0, 0, -1.0f};
  const optix::Ray ray =
      make_Ray(make_float3(0.0f, 0.0f, 0.0f), make_float3(0.0f, 0.0f, 1.0f), 0, 0.0f, 100.0f);
  if (mode.x == RT_VISIBILITY_ALL && mode.y == RT_RAY_FLAG_NONE) {
    rtTrace(top_object, ray, p);
  } else {
    rtTrace(top_object, ray, p, mode.x, static_cast<RTrayflags>(mode.y));
  }
  flags_result[index] = make_int4(p.closest_hits, p.any_hits, p.misses, static_cast<int>(index));
  flags_t[index] = p.t;
}

RT_PROGRAM void closest_hit() {
  payload.closest_hits += 1;
  payload.t = t_hit;
}
RT_PROGRAM void any_hit() { payload.any_hits += 1; }
RT_PROGRAM void miss() { payload.misses += 1; }

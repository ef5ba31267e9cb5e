// Programs that end the worker process running them, for crash_report_test.cc: a recursion
// without end, whose stack overflows, and exit()/quick_exit(), in program kinds that run on
// different threads of a worker (ray generation on the threads that run tiles, bounding box
// programs on the threads that build accelerations). Each strikes at one launch index or
// primitive; the others work, on the e2e scene's buffers.
#include <optix_world.h>

#include <cstdlib>

using namespace optix;

rtDeclareVariable(uint2, launch_index, rtLaunchIndex, );
rtBuffer<float4, 1> spheres;  // INPUT: center, radius
rtBuffer<float4, 2> image;    // OUTPUT
// How deep Descend goes: deeper than any stack unless the host says otherwise, and read at run
// time, so that the compiler cannot bound the recursion.
rtDeclareVariable(unsigned int, recursion_limit, , ) = 0xFFFFFFFFu;

namespace {

// A 4 KiB frame the compiler must keep (volatile) and work after the call: not a tail call, so
// neither a loop nor removable.
__attribute__((noinline)) unsigned Descend(unsigned depth) {
  volatile unsigned char frame[4096];
  frame[depth % sizeof(frame)] = static_cast<unsigned char>(depth);
  if (depth >= recursion_limit) return frame[0];
  return Descend(depth + 1) + frame[(depth * 7u) % sizeof(frame)];
}

void Bounds(int prim, float result[6]) {
  const float4 s = spheres[prim];
  result[0] = s.x - s.w;
  result[1] = s.y - s.w;
  result[2] = s.z - s.w;
  result[3] = s.x + s.w;
  result[4] = s.y + s.w;
  result[5] = s.z + s.w;
}

}  // namespace

RT_PROGRAM void render_overflow() {
  float depth = 0.f;
  if (launch_index.x == 5 && launch_index.y == 5) depth = static_cast<float>(Descend(0));
  image[launch_index] = make_float4(depth);
}

RT_PROGRAM void render_quick_exit() {
  if (launch_index.x == 5 && launch_index.y == 5) std::quick_exit(4);
  image[launch_index] = make_float4(1.f);
}

RT_PROGRAM void bounds_overflow(int prim, float result[6]) {
  Bounds(prim, result);
  if (prim == 12) result[0] -= static_cast<float>(Descend(0));
}

RT_PROGRAM void bounds_exit(int prim, float result[6]) {
  Bounds(prim, result);
  if (prim == 12) std::exit(5);
}

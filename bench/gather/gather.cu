// Ray generation programs of the gather benchmark: no rays at all, so a launch costs what moving
// its output costs. write_output fills every element of a float4 OUTPUT buffer with values the
// host can check; write_nothing is the same launch with nothing to gather.
#include <optix.h>
#include <optixu/optixu_math_namespace.h>

using namespace optix;

rtDeclareVariable(uint2, launch_index, rtLaunchIndex, );
rtBuffer<float4, 2> output_buffer;

// Exact in float for launch sizes up to 2^24 per dimension.
RT_PROGRAM void write_output() {
  output_buffer[launch_index] = make_float4(static_cast<float>(launch_index.x),
                                            static_cast<float>(launch_index.y), 0.5f, 1.f);
}

RT_PROGRAM void write_nothing() {}

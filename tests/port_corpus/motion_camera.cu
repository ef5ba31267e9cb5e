// A camera that moves while the shutter is open, in the style of the OptiX SDK's motion-blur
// samples: each sample takes a time in [time_begin, time_end] from the per-pixel random sequence
// (tea and rnd of the shared header), puts the eye at that time on its path from eye_begin
// (time 0) to eye_end (time 1), and traces with the time; the samples' average goes to an
// accumulation buffer and, as bytes, to the output buffer.
#include <optix.h>
#include <optixu/optixu_math_namespace.h>

#include "sample_common.h"

using namespace optix;

rtDeclareVariable(float3, eye_begin, , );
rtDeclareVariable(float3, eye_end, , );
rtDeclareVariable(float3, U, , );
rtDeclareVariable(float3, V, , );
rtDeclareVariable(float3, W, , );
rtDeclareVariable(float, time_begin, , );
rtDeclareVariable(float, time_end, , );
rtDeclareVariable(unsigned int, frame, , );
rtDeclareVariable(unsigned int, samples_per_launch, , ) = 4u;
rtDeclareVariable(float, scene_epsilon, , );
rtDeclareVariable(rtObject, top_object, , );
rtDeclareVariable(unsigned int, radiance_ray_type, , );

rtDeclareVariable(uint2, launch_index, rtLaunchIndex, );
rtBuffer<float4, 2> accum_buffer;
rtBuffer<uchar4, 2> output_buffer;

RT_PROGRAM void motion_camera() {
  size_t2 screen = output_buffer.size();
  unsigned int seed = tea<16>(screen.x * launch_index.y + launch_index.x, frame);

  float2 d = make_float2(launch_index) / make_float2(screen) * 2.f - 1.f;
  float3 ray_direction = normalize(d.x * U + d.y * V + W);

  float3 result = make_float3(0.0f);
  for (unsigned int i = 0; i < samples_per_launch; ++i) {
    const float ray_time = time_begin + (time_end - time_begin) * rnd(seed);
    const float3 ray_origin = lerp(eye_begin, eye_end, ray_time);
    optix::Ray ray(ray_origin, ray_direction, radiance_ray_type, scene_epsilon);

    PerRayData_radiance prd;
    prd.importance = 1.f;
    prd.depth = 0;
    rtTrace(top_object, ray, ray_time, prd);
    result += prd.result;
  }
  result = result / static_cast<float>(samples_per_launch);

  accum_buffer[launch_index] = make_float4(result, 1.0f);
  output_buffer[launch_index] = make_color(result);
}

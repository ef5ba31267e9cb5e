// A pinhole camera in the style of the OptiX SDK's pinhole_camera.cu: optix_world.h, a shared
// sutil-style header, the launch index named `index` (glibc's index() must not get in the way),
// OptiX 6's rtTrace with a time, a mask and ray flags, and make_color from the shared header.
#include <optix_world.h>

#include "sample_common.h"

using namespace optix;

rtDeclareVariable(float3, eye, , );
rtDeclareVariable(float3, U, , );
rtDeclareVariable(float3, V, , );
rtDeclareVariable(float3, W, , );
rtDeclareVariable(float3, bad_color, , );
rtDeclareVariable(float, scene_epsilon, , );
rtBuffer<uchar4, 2> output_buffer;
rtDeclareVariable(rtObject, top_object, , );
rtDeclareVariable(unsigned int, radiance_ray_type, , );

rtDeclareVariable(uint2, index, rtLaunchIndex, );
rtDeclareVariable(uint2, launch_dim, rtLaunchDim, );
rtDeclareVariable(float, time, , ) = 0.25f;  // glibc's time() must not get in the way either

RT_PROGRAM void pinhole_camera() {
  size_t2 screen = output_buffer.size();
  float2 d = make_float2(index) / make_float2(screen) * 2.f - 1.f;
  float3 ray_origin = eye;
  float3 ray_direction = normalize(d.x * U + d.y * V + W);

  optix::Ray ray =
      optix::make_Ray(ray_origin, ray_direction, radiance_ray_type, scene_epsilon, RT_DEFAULT_MAX);

  PerRayData_radiance prd;
  prd.importance = 1.f;
  prd.depth = 0;

  rtTrace(top_object, ray, time, prd, RT_VISIBILITY_ALL, RT_RAY_FLAG_DISABLE_ANYHIT);

  output_buffer[index] = make_color(prd.result);
}

RT_PROGRAM void exception() {
  const unsigned int code = rtGetExceptionCode();
  rtPrintf("Caught exception 0x%X at launch index (%d,%d)\n", code, index.x, index.y);
  output_buffer[index] = make_color(bad_color);
}

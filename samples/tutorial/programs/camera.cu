// Ray generation and exception programs of the tutorial (pinhole camera).
#include "tutorial.h"

rtDeclareVariable(float3, eye, , );
rtDeclareVariable(float3, U, , );
rtDeclareVariable(float3, V, , );
rtDeclareVariable(float3, W, , );
rtDeclareVariable(float3, bad_color, , );
rtDeclareVariable(float, scene_epsilon, , );
rtDeclareVariable(rtObject, top_object, , );
rtDeclareVariable(unsigned int, radiance_ray_type, , );
rtDeclareVariable(uint2, launch_index, rtLaunchIndex, );

// float4 rather than the SDK's uchar4: the host writes EXR without losing range, and tests can
// see NaNs. Row 0 is the bottom of the image, as in OptiX.
rtBuffer<float4, 2> output_buffer;

RT_PROGRAM void pinhole_camera() {
  size_t2 screen = output_buffer.size();

  // OptiX's make_float2(size_t2) is missing from Tessera's headers: convert by hand.
  float2 d = make_float2(launch_index) /
                 make_float2(static_cast<float>(screen.x), static_cast<float>(screen.y)) * 2.f -
             1.f;
  float3 ray_origin = eye;
  float3 ray_direction = normalize(d.x * U + d.y * V + W);

  optix::Ray ray =
      optix::make_Ray(ray_origin, ray_direction, radiance_ray_type, scene_epsilon, RT_DEFAULT_MAX);

  PerRayData_radiance prd;
  prd.importance = 1.f;
  prd.depth = 0;

  rtTrace(top_object, ray, prd);

  output_buffer[launch_index] = make_float4(prd.result.x, prd.result.y, prd.result.z, 1.f);
}

RT_PROGRAM void exception() {
  rtPrintExceptionDetails();
  output_buffer[launch_index] = make_float4(bad_color.x, bad_color.y, bad_color.z, 1.f);
}

// Tutorial step 11: an environment camera, the whole sphere of directions around the eye as a
// latitude-longitude image (x: azimuth around V, y: from straight down to straight up).
RT_PROGRAM void env_camera() {
  size_t2 screen = output_buffer.size();
  float2 d = make_float2(launch_index) /
                 make_float2(static_cast<float>(screen.x), static_cast<float>(screen.y)) *
                 make_float2(2.0f * M_PIf, M_PIf) +
             make_float2(M_PIf, 0.0f);
  float3 angle = make_float3(cosf(d.x) * sinf(d.y), -cosf(d.y), sinf(d.x) * sinf(d.y));
  float3 ray_origin = eye;
  float3 ray_direction =
      normalize(angle.x * normalize(U) + angle.y * normalize(V) + angle.z * normalize(W));

  optix::Ray ray =
      optix::make_Ray(ray_origin, ray_direction, radiance_ray_type, scene_epsilon, RT_DEFAULT_MAX);

  PerRayData_radiance prd;
  prd.importance = 1.f;
  prd.depth = 0;

  rtTrace(top_object, ray, prd);

  output_buffer[launch_index] = make_float4(prd.result.x, prd.result.y, prd.result.z, 1.f);
}

// Launch parameters and SBT data of the triangle sample, shared by host and programs.
#ifndef TESSERA_SAMPLES_OPTIX7_TRIANGLE_TRIANGLE_H_
#define TESSERA_SAMPLES_OPTIX7_TRIANGLE_TRIANGLE_H_

#include <optix.h>

struct Params {
  uchar4* image;
  unsigned int image_width;
  unsigned int image_height;
  float3 cam_eye;
  float3 cam_u, cam_v, cam_w;
  OptixTraversableHandle handle;
};

struct RayGenData {};
struct MissData {
  float3 bg_color;
};
struct HitGroupData {};

#endif  // TESSERA_SAMPLES_OPTIX7_TRIANGLE_TRIANGLE_H_

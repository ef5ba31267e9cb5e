// Launch parameters and SBT data of the multi-GPU sample.
#ifndef TESSERA_SAMPLES_OPTIX7_MULTI_GPU_MULTI_GPU_H_
#define TESSERA_SAMPLES_OPTIX7_MULTI_GPU_MULTI_GPU_H_

#include <optix.h>

enum RayType { kRadiance = 0, kShadow = 1, kRayTypeCount = 2 };
constexpr unsigned kMaxDevices = 16;

struct Params {
  uchar4* image;               // the launch's rows: row_offset and up, `width` pixels each
  unsigned int width, height;  // of the whole image
  unsigned int row_offset;     // the first image row this launch renders
  float3 eye, u, v, w;
  float3 light_direction;  // towards the light
  OptixTraversableHandle handle;
  // __raygen__gather: device i's rows share_row[i] .. share_row[i + 1] - 1 are in share[i], in
  // another device's memory (peer access).
  unsigned int shares;
  const uchar4* share[kMaxDevices];
  unsigned int share_row[kMaxDevices + 1];
};

struct MissData {
  float3 sky;
};
struct HitData {
  const float3* colors;   // per triangle
  const float3* normals;  // per triangle
};

#endif  // TESSERA_SAMPLES_OPTIX7_MULTI_GPU_MULTI_GPU_H_

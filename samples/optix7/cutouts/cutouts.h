// Launch parameters and SBT data of the cutouts sample.
#ifndef TESSERA_SAMPLES_OPTIX7_CUTOUTS_CUTOUTS_H_
#define TESSERA_SAMPLES_OPTIX7_CUTOUTS_CUTOUTS_H_

#include <optix.h>

enum RayType { kRadiance = 0, kShadow = 1, kRayTypeCount = 2 };

struct Params {
  uchar4* image;
  unsigned int width, height;
  float3 eye, u, v, w;
  float3 light_direction;
  OptixTraversableHandle handle;
  unsigned int* any_hit_calls;  // counted per pixel by the radiance any-hit program
};

struct HitData {
  float3 color;
  int cutout;  // 0: opaque; 1: a disc of holes
};

#endif  // TESSERA_SAMPLES_OPTIX7_CUTOUTS_CUTOUTS_H_

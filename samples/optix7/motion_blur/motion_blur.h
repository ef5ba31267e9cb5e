// Launch parameters and SBT data of the motion blur sample.
#ifndef TESSERA_SAMPLES_OPTIX7_MOTION_BLUR_MOTION_BLUR_H_
#define TESSERA_SAMPLES_OPTIX7_MOTION_BLUR_MOTION_BLUR_H_

#include <optix.h>

struct Params {
  float4* accum;  // summed colours, one per pixel
  uchar4* image;
  unsigned int width, height;
  unsigned int launch, launches, spp;  // this launch's index, how many, samples per launch
  float2 half_extent;                  // of the orthographic view, in world units
  OptixTraversableHandle handle;
};

struct HitData {
  float3 color;
};

#endif  // TESSERA_SAMPLES_OPTIX7_MOTION_BLUR_MOTION_BLUR_H_

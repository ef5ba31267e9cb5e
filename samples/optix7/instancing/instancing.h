// Launch parameters and SBT data of the instancing sample.
#ifndef TESSERA_SAMPLES_OPTIX7_INSTANCING_INSTANCING_H_
#define TESSERA_SAMPLES_OPTIX7_INSTANCING_INSTANCING_H_

#include <optix.h>

struct Params {
  uchar4* image;
  unsigned int width, height;
  float3 eye, u, v, w;
  OptixTraversableHandle handle;
};

struct HitData {
  float3 color;
};

#endif  // TESSERA_SAMPLES_OPTIX7_INSTANCING_INSTANCING_H_

// Launch parameters of the dynamic geometry sample.
#ifndef TESSERA_SAMPLES_OPTIX7_DYNAMIC_DYNAMIC_H_
#define TESSERA_SAMPLES_OPTIX7_DYNAMIC_DYNAMIC_H_

#include <optix.h>

struct Params {
  uchar4* image;          // the whole strip of frames
  unsigned int stride;    // pixels per image row
  unsigned int x_offset;  // where this frame's column starts
  unsigned int width, height;
  float3 eye, u, v, w;
  OptixTraversableHandle handle;
};

struct HitData {
  const float3* vertices;
  const uint3* indices;
};

#endif  // TESSERA_SAMPLES_OPTIX7_DYNAMIC_DYNAMIC_H_

// The light of the OptiX SDK's commonStructs.h: one struct that host code fills into a buffer of
// RT_FORMAT_USER elements and programs read as rtBuffer<BasicLight>, so both sides include it.
#pragma once

#include <optixu/optixu_vector_types.h>

struct BasicLight {
#if defined(__cplusplus)
  typedef optix::float3 float3;
#endif
  float3 pos;
  float3 color;
  int casts_shadow;
  int padding;  // 32 bytes, as the SDK pads it
};

static_assert(sizeof(BasicLight) == 32, "the layout host code fills");

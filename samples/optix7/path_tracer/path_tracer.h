// Launch parameters and SBT data of the path tracer sample (a Cornell box).
#ifndef TESSERA_SAMPLES_OPTIX7_PATH_TRACER_PATH_TRACER_H_
#define TESSERA_SAMPLES_OPTIX7_PATH_TRACER_PATH_TRACER_H_

#include <optix.h>

enum RayType { kRadiance = 0, kOcclusion = 1, kRayTypeCount = 2 };
// Direct callables, by SBT callable record: how a material scatters.
enum Bsdf { kLambert = 0, kGlossy = 1 };

struct Light {
  float3 corner, v1, v2;  // a parallelogram: corner + a*v1 + b*v2, a, b in [0, 1]
  float3 normal;
  float3 emission;
};

struct Params {
  unsigned int subframe_index;
  unsigned int samples_per_launch;
  unsigned int max_depth;
  float4* accum;
  uchar4* image;
  unsigned int width, height;
  float3 eye, u, v, w;
  Light light;
  OptixTraversableHandle handle;
};

struct HitData {
  float3 albedo;
  float3 emission;
  unsigned int bsdf;  // Bsdf: the direct callable that samples the next direction
  const float3* vertices;
};

#endif  // TESSERA_SAMPLES_OPTIX7_PATH_TRACER_PATH_TRACER_H_

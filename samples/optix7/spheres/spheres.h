// Launch parameters and SBT data of the spheres sample (custom primitives).
#ifndef TESSERA_SAMPLES_OPTIX7_SPHERES_SPHERES_H_
#define TESSERA_SAMPLES_OPTIX7_SPHERES_SPHERES_H_

#include <optix.h>

enum RayType { kRadiance = 0, kShadow = 1, kRayTypeCount = 2 };

struct Sphere {
  float3 center;
  float radius;
  float3 color;
};

struct Params {
  uchar4* image;
  unsigned int width, height;
  float3 eye, u, v, w;
  float3 light_direction;  // towards the light
  OptixTraversableHandle handle;
};

struct MissData {
  float3 sky;
};
struct HitData {
  const Sphere* spheres;
};

#endif  // TESSERA_SAMPLES_OPTIX7_SPHERES_SPHERES_H_

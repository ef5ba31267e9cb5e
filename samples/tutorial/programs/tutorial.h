// Program-side helpers shared by the tutorial's program modules (the SDK's tutorial.h).
#ifndef TESSERA_SAMPLES_TUTORIAL_PROGRAMS_TUTORIAL_H_
#define TESSERA_SAMPLES_TUTORIAL_PROGRAMS_TUTORIAL_H_

#include <optix.h>
#include <optixu/optixu_math_namespace.h>

#include "common_structs.h"

using namespace optix;

// Payload of radiance rays (ray type 0).
struct PerRayData_radiance {
  float3 result;
  float importance;
  int depth;
};

// Payload of shadow rays (ray type 1): how much light gets through.
struct PerRayData_shadow {
  float3 attenuation;
};

static __device__ __inline__ float step(float min, float value) { return value < min ? 0 : 1; }

static __device__ __inline__ float3 mix(float3 a, float3 b, float x) { return a * (1 - x) + b * x; }

// OptiX 3's optixu_math_namespace.h has fresnel_schlick; Tessera's does not (yet), so the
// tutorial carries its own. Calls are qualified, so a later header version cannot make them
// ambiguous.
namespace tutorial {

// Schlick's approximation: `minimum` at normal incidence (cos_theta == 1) rising to `maximum`
// at grazing incidence.
static __device__ __inline__ float fresnel_schlick(float cos_theta, float exponent = 5.0f,
                                                   float minimum = 0.0f, float maximum = 1.0f) {
  return clamp(minimum + (maximum - minimum) * powf(fmaxf(0.0f, 1.0f - cos_theta), exponent),
               minimum, maximum);
}

static __device__ __inline__ float3 fresnel_schlick(float cos_theta, float exponent,
                                                    const float3& minimum, const float3& maximum) {
  return make_float3(fresnel_schlick(cos_theta, exponent, minimum.x, maximum.x),
                     fresnel_schlick(cos_theta, exponent, minimum.y, maximum.y),
                     fresnel_schlick(cos_theta, exponent, minimum.z, maximum.z));
}

}  // namespace tutorial

// Schlick's approximation per color channel, with reflectance `rgb` at normal incidence.
static __device__ __inline__ float3 schlick(float nDi, const float3& rgb) {
  float r = tutorial::fresnel_schlick(nDi, 5, rgb.x, 1);
  float g = tutorial::fresnel_schlick(nDi, 5, rgb.y, 1);
  float b = tutorial::fresnel_schlick(nDi, 5, rgb.z, 1);
  return make_float3(r, g, b);
}

#endif  // TESSERA_SAMPLES_TUTORIAL_PROGRAMS_TUTORIAL_H_

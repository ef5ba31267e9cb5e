// 3D noise for the rusty metal of tutorial step 8, as the SDK tutorial computes it: a 64^3
// texture of random values in [0, 1) (made by the host, render.cc) read with trilinear filtering
// and repeat wrapping, scaled to [-2, 2].
#ifndef TESSERA_SAMPLES_TUTORIAL_PROGRAMS_NOISE_H_
#define TESSERA_SAMPLES_TUTORIAL_PROGRAMS_NOISE_H_

#include <optix.h>
#include <optixu/optixu_math_namespace.h>

rtTextureSampler<float, 3> noise_texture;

// Signed noise in [-2, 2].
static __device__ __inline__ float snoise(float3 p) {
  return tex3D(noise_texture, p.x, p.y, p.z) * 4.0f - 2.0f;
}

#endif  // TESSERA_SAMPLES_TUTORIAL_PROGRAMS_NOISE_H_

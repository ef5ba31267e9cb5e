// Procedural 3D noise for the rusty metal of tutorial step 8. The SDK samples a 64^3 texture of
// random values with trilinear filtering (tex3D(...) * 4 - 2); textures are not available yet,
// so this hashes the lattice instead and interpolates the same way.
#ifndef TESSERA_SAMPLES_TUTORIAL_PROGRAMS_NOISE_H_
#define TESSERA_SAMPLES_TUTORIAL_PROGRAMS_NOISE_H_

#include <optixu/optixu_math_namespace.h>

#include <cmath>

// Texels per unit of noise space, as the SDK's noise texture (64^3, normalized coordinates).
static const float kNoiseLatticeScale = 64.0f;

// A random value in [0, 1) for a lattice point (integer hash; wraps like a repeating texture).
static __device__ __inline__ float lattice_value(int x, int y, int z) {
  unsigned int h = static_cast<unsigned int>(x) * 0x8da6b343u ^
                   static_cast<unsigned int>(y) * 0xd8163841u ^
                   static_cast<unsigned int>(z) * 0xcb1ab31fu;
  h ^= h >> 16;
  h *= 0x7feb352du;
  h ^= h >> 15;
  h *= 0x846ca68bu;
  h ^= h >> 16;
  return static_cast<float>(h >> 8) * (1.0f / 16777216.0f);
}

// Signed noise in [-2, 2]: trilinear interpolation of lattice values, as a filtered texture.
static __device__ __inline__ float snoise(float3 p) {
  p *= kNoiseLatticeScale;
  // Texel centers sit at half-integer coordinates in a filtered texture.
  float fx = p.x - 0.5f, fy = p.y - 0.5f, fz = p.z - 0.5f;
  float ix = floorf(fx), iy = floorf(fy), iz = floorf(fz);
  float tx = fx - ix, ty = fy - iy, tz = fz - iz;
  int x = static_cast<int>(ix), y = static_cast<int>(iy), z = static_cast<int>(iz);

  float c00 = lerp(lattice_value(x, y, z), lattice_value(x + 1, y, z), tx);
  float c10 = lerp(lattice_value(x, y + 1, z), lattice_value(x + 1, y + 1, z), tx);
  float c01 = lerp(lattice_value(x, y, z + 1), lattice_value(x + 1, y, z + 1), tx);
  float c11 = lerp(lattice_value(x, y + 1, z + 1), lattice_value(x + 1, y + 1, z + 1), tx);
  float value = lerp(lerp(c00, c10, ty), lerp(c01, c11, ty), tz);
  return value * 4.0f - 2.0f;
}

#endif  // TESSERA_SAMPLES_TUTORIAL_PROGRAMS_NOISE_H_

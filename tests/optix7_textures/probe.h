// Launch parameters of the texture probe (probe.cu, main.cc): one lookup per launch index, its
// result's bits written out for the host to compare with the OptiX 3 sampler's.
#ifndef TESSERA_TESTS_OPTIX7_TEXTURES_PROBE_H_
#define TESSERA_TESTS_OPTIX7_TEXTURES_PROBE_H_

#include <optix.h>
#include <texture_types.h>

#include "probe_ops.h"

struct Probe {
  cudaTextureObject_t texture;
  unsigned op;
  unsigned result;
  float x, y, z, level;
  int layer, comp;
  float2 ddx, ddy;
};

struct Params {
  const Probe* probes;
  unsigned count;
  uint4* out;  // each result's components as bits, unused ones 0
};

#endif  // TESSERA_TESTS_OPTIX7_TEXTURES_PROBE_H_

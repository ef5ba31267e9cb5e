// Launch parameters of the OptiX 7 eyelight benchmark (eyelight7.cu).
#ifndef TESSERA_BENCH_OPTIX7_EYELIGHT7_H_
#define TESSERA_BENCH_OPTIX7_EYELIGHT7_H_

#include <optix.h>

struct EyelightParams {
  uchar4* image;  // row 0 at the bottom
  unsigned int width, height;
  float3 eye, u, v, w;
  OptixTraversableHandle handle;
  const float3* vertices;
  const int3* indices;
};

// What the bytes benchmark's programs write: `count` words of `words`, every `stride`-th.
struct WriteParams {
  unsigned int* words;
  unsigned int stride;
  unsigned int value;
};

#endif  // TESSERA_BENCH_OPTIX7_EYELIGHT7_H_

// Launch parameters of the exceptions sample.
#ifndef TESSERA_SAMPLES_OPTIX7_EXCEPTIONS_EXCEPTIONS_H_
#define TESSERA_SAMPLES_OPTIX7_EXCEPTIONS_EXCEPTIONS_H_

#include <optix.h>

// The user exception code raygen throws (user codes are 0..2^30-1).
constexpr int kUserCode = 42;

struct Params {
  uchar4* image;
  unsigned int width, height;
  OptixTraversableHandle handle;
  // Per pixel: the exception code the exception program saw (0: none) and its first detail.
  int* codes;
  unsigned int* details;
};

#endif  // TESSERA_SAMPLES_OPTIX7_EXCEPTIONS_EXCEPTIONS_H_

// Launch parameters of optix7_fault_programs.cu.
#ifndef TESSERA_TESTS_E2E_OPTIX7_FAULT_PARAMS_H_
#define TESSERA_TESTS_E2E_OPTIX7_FAULT_PARAMS_H_

#include <optix.h>

struct FaultParams {
  uchar4* image;
  const unsigned int* noise;
  unsigned int noise_words;
  unsigned int width;
  unsigned int iterations;
  unsigned int seed;
};

#endif  // TESSERA_TESTS_E2E_OPTIX7_FAULT_PARAMS_H_

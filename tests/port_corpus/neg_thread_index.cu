// Must not compile: CUDA's thread model in an OptiX program (the ctest checks the message).
#include <optix.h>

rtBuffer<float, 1> out;

RT_PROGRAM void kernel_style() {
  const unsigned i = threadIdx.x + blockIdx.x * blockDim.x;
  out[i] = 1.0f;
}

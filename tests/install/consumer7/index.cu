// Writes each launch index's linear number, plus a value from its SBT record, into params.out.
#include <optix.h>

struct Params {
  unsigned int* out;
  unsigned int width;
};
extern "C" {
__constant__ Params params;
}

extern "C" __global__ void __raygen__index() {
  const uint3 i = optixGetLaunchIndex();
  const unsigned int add = *reinterpret_cast<const unsigned int*>(optixGetSbtDataPointer());
  params.out[i.y * params.width + i.x] = i.y * params.width + i.x + add;
}

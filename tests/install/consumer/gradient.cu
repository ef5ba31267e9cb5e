// Built ahead of time by tessera_add_program_module: each launch index writes its own code.
#include <optix.h>
#include <optixu/optixu_math_namespace.h>

using namespace optix;

rtDeclareVariable(uint2, launch_index, rtLaunchIndex, );
rtDeclareVariable(uint2, launch_dim, rtLaunchDim, );
rtBuffer<unsigned int, 2> output;

RT_PROGRAM void gradient() {
  output[launch_index] = launch_index.y * launch_dim.x + launch_index.x;
}

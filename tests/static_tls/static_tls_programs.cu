// Programs of the static TLS tests (tests/static_tls): module variables, which are initial-exec
// thread-locals in the module's second build and local-dynamic in the first.
#include <optix_world.h>

using namespace optix;

rtDeclareVariable(uint2, launch_index, rtLaunchIndex, );
rtDeclareVariable(float, scale, , );
rtBuffer<float, 2> values;

RT_PROGRAM void write_values() {
  values[launch_index] = scale * static_cast<float>(launch_index.x + 100 * launch_index.y);
}

// A module whose thread-locals need more static TLS than a worker reserves for modules
// (tessera/worker/static_tls.h): its initial-exec build cannot be loaded, so devices load the
// module itself. The scratch array is a thread-local the program really uses.
#include <optix_world.h>

using namespace optix;

rtDeclareVariable(uint2, launch_index, rtLaunchIndex, );
rtDeclareVariable(float, scale, , );
rtBuffer<float, 2> values;

namespace {
constexpr unsigned kCells = 1u << 15;  // 128 KiB
struct Scratch {
  float cells[kCells];
};
thread_local TESSERA_TLS Scratch scratch;
}  // namespace

RT_PROGRAM void write_through_scratch() {
  const unsigned cell = (launch_index.x * 7919u + launch_index.y * 104729u) % kCells;
  // Through a volatile cell, so that the compiler keeps the array rather than the value.
  volatile float* at = &scratch.cells[cell];
  *at = scale * static_cast<float>(launch_index.x + 100 * launch_index.y);
  values[launch_index] = *at + 1.0f;
}

// Programs for the fault tests: slow work whose result depends only on the launch index (a launch
// that lost a device must give the bits of one that did not), and one that crashes the process
// running it.
#include <optix_world.h>

using namespace optix;

rtDeclareVariable(uint2, index2, rtLaunchIndex, );
rtDeclareVariable(unsigned int, iterations, , );
// 0: read from the host, so that the compiler cannot see the null pointer coming.
rtDeclareVariable(unsigned int, bad_address, , );

rtBuffer<unsigned int, 2> hashes;  // OUTPUT

// A chain of `iterations` dependent steps per launch index.
RT_PROGRAM void slow_hash() {
  unsigned int h = index2.x * 73856093u ^ index2.y * 19349663u;
  for (unsigned int i = 0; i < iterations; ++i) h = (h * 1664525u + 1013904223u) ^ (h >> 13);
  hashes[index2] = h;
}

// Writes through a null pointer at launch index (5, 5): SIGSEGV in whichever worker runs it.
// no_sanitize: built with UBSan (tools/sanitize.sh), the null store would end the worker with
// UBSan's report and SIGABRT instead of the SIGSEGV under test.
RT_PROGRAM __attribute__((no_sanitize("undefined"))) void crash_at_5_5() {
  if (index2.x == 5 && index2.y == 5) {
    *reinterpret_cast<volatile int*>(static_cast<size_t>(bad_address)) = 1;
  }
  hashes[index2] = 1u;
}

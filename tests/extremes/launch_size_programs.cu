// A launch of any size that writes one byte per launch index (edge_cases_test.cc, launch sizes).
#include <optix.h>

rtBuffer<unsigned char, 2> bytes;
rtDeclareVariable(uint2, launch_index, rtLaunchIndex, );

RT_PROGRAM void write_byte() {
  bytes[launch_index] = static_cast<unsigned char>((launch_index.x ^ launch_index.y) & 0xFFu);
}

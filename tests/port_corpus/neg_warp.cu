// Must not compile: a warp vote in an OptiX program (the ctest checks the message).
#include <optix.h>

rtBuffer<unsigned int, 1> out;
rtDeclareVariable(unsigned int, launch_index, rtLaunchIndex, );

RT_PROGRAM void vote() { out[launch_index] = __ballot_sync(0xFFFFFFFFu, launch_index & 1u); }

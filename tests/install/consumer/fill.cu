// Handed to rtProgramCreateFromPTXString as source text: libtessera compiles it at run time
// against the installed headers. install_test.sh adds installed_marker.h to the installed include
// root only, so this compiles only if libtessera found its own headers (not a source tree's).
#include <installed_marker.h>
#include <optix.h>

rtDeclareVariable(uint2, launch_index, rtLaunchIndex, );
rtDeclareVariable(unsigned int, value, , );
rtBuffer<unsigned int, 2> output;

RT_PROGRAM void fill() { output[launch_index] = value + launch_index.x; }

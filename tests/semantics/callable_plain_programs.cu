// A closest-hit program whose module declares no semantic variables (callable_test.cc): a
// callable program of another module still sees the hit's distance, attributes and payload, from
// the engine, and its payload writes come back.
#include <optix.h>

rtCallableProgram(void, shade_hit, ());

RT_PROGRAM void ch_plain() { shade_hit(); }

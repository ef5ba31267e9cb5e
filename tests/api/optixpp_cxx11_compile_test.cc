// OptiXpp compiles as C++11 (applications of the OptiX 3 era were built so); the program-side
// headers need C++17 and are not included here.
#include <optixu/optixpp.h>
#include <optixu/optixpp_namespace.h>

int main() {
  optix::Context context;  // a null handle: nothing to create for a compile check
  return context ? 1 : 0;
}

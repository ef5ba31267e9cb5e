/* OptiX compatibility: the host API (tessera/rt.h) everywhere, and, in C++ compiled as a program
 * module (__CUDACC__ defined, as nvcc defines it), the program-side API (tessera/device.h) too:
 * OptiX's optix.h includes optix_device.h only under __CUDACC__. So a header shared by a .cu and a
 * host .cpp (a PerRayData.h with `#ifdef __CUDACC__` helpers, optixu_math_namespace.h) compiles as
 * host code in the .cpp. Program modules are compiled with -D__CUDACC__ (README, "Writing
 * programs"; docs/programs.md says which other CUDA macros Tessera defines and why). */
#ifndef TESSERA_OPTIX_H_
#define TESSERA_OPTIX_H_

// clang-format off: before every other #include (see there)
#include "tessera/detail/program_prelude.h"
// clang-format on
#include "tessera/rt.h"

/* OptiX marks functions shared by host and program code with it; here both are plain C++. */
#ifndef RT_HOSTDEVICE
#define RT_HOSTDEVICE
#endif

#if defined(__cplusplus) && defined(__CUDACC__)
#include "tessera/device.h"
#elif defined(__cplusplus) && !defined(TESSERA_DEVICE_H_)
/* Host code: a program's declarations here mean the module was compiled without -D__CUDACC__.
 * Say so where they are, instead of "'rtDeclareVariable' was not declared". */
namespace tessera_host_code {
template <typename T>
inline constexpr bool kProgramSideApi = sizeof(T) == 0;
template <typename T, int Dim = 1>
struct ProgramSideBuffer {
  static_assert(kProgramSideApi<T>,
                "rtBuffer is program-side API: optix.h gives it only with __CUDACC__ defined; "
                "compile program modules with -D__CUDACC__ (README, \"Writing programs\")");
};
}  // namespace tessera_host_code
#define rtDeclareVariable(type, name, semantic, annotation)                                     \
  static_assert(::tessera_host_code::kProgramSideApi<type>,                                     \
                "rtDeclareVariable is program-side API: optix.h gives it only with __CUDACC__ " \
                "defined; compile program modules with -D__CUDACC__ (README, \"Writing "        \
                "programs\")");                                                                 \
  extern type name
#define rtBuffer ::tessera_host_code::ProgramSideBuffer
#endif
#endif

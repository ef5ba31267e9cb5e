// OptiX 3 ships the vector math twice, in namespace optix and without a namespace. Here the
// functions live in the global namespace and are re-exported into optix, so one header serves
// both spellings.
#ifndef OPTIXU_OPTIXU_MATH_H_
#define OPTIXU_OPTIXU_MATH_H_

// clang-format off: before every other #include (see there)
#include "../tessera/detail/program_prelude.h"
// clang-format on

#include "optixu_math_namespace.h"

#endif  // OPTIXU_OPTIXU_MATH_H_

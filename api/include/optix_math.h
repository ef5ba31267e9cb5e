/* OptiX compatibility: the deprecated top-level name of the vector math header, which OptiX
 * 3-era programs still include (`#include <optix_math.h>`). */
#ifndef TESSERA_OPTIX_MATH_H_
#define TESSERA_OPTIX_MATH_H_

// clang-format off: before every other #include (see there)
#include "tessera/detail/program_prelude.h"
// clang-format on

#include "optixu/optixu_math.h"
#endif

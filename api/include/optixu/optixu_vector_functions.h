// OptiX 3 declares the make_<type>() constructors in this header; here they live beside the
// types themselves, so it only forwards.
#ifndef OPTIXU_OPTIXU_VECTOR_FUNCTIONS_H_
#define OPTIXU_OPTIXU_VECTOR_FUNCTIONS_H_

// clang-format off: before every other #include (see there)
#include "../tessera/detail/program_prelude.h"
// clang-format on

#include "optixu_vector_types.h"

#endif  // OPTIXU_OPTIXU_VECTOR_FUNCTIONS_H_

// OptiX 3 ships the stream operators twice, in namespace optix and without a namespace. Here they
// live beside the types (global) and in optix, so one header serves both spellings.
#ifndef OPTIXU_OPTIXU_MATH_STREAM_H_
#define OPTIXU_OPTIXU_MATH_STREAM_H_

// clang-format off: before every other #include (see there)
#include "../tessera/detail/program_prelude.h"
// clang-format on

#include "optixu_math_stream_namespace.h"

#endif  // OPTIXU_OPTIXU_MATH_STREAM_H_

// OptiX 3 declares the make_<type>() constructors in this header; here they live beside the
// types themselves, so it only forwards.
#ifndef OPTIXU_OPTIXU_VECTOR_FUNCTIONS_H_
#define OPTIXU_OPTIXU_VECTOR_FUNCTIONS_H_

#include "optixu_vector_types.h"

#endif  // OPTIXU_OPTIXU_VECTOR_FUNCTIONS_H_

/* OptiX compatibility: everything optix.h gives (the program-side API only under __CUDACC__),
 * the optixu helpers, and in host C++ code OptiXpp, as OptiX's optix_world.h includes
 * optixpp_namespace.h for host code. */
#ifndef TESSERA_OPTIX_WORLD_H_
#define TESSERA_OPTIX_WORLD_H_
#include "optix.h"
#ifdef __cplusplus
#include "optixu/optixu_aabb_namespace.h"
#include "optixu/optixu_math_namespace.h"
#include "optixu/optixu_math_stream_namespace.h"
#include "optixu/optixu_matrix_namespace.h"
#include "optixu/optixu_vector_functions.h"
#include "optixu/optixu_vector_types.h"
#ifndef __CUDACC__
#include "optixu/optixpp_namespace.h"
#endif
#endif
#endif

/* OptiX compatibility: everything optix.h gives plus the optixu helpers. */
#ifndef TESSERA_OPTIX_WORLD_H_
#define TESSERA_OPTIX_WORLD_H_
#include "optix.h"
#ifdef __cplusplus
#include "optixu/optixu_aabb_namespace.h"
#include "optixu/optixu_math_namespace.h"
#include "optixu/optixu_matrix_namespace.h"
#include "optixu/optixu_vector_types.h"
#endif
#endif

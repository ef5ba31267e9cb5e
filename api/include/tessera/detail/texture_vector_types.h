// The vector types (float2, float4, uchar4, ...) that the shared sampling headers
// (api/include_common/tessera/detail/texture_*.h) return and take, from this include root: OptiX
// 3's optixu_vector_types.h. The OptiX 7 root has a header of this name that gives CUDA's
// vector_types.h; both declare the same global types with the same layouts.
#ifndef TESSERA_DETAIL_TEXTURE_VECTOR_TYPES_H_
#define TESSERA_DETAIL_TEXTURE_VECTOR_TYPES_H_

#include "optixu/optixu_vector_types.h"

#endif  // TESSERA_DETAIL_TEXTURE_VECTOR_TYPES_H_

// The exceptions sample's programs. Pixels of the left third throw a user exception carrying
// their x and y; pixels of the middle third trace a ray whose closest-hit program traces again
// and again, past the pipeline's maximum trace depth; the right third renders normally. The
// exception program records what it caught.
#include <optix.h>

#include "../common/vec_math.h"
#include "exceptions.h"

extern "C" {
__constant__ Params params;
}

extern "C" __global__ void __raygen__rg() {
  const uint3 idx = optixGetLaunchIndex();
  const unsigned int pixel = idx.y * params.width + idx.x;
  params.codes[pixel] = 0;
  params.details[pixel] = 0;
  if (idx.x < params.width / 3) {
    optixThrowException(kUserCode, idx.x, idx.y);
  }
  unsigned int depth = 0;
  unsigned int recurse = idx.x < 2 * params.width / 3 ? 1u : 0u;
  optixTrace(params.handle, make_float3(0.0f, 0.0f, 1.0f), make_float3(0.0f, 0.0f, -1.0f), 0.0f,
             1e16f, 0.0f, OptixVisibilityMask(255), OPTIX_RAY_FLAG_NONE, 0, 1, 0, depth, recurse);
  params.image[pixel] = make_uchar4(0, static_cast<unsigned char>(40 * depth), 0, 255);
}

extern "C" __global__ void __closesthit__again() {
  const unsigned int depth = optixGetPayload_0() + 1;
  optixSetPayload_0(depth);
  if (optixGetPayload_1() != 0) {
    unsigned int deeper = depth, recurse = 1;
    optixTrace(optixGetGASTraversableHandle(), make_float3(0.0f, 0.0f, 1.0f),
               make_float3(0.0f, 0.0f, -1.0f), 0.0f, 1e16f, 0.0f, OptixVisibilityMask(255),
               OPTIX_RAY_FLAG_NONE, 0, 1, 0, deeper, recurse);
    optixSetPayload_0(deeper);
  }
}

extern "C" __global__ void __miss__none() {}

extern "C" __global__ void __exception__record() {
  const uint3 idx = optixGetLaunchIndex();
  const unsigned int pixel = idx.y * params.width + idx.x;
  const int code = optixGetExceptionCode();
  params.codes[pixel] = code;
  if (code == kUserCode) {
    params.details[pixel] = optixGetExceptionDetail_0() * 1000 + optixGetExceptionDetail_1();
    params.image[pixel] = make_uchar4(255, 0, 0, 255);
  } else if (code == OPTIX_EXCEPTION_CODE_TRACE_DEPTH_EXCEEDED) {
    params.image[pixel] = make_uchar4(0, 0, 255, 255);
  } else {
    params.image[pixel] = make_uchar4(255, 255, 255, 255);
  }
}

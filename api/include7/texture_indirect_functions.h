/* CUDA's texture object functions, as texture_indirect_functions.h of the CUDA toolkit declares
 * them for device code: tex1Dfetch, tex1D, tex2D, tex3D, their Layered, Cubemap, Lod and Grad
 * forms and tex2Dgather on a cudaTextureObject_t, each in the value form (`tex2D<float4>(t, u,
 * v)`) and the pointer form (`tex2D(&c, t, u, v)`). nvcc makes them visible in every .cu file;
 * here optix_device.h includes this header.
 *
 * A texture object is the device address of a TesseraCudaTextureObject
 * (tessera/optix7_texture_abi.h) that cudaCreateTextureObject wrote; every lookup samples its view
 * with the OptiX 3 layer's sampler (tessera/detail/texture_sampling.h), which follows CUDA's
 * texture fetching arithmetic (docs/textures.md), so OptiX 3 and OptiX 7 programs get the same
 * bits from the same texels and modes. A zero or destroyed object reads zeros. A plain lookup
 * reads mip level 0 (after the bias and clamps): a CPU has no screen-space derivatives. */
#ifndef TESSERA_OPTIX7_TEXTURE_INDIRECT_FUNCTIONS_H_
#define TESSERA_OPTIX7_TEXTURE_INDIRECT_FUNCTIONS_H_

#ifndef __cplusplus
#error "texture_indirect_functions.h: texture lookups are C++ templates"
#endif

#include "tessera/detail/texture_sampling.h"
#include "tessera/optix7_cuda_defines.h"
#include "tessera/optix7_texture_abi.h"
#include "texture_types.h"
#include "vector_types.h"

namespace tessera_optix7 {

/* The view of a live texture object, or null. */
inline const TesseraTextureView* TextureObjectView(cudaTextureObject_t object) {
  if (object == 0) return nullptr;
  const auto* d = reinterpret_cast<const TesseraCudaTextureObject*>(object);
  return d->magic == TESSERA_CUDA_TEXTURE_MAGIC ? &d->view : nullptr;
}

}  // namespace tessera_optix7

/* Each lookup in both forms: `T name<T>(cudaTextureObject_t, params)` and
 * `void name(T*, cudaTextureObject_t, params)`, sampling with tessera::texture::call. */
#define TESSERA_CUDA_TEX(name, params, call)                                      \
  template <class T>                                                              \
  static __forceinline__ __device__ T name(                                       \
      cudaTextureObject_t texObject TESSERA_CUDA_TEX_COMMA params) {              \
    const TesseraTextureView* v = ::tessera_optix7::TextureObjectView(texObject); \
    return v != nullptr ? ::tessera::texture::call : T{};                         \
  }                                                                               \
  template <class T>                                                              \
  static __forceinline__ __device__ void name(                                    \
      T* retVal, cudaTextureObject_t texObject TESSERA_CUDA_TEX_COMMA params) {   \
    *retVal = name<T>(texObject, TESSERA_CUDA_TEX_ARGS_##name);                   \
  }
#define TESSERA_CUDA_TEX_COMMA ,

#define TESSERA_CUDA_TEX_ARGS_tex1Dfetch x
#define TESSERA_CUDA_TEX_ARGS_tex1D x
#define TESSERA_CUDA_TEX_ARGS_tex2D x, y
#define TESSERA_CUDA_TEX_ARGS_tex3D x, y, z
#define TESSERA_CUDA_TEX_ARGS_tex1DLayered x, layer
#define TESSERA_CUDA_TEX_ARGS_tex2DLayered x, y, layer
#define TESSERA_CUDA_TEX_ARGS_texCubemap x, y, z
#define TESSERA_CUDA_TEX_ARGS_texCubemapLayered x, y, z, layer
#define TESSERA_CUDA_TEX_ARGS_tex1DLod x, level
#define TESSERA_CUDA_TEX_ARGS_tex2DLod x, y, level
#define TESSERA_CUDA_TEX_ARGS_tex3DLod x, y, z, level
#define TESSERA_CUDA_TEX_ARGS_tex1DLayeredLod x, layer, level
#define TESSERA_CUDA_TEX_ARGS_tex2DLayeredLod x, y, layer, level
#define TESSERA_CUDA_TEX_ARGS_texCubemapLod x, y, z, level
#define TESSERA_CUDA_TEX_ARGS_texCubemapLayeredLod x, y, z, layer, level
#define TESSERA_CUDA_TEX_ARGS_tex1DGrad x, dPdx, dPdy
#define TESSERA_CUDA_TEX_ARGS_tex2DGrad x, y, dPdx, dPdy
#define TESSERA_CUDA_TEX_ARGS_tex3DGrad x, y, z, dPdx, dPdy
#define TESSERA_CUDA_TEX_ARGS_tex1DLayeredGrad x, layer, dPdx, dPdy
#define TESSERA_CUDA_TEX_ARGS_tex2DLayeredGrad x, y, layer, dPdx, dPdy
#define TESSERA_CUDA_TEX_ARGS_tex2Dgather x, y, comp

/* Integer texel coordinates, no filtering or wrapping (linear memory's lookup). */
TESSERA_CUDA_TEX(tex1Dfetch, int x, Fetch1D<T>(*v, x))
TESSERA_CUDA_TEX(tex1D, float x, Sample1D<T>(*v, x))
TESSERA_CUDA_TEX(tex2D, float x TESSERA_CUDA_TEX_COMMA float y, Sample2D<T>(*v, x, y))
TESSERA_CUDA_TEX(tex3D, float x TESSERA_CUDA_TEX_COMMA float y TESSERA_CUDA_TEX_COMMA float z,
                 Sample3D<T>(*v, x, y, z))
TESSERA_CUDA_TEX(tex1DLayered, float x TESSERA_CUDA_TEX_COMMA int layer,
                 Sample1DLayered<T>(*v, x, layer))
TESSERA_CUDA_TEX(tex2DLayered,
                 float x TESSERA_CUDA_TEX_COMMA float y TESSERA_CUDA_TEX_COMMA int layer,
                 Sample2DLayered<T>(*v, x, y, layer))
TESSERA_CUDA_TEX(texCubemap, float x TESSERA_CUDA_TEX_COMMA float y TESSERA_CUDA_TEX_COMMA float z,
                 SampleCubemap<T>(*v, x, y, z))
TESSERA_CUDA_TEX(texCubemapLayered,
                 float x TESSERA_CUDA_TEX_COMMA float y TESSERA_CUDA_TEX_COMMA float z
                     TESSERA_CUDA_TEX_COMMA int layer,
                 SampleCubemapLayered<T>(*v, x, y, z, layer))
TESSERA_CUDA_TEX(tex1DLod, float x TESSERA_CUDA_TEX_COMMA float level, Sample1DLod<T>(*v, x, level))
TESSERA_CUDA_TEX(tex2DLod,
                 float x TESSERA_CUDA_TEX_COMMA float y TESSERA_CUDA_TEX_COMMA float level,
                 Sample2DLod<T>(*v, x, y, level))
TESSERA_CUDA_TEX(tex3DLod,
                 float x TESSERA_CUDA_TEX_COMMA float y TESSERA_CUDA_TEX_COMMA float z
                     TESSERA_CUDA_TEX_COMMA float level,
                 Sample3DLod<T>(*v, x, y, z, level))
TESSERA_CUDA_TEX(tex1DLayeredLod,
                 float x TESSERA_CUDA_TEX_COMMA int layer TESSERA_CUDA_TEX_COMMA float level,
                 Sample1DLayeredLod<T>(*v, x, layer, level))
TESSERA_CUDA_TEX(tex2DLayeredLod,
                 float x TESSERA_CUDA_TEX_COMMA float y TESSERA_CUDA_TEX_COMMA int layer
                     TESSERA_CUDA_TEX_COMMA float level,
                 Sample2DLayeredLod<T>(*v, x, y, layer, level))
TESSERA_CUDA_TEX(texCubemapLod,
                 float x TESSERA_CUDA_TEX_COMMA float y TESSERA_CUDA_TEX_COMMA float z
                     TESSERA_CUDA_TEX_COMMA float level,
                 SampleCubemapLod<T>(*v, x, y, z, level))
TESSERA_CUDA_TEX(texCubemapLayeredLod,
                 float x TESSERA_CUDA_TEX_COMMA float y TESSERA_CUDA_TEX_COMMA float z
                     TESSERA_CUDA_TEX_COMMA int layer TESSERA_CUDA_TEX_COMMA float level,
                 SampleCubemapLayeredLod<T>(*v, x, y, z, layer, level))
/* The level of detail from the coordinates' derivatives along the two screen axes. */
TESSERA_CUDA_TEX(tex1DGrad,
                 float x TESSERA_CUDA_TEX_COMMA float dPdx TESSERA_CUDA_TEX_COMMA float dPdy,
                 Sample1DGrad<T>(*v, x, dPdx, dPdy))
TESSERA_CUDA_TEX(tex2DGrad,
                 float x TESSERA_CUDA_TEX_COMMA float y TESSERA_CUDA_TEX_COMMA float2 dPdx
                     TESSERA_CUDA_TEX_COMMA float2 dPdy,
                 Sample2DGrad<T>(*v, x, y, dPdx, dPdy))
TESSERA_CUDA_TEX(tex3DGrad,
                 float x TESSERA_CUDA_TEX_COMMA float y TESSERA_CUDA_TEX_COMMA float z
                     TESSERA_CUDA_TEX_COMMA float4 dPdx TESSERA_CUDA_TEX_COMMA float4 dPdy,
                 Sample3DGrad<T>(*v, x, y, z, dPdx, dPdy))
TESSERA_CUDA_TEX(tex1DLayeredGrad,
                 float x TESSERA_CUDA_TEX_COMMA int layer TESSERA_CUDA_TEX_COMMA float dPdx
                     TESSERA_CUDA_TEX_COMMA float dPdy,
                 Sample1DLayeredGrad<T>(*v, x, layer, dPdx, dPdy))
TESSERA_CUDA_TEX(tex2DLayeredGrad,
                 float x TESSERA_CUDA_TEX_COMMA float y TESSERA_CUDA_TEX_COMMA int layer
                     TESSERA_CUDA_TEX_COMMA float2 dPdx TESSERA_CUDA_TEX_COMMA float2 dPdy,
                 Sample2DLayeredGrad<T>(*v, x, y, layer, dPdx, dPdy))
/* Channel comp (0-3) of the four texels bilinear filtering would read; T has four components.
 * comp defaults to 0 in the value form only, as in CUDA. */
TESSERA_CUDA_TEX(tex2Dgather,
                 float x TESSERA_CUDA_TEX_COMMA float y TESSERA_CUDA_TEX_COMMA int comp,
                 Gather2D<T>(*v, x, y, comp))
template <class T>
static __forceinline__ __device__ T tex2Dgather(cudaTextureObject_t texObject, float x, float y) {
  return tex2Dgather<T>(texObject, x, y, 0);
}

#undef TESSERA_CUDA_TEX
#undef TESSERA_CUDA_TEX_COMMA

#endif /* TESSERA_OPTIX7_TEXTURE_INDIRECT_FUNCTIONS_H_ */

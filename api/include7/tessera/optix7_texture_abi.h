/* What a CUDA texture object is on Tessera (docs/optix7.md, "Textures"): cudaCreateTextureObject
 * writes one of these into device memory and returns its address as the cudaTextureObject_t, so
 * it travels to workers like any device memory and a program reads it wherever it runs. The view
 * is the OptiX 3 sampler's (tessera/detail/texture_view.h), its texel pointers device addresses.
 * Shared by the host (api/optix7/cuda_textures.cc) and programs (texture_indirect_functions.h):
 * both must agree on the layout. C and C++. */
#ifndef TESSERA_OPTIX7_TEXTURE_ABI_H_
#define TESSERA_OPTIX7_TEXTURE_ABI_H_

#include "tessera/detail/texture_view.h"

/* "TSRATEX7", first in every descriptor: a program that is handed something else (a destroyed
 * object's recycled memory, a stray integer) reads zeros instead of sampling garbage texels. */
#define TESSERA_CUDA_TEXTURE_MAGIC 0x3758455441525354ull

typedef struct {
  unsigned long long magic; /* TESSERA_CUDA_TEXTURE_MAGIC while the object lives */
  unsigned long long reserved;
  TesseraTextureView view;
} TesseraCudaTextureObject;

#endif /* TESSERA_OPTIX7_TEXTURE_ABI_H_ */

/* What a program sees of a texture: the OptiX 3 engine fills one per sampler bound to a program
 * (an rtTextureSampler declaration, or a bindless id), the OptiX 7 layer one per CUDA texture
 * object (in device memory, tessera/optix7_texture_abi.h), and the sampling functions of
 * tessera/detail/texture_sampling.h read texels through it. Plain C, part of both module ABIs
 * (tessera/detail/module_abi.h, tessera/optix7_device_abi.h): both sides must agree on its
 * layout. The modes are OptiX 3's enum values (tessera/detail/texture_modes.h). Shared by both
 * include roots (api/include_common). */
#ifndef TESSERA_DETAIL_TEXTURE_VIEW_H_
#define TESSERA_DETAIL_TEXTURE_VIEW_H_

#ifdef __cplusplus
extern "C" {
#endif

/* A texture has at most this many mip levels (a 32768-texel side has 16). */
#define TESSERA_TEXTURE_MAX_LEVELS 16

/* One mip level: texels in x-fastest order, then y, then z (or layer, or cube face). */
typedef struct {
  const void* data;
  unsigned width, height, depth; /* unused dimensions are 1 */
  /* Texels from the start of one row to the next; 0 means width (packed rows). Only CUDA's
   * pitched 2D memory (cudaResourceTypePitch2D) has longer rows. It fills what was the struct's
   * tail padding, so the layout and the size stay those of module ABI 9, and views that engines
   * value-initialize read 0. */
  unsigned pitch;
} TesseraTextureLevel;

typedef struct {
  TesseraTextureLevel levels[TESSERA_TEXTURE_MAX_LEVELS];
  unsigned level_count;    /* 1 without mipmaps */
  unsigned dimensionality; /* of the buffer: 1, 2 or 3 */
  unsigned format;         /* RTformat of a texel (kFormat*) */
  unsigned element_size;   /* bytes per texel */
  /* RT_BUFFER_LAYERED: depth counts layers. RT_BUFFER_CUBEMAP: depth counts faces (+x, -x, +y,
   * -y, +z, -z), 6 per layer when both are set. */
  unsigned layered;
  unsigned cubemap;
  unsigned wrap[3];         /* RTwrapmode per dimension (kWrap*) */
  unsigned min_filter;      /* RTfiltermode (kFilter*) */
  unsigned mag_filter;      /* RTfiltermode */
  unsigned mip_filter;      /* RTfiltermode: RT_FILTER_NONE samples level 0 only */
  unsigned read_mode;       /* RTtexturereadmode (kRead*) */
  unsigned index_mode;      /* RTtextureindexmode (kIndex*) */
  float max_anisotropy;     /* accepted; 1 means none */
  float mip_level_clamp[2]; /* min, max level */
  float mip_level_bias;
  int id;        /* rtTextureSamplerGetId */
  unsigned fast; /* a lookup path for this view alone (tessera/detail/texture_fast.h); 0: none */
  /* The linear float lookup of tessera/detail/texture_fast_float.h: (dimensions << 4) | channels;
   * 0: none. Since OptiX 3 module ABI 11 and OptiX 7 module ABI 4. */
  unsigned fast_linear;
  unsigned reserved; /* 0; keeps the size a multiple of the pointers' alignment */
} TesseraTextureView;

#ifdef __cplusplus
}
#endif

#endif /* TESSERA_DETAIL_TEXTURE_VIEW_H_ */

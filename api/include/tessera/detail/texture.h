// Program-side textures (OptiX guide 4.8; OptiX 3.9+ layered, cube map and mipmapped textures):
// `rtTextureSampler<T, Dim, ReadMode> name;` at namespace scope, read with CUDA's tex1D, tex2D …,
// and bindless rtTex* calls on the ids rtTextureSamplerGetId gives. The engine fills a
// TesseraTextureView per sampler (tessera/detail/texture_view.h); the sampling functions of
// tessera/detail/texture_sampling.h filter texels through it. Included by tessera/device.h.
//
// A declaration is a namespace-scope object holding a slot index, named (as rtBuffer objects)
// from the module's dynamic symbol table: it must not be `static`. Before a program runs, the
// engine binds each slot to the sampler the declaration's name resolves to through the program's
// scopes (OptiX guide Table 5); a slot no scope binds reads zeros.
#ifndef TESSERA_DETAIL_TEXTURE_H_
#define TESSERA_DETAIL_TEXTURE_H_

#include <vector>

#include "optixu/optixu_vector_types.h"
#include "tessera/detail/module_abi.h"
#include "tessera/detail/texture_view.h"

// ---- CUDA's texture enums, as programs name them ---------------------------------------------
#ifndef cudaTextureType1D
#define cudaTextureType1D 0x01
#define cudaTextureType2D 0x02
#define cudaTextureType3D 0x03
#define cudaTextureTypeCubemap 0x0C
#define cudaTextureType1DLayered 0xF1
#define cudaTextureType2DLayered 0xF2
#define cudaTextureTypeCubemapLayered 0xFC
#endif
// CUDA's driver_types.h declares it too; a program module compiled by Tessera has no CUDA headers
// (it defines __CUDACC__ all the same: docs/programs.md "Compiling programs").
#if !defined(__DRIVER_TYPES_H__)
enum cudaTextureReadMode { cudaReadModeElementType = 0, cudaReadModeNormalizedFloat = 1 };
#endif

#include "tessera/detail/texture_sampling.h"

#pragma GCC visibility push(hidden)
namespace tessera::detail {

inline std::vector<TesseraTextureDecl>& TextureDecls() {
  static std::vector<TesseraTextureDecl> decls;
  return decls;
}

// Registers one declaration; the module's description (TesseraModuleInfo) lists them all. Runs
// from static constructors, before the engine calls tessera_module_init.
inline unsigned RegisterTexture(const void* object, size_t element_size, unsigned dim,
                                unsigned read_mode) {
  std::vector<TesseraTextureDecl>& decls = TextureDecls();
  decls.push_back({object, element_size, dim, read_mode});
  TesseraModuleInfo& info = Registry().info;
  info.texture_count = static_cast<unsigned>(decls.size());
  info.textures = decls.data();
  return static_cast<unsigned>(decls.size() - 1);
}

// What a read returns: T, or with cudaReadModeNormalizedFloat the float type of as many
// components (CUDA: an 8- or 16-bit integer texel reads as a float in [0, 1] or [-1, 1]).
template <typename T, int ReadMode>
struct TexelResult {
  using type = T;
};
#define TESSERA_NORMALIZED_AS(from, to)                   \
  template <>                                             \
  struct TexelResult<from, cudaReadModeNormalizedFloat> { \
    using type = to;                                      \
  };
TESSERA_NORMALIZED_AS(char, float)
TESSERA_NORMALIZED_AS(signed char, float)
TESSERA_NORMALIZED_AS(unsigned char, float)
TESSERA_NORMALIZED_AS(short, float)
TESSERA_NORMALIZED_AS(unsigned short, float)
TESSERA_NORMALIZED_AS(char1, float1)
TESSERA_NORMALIZED_AS(uchar1, float1)
TESSERA_NORMALIZED_AS(short1, float1)
TESSERA_NORMALIZED_AS(ushort1, float1)
TESSERA_NORMALIZED_AS(char2, float2)
TESSERA_NORMALIZED_AS(uchar2, float2)
TESSERA_NORMALIZED_AS(short2, float2)
TESSERA_NORMALIZED_AS(ushort2, float2)
TESSERA_NORMALIZED_AS(char4, float4)
TESSERA_NORMALIZED_AS(uchar4, float4)
TESSERA_NORMALIZED_AS(short4, float4)
TESSERA_NORMALIZED_AS(ushort4, float4)
#undef TESSERA_NORMALIZED_AS

}  // namespace tessera::detail
#pragma GCC visibility pop

// rtTextureSampler<T, Dim, ReadMode>: Dim is 1, 2, 3 or a cudaTextureType* (layered, cube map).
template <typename T, int Dim = cudaTextureType1D, int ReadMode = cudaReadModeElementType>
class rtTextureSampler {
  static_assert(Dim == cudaTextureType1D || Dim == cudaTextureType2D || Dim == cudaTextureType3D ||
                    Dim == cudaTextureTypeCubemap || Dim == cudaTextureType1DLayered ||
                    Dim == cudaTextureType2DLayered || Dim == cudaTextureTypeCubemapLayered,
                "rtTextureSampler: Dim must be 1, 2, 3 or a cudaTextureType* value");
  static_assert(ReadMode == cudaReadModeElementType || ReadMode == cudaReadModeNormalizedFloat,
                "rtTextureSampler: ReadMode must be cudaReadModeElementType or "
                "cudaReadModeNormalizedFloat");

 public:
  using Result = typename ::tessera::detail::TexelResult<T, ReadMode>::type;

  rtTextureSampler() : slot_(::tessera::detail::RegisterTexture(this, sizeof(T), Dim, ReadMode)) {}
  rtTextureSampler(const rtTextureSampler&) = delete;
  rtTextureSampler& operator=(const rtTextureSampler&) = delete;

  // The running program's view of the sampler bound to this declaration; null when none is.
  // Every binding of a program has a view per declaration of its module (level_count 0: none).
  const TesseraTextureView* View() const {
    const TesseraTextureView& v = ::tessera::detail::AtThreadPointer<const TesseraTextureView>(
        ::tessera::detail::g_texture_table_offset)[slot_];
    return v.level_count != 0 ? &v : nullptr;
  }

 private:
  unsigned slot_;
};

namespace tessera::detail {
// Calls `sample` on the view, or gives zeros when no sampler is bound (as an unbound rtBuffer).
template <typename R, typename Sample>
inline R SampleOr0(const TesseraTextureView* view, Sample&& sample) {
  return view != nullptr ? sample(*view) : R{};
}
}  // namespace tessera::detail

// Reads through a declared sampler (CUDA's texture functions, by the sampler's Dim).
#define TESSERA_TEX(name, dim, params, call)                                              \
  template <typename T, int M>                                                            \
  inline typename rtTextureSampler<T, dim, M>::Result name(                               \
      const rtTextureSampler<T, dim, M>& s TESSERA_TEX_UNPAREN params) {                  \
    using R = typename rtTextureSampler<T, dim, M>::Result;                               \
    return ::tessera::detail::SampleOr0<R>(                                               \
        s.View(), [&](const TesseraTextureView& v) { return ::tessera::texture::call; }); \
  }
#define TESSERA_TEX_UNPAREN(...) , __VA_ARGS__

TESSERA_TEX(tex1D, cudaTextureType1D, (float x), Sample1D<R>(v, x))
TESSERA_TEX(tex2D, cudaTextureType2D, (float x, float y), Sample2D<R>(v, x, y))
TESSERA_TEX(tex3D, cudaTextureType3D, (float x, float y, float z), Sample3D<R>(v, x, y, z))
TESSERA_TEX(tex1DLayered, cudaTextureType1DLayered, (float x, int layer),
            Sample1DLayered<R>(v, x, layer))
TESSERA_TEX(tex2DLayered, cudaTextureType2DLayered, (float x, float y, int layer),
            Sample2DLayered<R>(v, x, y, layer))
TESSERA_TEX(texCubemap, cudaTextureTypeCubemap, (float x, float y, float z),
            SampleCubemap<R>(v, x, y, z))
TESSERA_TEX(texCubemapLayered, cudaTextureTypeCubemapLayered,
            (float x, float y, float z, int layer), SampleCubemapLayered<R>(v, x, y, z, layer))
TESSERA_TEX(tex1DLod, cudaTextureType1D, (float x, float level), Sample1DLod<R>(v, x, level))
TESSERA_TEX(tex2DLod, cudaTextureType2D, (float x, float y, float level),
            Sample2DLod<R>(v, x, y, level))
TESSERA_TEX(tex3DLod, cudaTextureType3D, (float x, float y, float z, float level),
            Sample3DLod<R>(v, x, y, z, level))
TESSERA_TEX(tex1DLayeredLod, cudaTextureType1DLayered, (float x, int layer, float level),
            Sample1DLayeredLod<R>(v, x, layer, level))
TESSERA_TEX(tex2DLayeredLod, cudaTextureType2DLayered, (float x, float y, int layer, float level),
            Sample2DLayeredLod<R>(v, x, y, layer, level))
TESSERA_TEX(texCubemapLod, cudaTextureTypeCubemap, (float x, float y, float z, float level),
            SampleCubemapLod<R>(v, x, y, z, level))
TESSERA_TEX(texCubemapLayeredLod, cudaTextureTypeCubemapLayered,
            (float x, float y, float z, int layer, float level),
            SampleCubemapLayeredLod<R>(v, x, y, z, layer, level))
TESSERA_TEX(tex1DGrad, cudaTextureType1D, (float x, float dPdx, float dPdy),
            Sample1DGrad<R>(v, x, dPdx, dPdy))
TESSERA_TEX(tex2DGrad, cudaTextureType2D, (float x, float y, float2 dPdx, float2 dPdy),
            Sample2DGrad<R>(v, x, y, dPdx, dPdy))
TESSERA_TEX(tex3DGrad, cudaTextureType3D, (float x, float y, float z, float4 dPdx, float4 dPdy),
            Sample3DGrad<R>(v, x, y, z, dPdx, dPdy))
TESSERA_TEX(tex1DLayeredGrad, cudaTextureType1DLayered,
            (float x, int layer, float dPdx, float dPdy),
            Sample1DLayeredGrad<R>(v, x, layer, dPdx, dPdy))
TESSERA_TEX(tex2DLayeredGrad, cudaTextureType2DLayered,
            (float x, float y, int layer, float2 dPdx, float2 dPdy),
            Sample2DLayeredGrad<R>(v, x, y, layer, dPdx, dPdy))
TESSERA_TEX(tex1Dfetch, cudaTextureType1D, (int x), Fetch1D<R>(v, x))
#undef TESSERA_TEX

// CUDA's tex2Dgather: component `comp` of the four texels bilinear filtering would use.
template <typename T, int M>
inline auto tex2Dgather(const rtTextureSampler<T, cudaTextureType2D, M>& s, float x, float y,
                        int comp = 0) {
  using R = typename rtTextureSampler<T, cudaTextureType2D, M>::Result;
  return ::tessera::detail::SampleOr0<R>(s.View(), [&](const TesseraTextureView& v) {
    return ::tessera::texture::Gather2D<R>(v, x, y, comp);
  });
}

// ---- Bindless textures (OptiX 3.0 rtTex1D/2D/3D, OptiX 3.9 the rest) --------------------------
// `id` comes from rtTextureSamplerGetId; an unknown id raises RT_EXCEPTION_TEXTURE_ID_INVALID
// (zeros when that exception is disabled). T is what the read returns (float4, uchar4 …), as the
// host sampler's read mode makes it.
typedef int rtTextureId;
#define RT_TEXTURE_ID_NULL 0

namespace tessera::detail {
// The view of sampler `id`: from the plan's table indexed by id without a call; any id the table
// lacks asks the engine, which raises RT_EXCEPTION_TEXTURE_ID_INVALID with the reason.
inline const TesseraTextureView* TextureById(rtTextureId id) {
  const TesseraTextureIdTable* t =
      AtThreadPointer<const TesseraTextureIdTable>(g_texture_id_table_offset);
  const unsigned long long u = static_cast<unsigned>(id);  // a negative id is past the end
  if (u < t->count && t->views[u] != nullptr) return t->views[u];
  return Rt()->texture_by_id(id);
}

template <typename T, typename Sample>
inline T SampleId(rtTextureId id, Sample&& sample) {
  return SampleOr0<T>(TextureById(id), sample);
}
}  // namespace tessera::detail

// Each rtTex* comes as `T rtTexX<T>(id, …)` and as `void rtTexX(T* result, id, …)`.
#define TESSERA_RT_TEX(name, params, args, call)                                    \
  template <typename T>                                                             \
  inline T name(rtTextureId id TESSERA_TEX_UNPAREN params) {                        \
    return ::tessera::detail::SampleId<T>(                                          \
        id, [&](const TesseraTextureView& v) { return ::tessera::texture::call; }); \
  }                                                                                 \
  template <typename T>                                                             \
  inline void name(T* result, rtTextureId id TESSERA_TEX_UNPAREN params) {          \
    *result = name<T>(id TESSERA_TEX_UNPAREN args);                                 \
  }

TESSERA_RT_TEX(rtTex1D, (float x), (x), Sample1D<T>(v, x))
TESSERA_RT_TEX(rtTex2D, (float x, float y), (x, y), Sample2D<T>(v, x, y))
TESSERA_RT_TEX(rtTex3D, (float x, float y, float z), (x, y, z), Sample3D<T>(v, x, y, z))
TESSERA_RT_TEX(rtTex1DFetch, (int x), (x), Fetch1D<T>(v, x))
TESSERA_RT_TEX(rtTex2DFetch, (int x, int y), (x, y), Fetch2D<T>(v, x, y))
TESSERA_RT_TEX(rtTex3DFetch, (int x, int y, int z), (x, y, z), Fetch3D<T>(v, x, y, z))
TESSERA_RT_TEX(rtTex2DGather, (float x, float y, int comp), (x, y, comp),
               Gather2D<T>(v, x, y, comp))
TESSERA_RT_TEX(rtTex1DLayered, (float x, int layer), (x, layer), Sample1DLayered<T>(v, x, layer))
TESSERA_RT_TEX(rtTex2DLayered, (float x, float y, int layer), (x, y, layer),
               Sample2DLayered<T>(v, x, y, layer))
TESSERA_RT_TEX(rtTexCubemap, (float x, float y, float z), (x, y, z), SampleCubemap<T>(v, x, y, z))
TESSERA_RT_TEX(rtTexCubemapLayered, (float x, float y, float z, int layer), (x, y, z, layer),
               SampleCubemapLayered<T>(v, x, y, z, layer))
TESSERA_RT_TEX(rtTex1DLod, (float x, float level), (x, level), Sample1DLod<T>(v, x, level))
TESSERA_RT_TEX(rtTex2DLod, (float x, float y, float level), (x, y, level),
               Sample2DLod<T>(v, x, y, level))
TESSERA_RT_TEX(rtTex3DLod, (float x, float y, float z, float level), (x, y, z, level),
               Sample3DLod<T>(v, x, y, z, level))
TESSERA_RT_TEX(rtTex1DLayeredLod, (float x, int layer, float level), (x, layer, level),
               Sample1DLayeredLod<T>(v, x, layer, level))
TESSERA_RT_TEX(rtTex2DLayeredLod, (float x, float y, int layer, float level), (x, y, layer, level),
               Sample2DLayeredLod<T>(v, x, y, layer, level))
TESSERA_RT_TEX(rtTexCubemapLod, (float x, float y, float z, float level), (x, y, z, level),
               SampleCubemapLod<T>(v, x, y, z, level))
TESSERA_RT_TEX(rtTexCubemapLayeredLod, (float x, float y, float z, int layer, float level),
               (x, y, z, layer, level), SampleCubemapLayeredLod<T>(v, x, y, z, layer, level))
TESSERA_RT_TEX(rtTex1DGrad, (float x, float dPdx, float dPdy), (x, dPdx, dPdy),
               Sample1DGrad<T>(v, x, dPdx, dPdy))
TESSERA_RT_TEX(rtTex2DGrad, (float x, float y, float2 dPdx, float2 dPdy), (x, y, dPdx, dPdy),
               Sample2DGrad<T>(v, x, y, dPdx, dPdy))
TESSERA_RT_TEX(rtTex3DGrad, (float x, float y, float z, float4 dPdx, float4 dPdy),
               (x, y, z, dPdx, dPdy), Sample3DGrad<T>(v, x, y, z, dPdx, dPdy))
TESSERA_RT_TEX(rtTex1DLayeredGrad, (float x, int layer, float dPdx, float dPdy),
               (x, layer, dPdx, dPdy), Sample1DLayeredGrad<T>(v, x, layer, dPdx, dPdy))
TESSERA_RT_TEX(rtTex2DLayeredGrad, (float x, float y, int layer, float2 dPdx, float2 dPdy),
               (x, y, layer, dPdx, dPdy), Sample2DLayeredGrad<T>(v, x, y, layer, dPdx, dPdy))
#undef TESSERA_RT_TEX
#undef TESSERA_TEX_UNPAREN

// rtTex2DGather's `comp` defaults to 0 (the x components).
template <typename T>
inline T rtTex2DGather(rtTextureId id, float x, float y) {
  return rtTex2DGather<T>(id, x, y, 0);
}

// The size of level 0 of the sampler `id` names (rtTexSize, OptiX 3.9); zeros for no sampler.
inline uint3 rtTexSize(rtTextureId id) {
  const TesseraTextureView* v = ::tessera::detail::TextureById(id);
  if (v == nullptr || v->level_count == 0) return uint3{0, 0, 0};
  return uint3{v->levels[0].width, v->levels[0].height, v->levels[0].depth};
}

#endif  // TESSERA_DETAIL_TEXTURE_H_

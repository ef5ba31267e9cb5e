/* Texture sampling for programs: what tex1D/tex2D/tex3D, their Lod/Grad/Layered/Cubemap forms,
 * tex2Dgather and the integer fetches compute, following the arithmetic of the CUDA Programming
 * Guide's "Texture Fetching" appendix so that images match a GPU's (docs/textures.md says how,
 * and where they may still differ). Header-only and allocation-free: a program module inlines it
 * and reads texels straight from the engine's memory through a TesseraTextureView.
 *
 * Everything a view says (format, read mode, filters, wrap modes) is read per call; the format and
 * read mode pick one instantiation with a single switch, so the texel loops below carry no
 * per-texel branch on them. A view the engine marked (TesseraTextureView::fast) takes the lookup
 * of tessera/detail/texture_fast.h instead, which gives the same bits. Formats and read modes are
 * in texture_formats.h, addressing in texture_addressing.h. */
#ifndef TESSERA_DETAIL_TEXTURE_SAMPLING_H_
#define TESSERA_DETAIL_TEXTURE_SAMPLING_H_

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <type_traits>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "tessera/detail/texture_addressing.h"
#include "tessera/detail/texture_fast.h"
#include "tessera/detail/texture_fast_float.h"
#include "tessera/detail/texture_formats.h"
#include "tessera/detail/texture_vector_types.h"
#include "tessera/detail/texture_view.h"

namespace tessera::texture {
namespace detail {

// ---- Filtering one level ---------------------------------------------------------------------

template <int D>
TESSERA_TEXTURE_INLINE void SizesOf(const TesseraTextureLevel& lv, int size[3]) {
  size[0] = static_cast<int>(lv.width);
  size[1] = static_cast<int>(lv.height);
  size[2] = static_cast<int>(lv.depth);
}

template <int D, bool kLinear>
TESSERA_TEXTURE_INLINE void AxesFor(const TesseraTextureLevel& lv, const Request& r, Axis axes[3]) {
  int size[3];
  SizesOf<D>(lv, size);
#pragma GCC unroll 4
  for (int a = 0; a < D; ++a) axes[a] = AxisAt<kLinear>(r.x[a], size[a], r.wrap[a], r.normalized);
#pragma GCC unroll 4
  for (int a = D; a < 3; ++a) axes[a] = Axis{{0, 0}, {1, 0}, {1, 1}};
}

// Nearest or linear (bilinear, trilinear) filtering of one level into out[0, kChannels):
//   tex(x, y) = (1-a)(1-b)T[i,j] + a(1-b)T[i+1,j] + (1-a)bT[i,j+1] + abT[i+1,j+1]
// false when the level holds no texels.
template <typename F, typename Mode, int D, bool kLinear>
TESSERA_TEXTURE_INLINE bool FilterLevel(const TesseraTextureLevel& lv, const Request& r,
                                        float out[4]) {
  using Ch = Channels<F, Mode>;
  constexpr int kC = F::kChannels;
  constexpr int kBits = kLinear ? 8 * D : 0;
  constexpr int kTaps = kLinear ? 2 : 1;
  const typename F::Scalar* base = PlaneBase<F, D>(lv, r);
  if (base == nullptr) return false;
  Axis ax[3];
  AxesFor<D, kLinear>(lv, r, ax);
  const std::size_t row = RowTexels(lv), slice = row * lv.height;
#if defined(__SSE2__)
  // RGBA8 read as normalized float, the commonest texture: the same exact float arithmetic as
  // below, four channels at a time.
  if constexpr (std::is_same_v<F, Format<unsigned char, 4>> && std::is_same_v<Mode, ModeUnorm> &&
                kBits <= 16) {
    const __m128i zero = _mm_setzero_si128();
    __m128 sum = _mm_setzero_ps();
#pragma GCC unroll 4
    for (int k = 0; k < (D > 2 ? kTaps : 1); ++k) {
#pragma GCC unroll 4
      for (int j = 0; j < (D > 1 ? kTaps : 1); ++j) {
#pragma GCC unroll 4
        for (int i = 0; i < kTaps; ++i) {
          const int w = ax[0].weight[i] * ax[1].weight[j] * ax[2].weight[k];
          const std::size_t texel = ax[0].index[i] + ax[1].index[j] * row + ax[2].index[k] * slice;
          int bits;
          std::memcpy(&bits, base + texel * 4, 4);
          const __m128i wide =
              _mm_unpacklo_epi16(_mm_unpacklo_epi8(_mm_cvtsi32_si128(bits), zero), zero);
          sum = _mm_add_ps(sum, _mm_mul_ps(_mm_cvtepi32_ps(wide), _mm_set1_ps(float(w))));
        }
      }
    }
    _mm_storeu_ps(out, _mm_div_ps(sum, _mm_set1_ps(float(255 << kBits))));
    return true;
  }
#endif
  typename Ch::template Acc<kBits> acc[kC] = {};
#pragma GCC unroll 4
  for (int k = 0; k < (D > 2 ? kTaps : 1); ++k) {
#pragma GCC unroll 4
    for (int j = 0; j < (D > 1 ? kTaps : 1); ++j) {
#pragma GCC unroll 4
      for (int i = 0; i < kTaps; ++i) {
        const int w = ax[0].weight[i] * ax[1].weight[j] * ax[2].weight[k];
        const std::size_t texel = ax[0].index[i] + ax[1].index[j] * row + ax[2].index[k] * slice;
        const typename F::Scalar* t = base + texel * kC;
#pragma GCC unroll 4
        for (int c = 0; c < kC; ++c) acc[c] += Ch::template Weighted<kBits>(w, t, c);
      }
    }
  }
#pragma GCC unroll 4
  for (int c = 0; c < kC; ++c) out[c] = Ch::template Finish<kBits>(acc[c]);
  return true;
}

template <typename F, typename Mode, int D>
inline bool FilterLevel(const TesseraTextureView& v, int level, bool linear, const Request& r,
                        float out[4]) {
  const TesseraTextureLevel& lv = v.levels[level];
  return linear ? FilterLevel<F, Mode, D, true>(lv, r, out)
                : FilterLevel<F, Mode, D, false>(lv, r, out);
}

// ---- Mip levels ------------------------------------------------------------------------------

inline int LevelCount(const TesseraTextureView& v) {
  const unsigned n =
      v.level_count < TESSERA_TEXTURE_MAX_LEVELS ? v.level_count : TESSERA_TEXTURE_MAX_LEVELS;
  return n > 0 ? static_cast<int>(n) : 1;
}

// The level of detail after mip_level_bias and mip_level_clamp (NaN reads as 0).
inline float AdjustLod(const TesseraTextureView& v, float lod) {
  lod = lod == lod ? lod : 0.f;
  lod += v.mip_level_bias;
  lod = lod < v.mip_level_clamp[1] ? lod : v.mip_level_clamp[1];
  lod = lod > v.mip_level_clamp[0] ? lod : v.mip_level_clamp[0];
  return lod == lod ? lod : 0.f;
}

inline bool Magnifies(float lod) { return lod <= 0.f; }

// Filters at level of detail `lod` (before bias and clamp): magnification (lod <= 0) uses
// mag_filter, minification min_filter; mip_filter none reads level 0, nearest the level
// round(lod), linear blends floor(lod) and the next with a weight in 1/256 as alpha is.
template <typename F, typename Mode, int D>
inline bool SampleMip(const TesseraTextureView& v, const Request& r, float lod, float out[4]) {
  lod = AdjustLod(v, lod);
  const bool linear = (Magnifies(lod) ? v.mag_filter : v.min_filter) == kFilterLinear;
  const int count = LevelCount(v);
  int level = 0, q = 0;  // q: the weight of level + 1, in 1/256
  if (count > 1 && v.mip_filter != kFilterNone) {
    const float top = static_cast<float>(count - 1);
    lod = lod > 0.f ? (lod < top ? lod : top) : 0.f;
    if (v.mip_filter == kFilterLinear) {
      level = FloorToInt(lod);
      q = static_cast<int>((lod - static_cast<float>(level)) * 256.f + 0.5f);
      if (q == 256) {
        ++level;
        q = 0;
      }
    } else {
      level = FloorToInt(lod + 0.5f);
    }
  }
  if (q == 0) return FilterLevel<F, Mode, D>(v, level, linear, r, out);
  float a[4] = {0.f, 0.f, 0.f, 1.f}, b[4] = {0.f, 0.f, 0.f, 1.f};
  if (!FilterLevel<F, Mode, D>(v, level, linear, r, a) ||
      !FilterLevel<F, Mode, D>(v, level + 1, linear, r, b)) {
    return false;
  }
  for (int c = 0; c < F::kChannels; ++c) {
    out[c] = static_cast<float>(((256 - q) * double(a[c]) + q * double(b[c])) / 256.0);
  }
  return true;
}

// Element-type reads of integer texels: the nearest texel of the nearest level (integers can be
// neither filtered nor blended; CUDA refuses linear filtering for them).
template <typename F, int D>
inline bool ElementMip(const TesseraTextureView& v, const Request& r, float lod,
                       typename F::Scalar out[4]) {
  int level = 0;
  if (LevelCount(v) > 1 && v.mip_filter != kFilterNone) {
    const float top = static_cast<float>(LevelCount(v) - 1);
    float l = AdjustLod(v, lod);
    l = l > 0.f ? (l < top ? l : top) : 0.f;
    level = FloorToInt(l + 0.5f);
  }
  const TesseraTextureLevel& lv = v.levels[level];
  const typename F::Scalar* base = PlaneBase<F, D>(lv, r);
  if (base == nullptr) return false;
  Axis ax[3];
  AxesFor<D, false>(lv, r, ax);
  const std::size_t row = RowTexels(lv);
  const std::size_t texel =
      ax[0].index[0] + ax[1].index[0] * row + ax[2].index[0] * row * lv.height;
  const bool inside = ax[0].inside[0] && ax[1].inside[0] && ax[2].inside[0];
#pragma GCC unroll 4
  for (int c = 0; c < F::kChannels; ++c) {
    out[c] = inside ? base[texel * F::kChannels + c] : typename F::Scalar(0);
  }
  return true;
}

// ---- Results ---------------------------------------------------------------------------------

// Channels the format lacks read (0, 0, 0, 1), as Direct3D and OpenGL define them.
template <typename T>
inline T FromFloats(const float* f) {
  using S = typename Result<T>::Scalar;
  S c[4];
#pragma GCC unroll 4
  for (int k = 0; k < 4; ++k) c[k] = FromFloat<S>(f[k]);
  return Result<T>::Make(c);
}

template <typename T, typename E>
inline T FromElements(const E* e) {
  using S = typename Result<T>::Scalar;
  S c[4];
#pragma GCC unroll 4
  for (int k = 0; k < 4; ++k) c[k] = static_cast<S>(e[k]);
  return Result<T>::Make(c);
}

// One format and read mode of Run. A function template rather than a lambda nested in Run's:
// Clang checks what does not depend on a nested lambda's own parameters when the outer one is
// instantiated, discarded `if constexpr` branches included.
template <typename T, typename F, typename M, typename FloatOp, typename ElementOp>
inline T RunMode(FloatOp& float_op, ElementOp& element_op) {
  if constexpr (std::is_same_v<M, ModeElement>) {
    typename F::Scalar e[4] = {0, 0, 0, 1};
    return element_op(F{}, e) ? FromElements<T>(e) : T{};
  } else {
    float f[4] = {0.f, 0.f, 0.f, 1.f};
    return float_op(F{}, M{}, f) ? FromFloats<T>(f) : T{};
  }
}

// Runs float_op(Format, Mode, float out[4]) or element_op(Format, Scalar out[4]) for the view's
// format and read mode and converts what it wrote to T; T{} when there are no texels.
template <typename T, typename FloatOp, typename ElementOp>
inline T Run(const TesseraTextureView& v, FloatOp&& float_op, ElementOp&& element_op) {
  return WithFormat<T>(v, [&](auto format) -> T {
    using F = decltype(format);
    return WithMode<F>(
        v, [&](auto mode) -> T { return RunMode<T, F, decltype(mode)>(float_op, element_op); });
  });
}

// The commonest lookup never gets here: views the engine marked take texture_fast.h.
template <typename T, int D>
inline T SampleLod(const TesseraTextureView& v, const Request& r, float lod) {
  return Run<T>(
      v,
      [&](auto format, auto mode, float* out) {
        return SampleMip<decltype(format), decltype(mode), D>(v, r, lod, out);
      },
      [&](auto format, auto* out) { return ElementMip<decltype(format), D>(v, r, lod, out); });
}

// ---- Derivatives -----------------------------------------------------------------------------

// The level of detail of a pixel footprint whose sides are the coordinate derivatives dx, dy
// (in texels: normalized coordinates scale by the size of level 0): log2 of the longer side.
// With max_anisotropy > 1 (2D only) the footprint is covered by `probes` lookups spaced along its
// longer side, each at the level of the longer side divided by min(longer / shorter,
// max_anisotropy): the usual hardware scheme; a GPU's exact probe pattern is not documented.
struct Footprint {
  float lod;
  int probes;
  float axis[3];  // the longer side, in the coordinates' own units
};

template <int D>
inline Footprint FootprintOf(const TesseraTextureView& v, bool normalized, const float* dx,
                             const float* dy) {
  const TesseraTextureLevel& l0 = v.levels[0];
  const float size[3] = {normalized ? float(l0.width) : 1.f, normalized ? float(l0.height) : 1.f,
                         normalized ? float(l0.depth) : 1.f};
  float lx = 0.f, ly = 0.f;
  for (int a = 0; a < D; ++a) {
    lx += (dx[a] * size[a]) * (dx[a] * size[a]);
    ly += (dy[a] * size[a]) * (dy[a] * size[a]);
  }
  lx = std::sqrt(lx);
  ly = std::sqrt(ly);
  const bool x_major = lx >= ly;
  const float major = x_major ? lx : ly, minor = x_major ? ly : lx;
  Footprint fp;
  fp.probes = 1;
  for (int a = 0; a < 3; ++a) fp.axis[a] = a < D ? (x_major ? dx[a] : dy[a]) : 0.f;
  float ratio = 1.f;
  const float max_aniso = v.max_anisotropy < 16.f ? v.max_anisotropy : 16.f;  // NaN: none
  if (D == 2 && max_aniso > 1.f && major > minor) {
    ratio = minor > 0.f && major / minor < max_aniso ? major / minor : max_aniso;
    fp.probes = static_cast<int>(std::ceil(ratio));
  }
  fp.lod = std::log2(major / ratio);
  return fp;
}

template <typename T, int D>
inline T SampleGrad(const TesseraTextureView& v, const Request& r, const float* dx,
                    const float* dy) {
  const Footprint fp = FootprintOf<D>(v, r.normalized, dx, dy);
  return Run<T>(
      v,
      [&](auto format, auto mode, float* out) {
        using F = decltype(format);
        using M = decltype(mode);
        if (fp.probes == 1) return SampleMip<F, M, D>(v, r, fp.lod, out);
        double sum[4] = {};
        Request p = r;
        for (int k = 0; k < fp.probes; ++k) {
          const float t = (static_cast<float>(k) + 0.5f) / static_cast<float>(fp.probes) - 0.5f;
          for (int a = 0; a < D; ++a) p.x[a] = r.x[a] + t * fp.axis[a];
          float probe[4] = {0.f, 0.f, 0.f, 1.f};
          if (!SampleMip<F, M, D>(v, p, fp.lod, probe)) return false;
          for (int c = 0; c < F::kChannels; ++c) sum[c] += probe[c];
        }
        for (int c = 0; c < F::kChannels; ++c) out[c] = static_cast<float>(sum[c] / fp.probes);
        return true;
      },
      [&](auto format, auto* out) { return ElementMip<decltype(format), D>(v, r, fp.lod, out); });
}

// ---- Gather and fetch ------------------------------------------------------------------------

// One channel of one texel as the read mode returns it (what a nearest lookup gives).
template <typename F, typename Mode>
inline float TexelChannel(const typename F::Scalar* t, int c) {
  using Ch = Channels<F, Mode>;
  return Ch::template Finish<0>(Ch::template Weighted<0>(1, t, c));
}

// tex2Dgather: channel `comp` of the four texels bilinear filtering would use at level 0, in the
// order of PTX tld4 (counter-clockwise from the lower left): (i, j+1), (i+1, j+1), (i+1, j),
// (i, j). Border texels read 0; a channel the format lacks reads 0 (1 for w).
template <typename T>
inline T Gather(const TesseraTextureView& v, const Request& r, int comp) {
  comp = comp < 0 ? 0 : (comp > 3 ? 3 : comp);
  const int order[4][2] = {{0, 1}, {1, 1}, {1, 0}, {0, 0}};
  auto each = [&](auto format, auto* out, auto read) {
    using F = decltype(format);
    const TesseraTextureLevel& lv = v.levels[0];
    const typename F::Scalar* base = PlaneBase<F, 2>(lv, r);
    if (base == nullptr) return false;
    Axis ax[3];
    AxesFor<2, true>(lv, r, ax);
    for (int k = 0; k < 4; ++k) {
      const int i = order[k][0], j = order[k][1];
      const auto* t = base + (ax[0].index[i] + ax[1].index[j] * RowTexels(lv)) * F::kChannels;
      const bool inside = ax[0].inside[i] && ax[1].inside[j];
      out[k] = comp >= F::kChannels ? (comp == 3 ? 1 : 0) : (inside ? read(t) : 0);
    }
    return true;
  };
  return Run<T>(
      v,
      [&](auto format, auto mode, float* out) {
        using F = decltype(format);
        using M = decltype(mode);
        return each(format, out,
                    [&](const typename F::Scalar* t) { return TexelChannel<F, M>(t, comp); });
      },
      [&](auto format, auto* out) {
        return each(format, out, [&](const auto* t) { return t[comp]; });
      });
}

// Integer texel access at level 0: no filtering and no wrapping; outside the texture reads 0
// (as tex1Dfetch does past its range).
template <typename T>
inline T Fetch(const TesseraTextureView& v, int x, int y, int z) {
  const TesseraTextureLevel& lv = v.levels[0];
  if (x < 0 || y < 0 || z < 0 || static_cast<unsigned>(x) >= lv.width ||
      static_cast<unsigned>(y) >= lv.height || static_cast<unsigned>(z) >= lv.depth ||
      lv.data == nullptr) {
    return T{};
  }
  const std::size_t texel =
      x + RowTexels(lv) * (y + std::size_t(lv.height) * static_cast<std::size_t>(z));
  return Run<T>(
      v,
      [&](auto format, auto mode, float* out) {
        using F = decltype(format);
        const auto* t = static_cast<const typename F::Scalar*>(lv.data) + texel * F::kChannels;
        for (int c = 0; c < F::kChannels; ++c) {
          out[c] = TexelChannel<F, decltype(mode)>(t, c);
        }
        return true;
      },
      [&](auto format, auto* out) {
        using F = decltype(format);
        const auto* t = static_cast<const typename F::Scalar*>(lv.data) + texel * F::kChannels;
        for (int c = 0; c < F::kChannels; ++c) out[c] = t[c];
        return true;
      });
}

}  // namespace detail

// ---- What programs call ----------------------------------------------------------------------
// T: the program's declared element type (float, float2, float4, uchar4, int4, ...). A plain
// lookup is the Lod form at level 0: a CPU has no screen-space derivatives (docs/textures.md).

template <typename T>
inline T Sample1DLod(const TesseraTextureView& v, float x, float level) {
  return detail::SampleLod<T, 1>(v, detail::MakeRequest(v, x, 0.f, 0.f, 0), level);
}
template <typename T>
inline T Sample2DLod(const TesseraTextureView& v, float x, float y, float level) {
#if defined(__SSE2__)
  if (v.fast != kFastNone) {  // one level, one filter: `level` changes nothing
    float f[4];
    if (v.fast == kFastBilinearRgba8Clamp) {
      detail::FastBilinearRgba8<false>(v, x, y, f);
    } else {
      detail::FastBilinearRgba8<true>(v, x, y, f);
    }
    return detail::FromFloats<T>(f);
  }
#endif
  if ((v.fast_linear >> 4) == 2) {  // one level, one filter: `level` changes nothing
    const float c[2] = {x, y};
    float f[4] = {0.f, 0.f, 0.f, 1.f};
    detail::FastLinear<2>(v, c, f);
    return detail::FromFloats<T>(f);
  }
  return detail::SampleLod<T, 2>(v, detail::MakeRequest(v, x, y, 0.f, 0), level);
}
template <typename T>
inline T Sample3DLod(const TesseraTextureView& v, float x, float y, float z, float level) {
  if ((v.fast_linear >> 4) == 3) {
    const float c[3] = {x, y, z};
    float f[4] = {0.f, 0.f, 0.f, 1.f};
    detail::FastLinear<3>(v, c, f);
    return detail::FromFloats<T>(f);
  }
  return detail::SampleLod<T, 3>(v, detail::MakeRequest(v, x, y, z, 0), level);
}
template <typename T>
inline T Sample1DLayeredLod(const TesseraTextureView& v, float x, int layer, float level) {
  return detail::SampleLod<T, 1>(v, detail::MakeRequest(v, x, 0.f, 0.f, layer), level);
}
template <typename T>
inline T Sample2DLayeredLod(const TesseraTextureView& v, float x, float y, int layer, float level) {
  return detail::SampleLod<T, 2>(v, detail::MakeRequest(v, x, y, 0.f, layer), level);
}
template <typename T>
inline T SampleCubemapLod(const TesseraTextureView& v, float x, float y, float z, float level) {
  return detail::SampleLod<T, 2>(v, detail::CubeRequest(v, x, y, z, 0), level);
}
template <typename T>
inline T SampleCubemapLayeredLod(const TesseraTextureView& v, float x, float y, float z, int layer,
                                 float level) {
  return detail::SampleLod<T, 2>(v, detail::CubeRequest(v, x, y, z, layer), level);
}

template <typename T>
inline T Sample1D(const TesseraTextureView& v, float x) {
  return Sample1DLod<T>(v, x, 0.f);
}
template <typename T>
inline T Sample2D(const TesseraTextureView& v, float x, float y) {
  return Sample2DLod<T>(v, x, y, 0.f);
}
template <typename T>
inline T Sample3D(const TesseraTextureView& v, float x, float y, float z) {
  return Sample3DLod<T>(v, x, y, z, 0.f);
}
template <typename T>
inline T Sample1DLayered(const TesseraTextureView& v, float x, int layer) {
  return Sample1DLayeredLod<T>(v, x, layer, 0.f);
}
template <typename T>
inline T Sample2DLayered(const TesseraTextureView& v, float x, float y, int layer) {
  return Sample2DLayeredLod<T>(v, x, y, layer, 0.f);
}
template <typename T>
inline T SampleCubemap(const TesseraTextureView& v, float x, float y, float z) {
  return SampleCubemapLod<T>(v, x, y, z, 0.f);
}
template <typename T>
inline T SampleCubemapLayered(const TesseraTextureView& v, float x, float y, float z, int layer) {
  return SampleCubemapLayeredLod<T>(v, x, y, z, layer, 0.f);
}

// Level of detail from the derivatives of the coordinates along the two screen axes.
template <typename T>
inline T Sample1DGrad(const TesseraTextureView& v, float x, float dPdx, float dPdy) {
  return detail::SampleGrad<T, 1>(v, detail::MakeRequest(v, x, 0.f, 0.f, 0), &dPdx, &dPdy);
}
template <typename T>
inline T Sample2DGrad(const TesseraTextureView& v, float x, float y, float2 dPdx, float2 dPdy) {
  const float dx[2] = {dPdx.x, dPdx.y}, dy[2] = {dPdy.x, dPdy.y};
  return detail::SampleGrad<T, 2>(v, detail::MakeRequest(v, x, y, 0.f, 0), dx, dy);
}
// float4 derivatives as CUDA's tex3DGrad takes them (w unused).
template <typename T>
inline T Sample3DGrad(const TesseraTextureView& v, float x, float y, float z, float4 dPdx,
                      float4 dPdy) {
  const float dx[3] = {dPdx.x, dPdx.y, dPdx.z}, dy[3] = {dPdy.x, dPdy.y, dPdy.z};
  return detail::SampleGrad<T, 3>(v, detail::MakeRequest(v, x, y, z, 0), dx, dy);
}
template <typename T>
inline T Sample1DLayeredGrad(const TesseraTextureView& v, float x, int layer, float dPdx,
                             float dPdy) {
  return detail::SampleGrad<T, 1>(v, detail::MakeRequest(v, x, 0.f, 0.f, layer), &dPdx, &dPdy);
}
template <typename T>
inline T Sample2DLayeredGrad(const TesseraTextureView& v, float x, float y, int layer, float2 dPdx,
                             float2 dPdy) {
  const float dx[2] = {dPdx.x, dPdx.y}, dy[2] = {dPdy.x, dPdy.y};
  return detail::SampleGrad<T, 2>(v, detail::MakeRequest(v, x, y, 0.f, layer), dx, dy);
}

// tex2Dgather: channel comp (0-3) of the four texels of the bilinear footprint; T has 4
// components.
template <typename T>
inline T Gather2D(const TesseraTextureView& v, float x, float y, int comp) {
  return detail::Gather<T>(v, detail::MakeRequest(v, x, y, 0.f, 0), comp);
}

// Integer texel coordinates at level 0 (tex1Dfetch, rtTex1DFetch ... rtTex3DFetch).
template <typename T>
inline T Fetch1D(const TesseraTextureView& v, int x) {
  return detail::Fetch<T>(v, x, 0, 0);
}
template <typename T>
inline T Fetch2D(const TesseraTextureView& v, int x, int y) {
  return detail::Fetch<T>(v, x, y, 0);
}
template <typename T>
inline T Fetch3D(const TesseraTextureView& v, int x, int y, int z) {
  return detail::Fetch<T>(v, x, y, z);
}

}  // namespace tessera::texture

#undef TESSERA_TEXTURE_INLINE

#endif  // TESSERA_DETAIL_TEXTURE_SAMPLING_H_

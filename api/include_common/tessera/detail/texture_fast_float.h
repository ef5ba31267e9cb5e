/* A second fast lookup (after texture_fast.h's RGBA8 one): linear filtering of a 2D or 3D float
 * texture of 1, 2 or 4 channels at normalized coordinates, each axis clamped to the edge or
 * repeated, from one mip level. HDR environment maps (float4, repeated around u, clamped at the
 * poles) and noise volumes (float, 3D, repeated) are read this way. The engine marks the views it
 * fits (TesseraTextureView::fast_linear, from FastLinearKind when it fills them).
 *
 * It skips the general path's format, read-mode and mip dispatch and addresses each axis with
 * that path's own AxisAt, its wrap mode known; the taps are the general path's products in its
 * order (z, then y, then x), summed in doubles, four channels in two SSE2 registers. So the
 * result is the general path's bits (tests/texture/texture_fast_float_test.cc checks it): every
 * product weight * texel is exact in a double, and the sums are the same sums in the same order.
 * A zero weight adds +0.0, as the general path does for it, so an infinite or NaN texel beside an
 * exactly hit one still leaves it alone. */
#ifndef TESSERA_DETAIL_TEXTURE_FAST_FLOAT_H_
#define TESSERA_DETAIL_TEXTURE_FAST_FLOAT_H_

#include <cstddef>
#include <cstring>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "tessera/detail/texture_addressing.h"
#include "tessera/detail/texture_fast.h"
#include "tessera/detail/texture_modes.h"
#include "tessera/detail/texture_view.h"

namespace tessera::texture {

/* TesseraTextureView::fast_linear: 0, or (dimensions << 4) | channels of a view this lookup
 * takes. Views of 1D, layered and cubemap textures, integer and half texels, several mip levels
 * read with mip filtering, nearest filtering, array indices and mirror or border wrapping take the
 * general path. */
inline unsigned FastLinearKind(const TesseraTextureView& v) {
  unsigned channels = 0;
  switch (v.format) {
    case kFormatFloat:
      channels = 1;
      break;
    case kFormatFloat2:
      channels = 2;
      break;
    case kFormatFloat4:
      channels = 4;
      break;
    default:
      return 0;
  }
  const unsigned d = v.dimensionality;
  const TesseraTextureLevel& lv = v.levels[0];
  const bool fits = v.element_size == 4 * channels && (d == 2 || d == 3) && v.layered == 0 &&
                    v.cubemap == 0 && v.index_mode == kIndexNormalizedCoordinates &&
                    v.mag_filter == kFilterLinear && v.min_filter == kFilterLinear &&
                    (v.level_count <= 1 || v.mip_filter == kFilterNone) && lv.data != nullptr &&
                    lv.width > 0 && lv.height > 0 && lv.depth > 0 && lv.width < (1u << 24) &&
                    lv.height < (1u << 24) && lv.depth < (1u << 24);
  if (!fits) return 0;
  for (unsigned a = 0; a < d; ++a) {
    if (v.wrap[a] != kWrapClampToEdge && v.wrap[a] != kWrapRepeat) return 0;
  }
  return (d << 4) | channels;
}

// Stores both fast kinds of a view: what an engine does once for each view it fills.
inline void MarkFastLookups(TesseraTextureView& v) {
  v.fast = FastKind(v);
  v.fast_linear = FastLinearKind(v);
}

namespace detail {

// One axis of a linear lookup at a normalized coordinate, its wrap mode clamp to edge or repeat:
// AxisAt with the mode a constant in each branch.
TESSERA_TEXTURE_INLINE Axis FastLinearAxis(float x, unsigned n, unsigned wrap) {
  return wrap == kWrapRepeat ? AxisAt<true>(x, static_cast<int>(n), kWrapRepeat, true)
                             : AxisAt<true>(x, static_cast<int>(n), kWrapClampToEdge, true);
}

// Calls tap(weight, first channel) for each texel of a linear lookup on axes `ax`, in the
// general path's order: z, then y, then x.
template <int D, int C, typename Tap>
TESSERA_TEXTURE_INLINE void ForEachTap(const Axis (&ax)[3], const float* base, std::size_t row,
                                       std::size_t slice, Tap&& tap) {
#pragma GCC unroll 2
  for (int k = 0; k < (D == 3 ? 2 : 1); ++k) {
#pragma GCC unroll 2
    for (int j = 0; j < 2; ++j) {
#pragma GCC unroll 2
      for (int i = 0; i < 2; ++i) {
        tap(ax[0].weight[i] * ax[1].weight[j] * ax[2].weight[k],
            base + (ax[0].index[i] + ax[1].index[j] * row + ax[2].index[k] * slice) * C);
      }
    }
  }
}

// The lookup at x[0, D) into out[0, C), for a view whose fast_linear is (D << 4) | C.
template <int D, int C>
TESSERA_TEXTURE_INLINE void FastLinearFloat(const TesseraTextureView& v, const float* x,
                                            float out[4]) {
  static_assert(D == 2 || D == 3);
  static_assert(C == 1 || C == 2 || C == 4);
  constexpr int kBits = 8 * D;
  const TesseraTextureLevel& lv = v.levels[0];
  const unsigned size[3] = {lv.width, lv.height, lv.depth};
  Axis ax[3];
#pragma GCC unroll 3
  for (int a = 0; a < D; ++a) ax[a] = FastLinearAxis(x[a], size[a], v.wrap[a]);
  if constexpr (D == 2) ax[2] = Axis{{0, 0}, {1, 0}, {1, 1}};
  const auto* base = static_cast<const float*>(lv.data);
  const std::size_t row = RowTexels(lv), slice = row * lv.height;
  constexpr double kScale = 1.0 / double(1u << kBits);
#if defined(__SSE2__)
  if constexpr (C != 1) {
    __m128d lo = _mm_setzero_pd(), hi = _mm_setzero_pd();
    ForEachTap<D, C>(ax, base, row, slice, [&](int w, const float* t) {
      const __m128d weight = _mm_set1_pd(static_cast<double>(w));
      const __m128d keep = _mm_castsi128_pd(_mm_set1_epi64x(w != 0 ? -1 : 0));
      if constexpr (C == 4) {
        const __m128 q = _mm_loadu_ps(t);
        lo = _mm_add_pd(lo, _mm_and_pd(_mm_mul_pd(_mm_cvtps_pd(q), weight), keep));
        hi =
            _mm_add_pd(hi, _mm_and_pd(_mm_mul_pd(_mm_cvtps_pd(_mm_movehl_ps(q, q)), weight), keep));
      } else {
        const __m128 q = _mm_castsi128_ps(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(t)));
        lo = _mm_add_pd(lo, _mm_and_pd(_mm_mul_pd(_mm_cvtps_pd(q), weight), keep));
      }
    });
    const __m128d scale = _mm_set1_pd(kScale);
    const __m128 l = _mm_cvtpd_ps(_mm_mul_pd(lo, scale));
    if constexpr (C == 4) {
      const __m128 h = _mm_cvtpd_ps(_mm_mul_pd(hi, scale));
      _mm_storeu_ps(out, _mm_movelh_ps(l, h));
    } else {
      _mm_storel_epi64(reinterpret_cast<__m128i*>(out), _mm_castps_si128(l));
    }
    return;
  }
#endif
  double acc[C] = {};
  ForEachTap<D, C>(ax, base, row, slice, [&](int w, const float* t) {
#pragma GCC unroll 4
    for (int c = 0; c < C; ++c) acc[c] += w != 0 ? w * double(t[c]) : 0.0;
  });
#pragma GCC unroll 4
  for (int c = 0; c < C; ++c) out[c] = static_cast<float>(acc[c] * kScale);
}

// The lookup for a view whose fast_linear has D dimensions: out[] holds (0, 0, 0, 1) beyond the
// view's channels, as the general path leaves it.
template <int D>
TESSERA_TEXTURE_INLINE void FastLinear(const TesseraTextureView& v, const float* x, float out[4]) {
  switch (v.fast_linear & 0xF) {
    case 1:
      FastLinearFloat<D, 1>(v, x, out);
      return;
    case 2:
      FastLinearFloat<D, 2>(v, x, out);
      return;
    default:
      FastLinearFloat<D, 4>(v, x, out);
  }
}

}  // namespace detail
}  // namespace tessera::texture

#endif  // TESSERA_DETAIL_TEXTURE_FAST_FLOAT_H_

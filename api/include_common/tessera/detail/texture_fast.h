/* The commonest lookup without the general path's dispatch: a bilinear read of a 2D RGBA8
 * texture as normalized floats, at normalized coordinates, clamped to the edge or repeated, from
 * one mip level (an LDR image read by tex2D). Both axes are addressed at once in SSE registers.
 * The engine marks the views it fits (TesseraTextureView::fast, set from FastKind when it fills
 * them); the result is bit for bit the general path's (tests/texture checks it).
 *
 * Why the result is exact whatever the order of the sums: a texel is an integer below 256 and a
 * weight an integer product of two 1/256 steps, so every partial sum is an integer below 2^24,
 * which a float holds exactly; one division ends the lookup in both paths. */
#ifndef TESSERA_DETAIL_TEXTURE_FAST_H_
#define TESSERA_DETAIL_TEXTURE_FAST_H_

#include <cstddef>
#include <cstring>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "tessera/detail/texture_modes.h"
#include "tessera/detail/texture_view.h"

namespace tessera::texture {

/* Values of TesseraTextureView::fast: the lookup above with both axes clamped to the edge, or
 * both repeated (other wrap modes, and mixed ones, take the general path). */
enum FastKindValue : unsigned {
  kFastNone = 0,
  kFastBilinearRgba8Clamp = 1,
  kFastBilinearRgba8Repeat = 2,
};

// The fast kind a view fits. Not computed per lookup: the engine stores it in the view.
inline unsigned FastKind(const TesseraTextureView& v) {
#if defined(__SSE2__)
  const TesseraTextureLevel& lv = v.levels[0];
  const bool fits =
      v.format == kFormatUnsignedByte4 && v.element_size == 4 && v.dimensionality == 2 &&
      v.layered == 0 && v.cubemap == 0 && v.read_mode == kReadNormalizedFloat &&
      v.index_mode == kIndexNormalizedCoordinates && v.mag_filter == kFilterLinear &&
      v.min_filter == kFilterLinear && (v.level_count <= 1 || v.mip_filter == kFilterNone) &&
      lv.data != nullptr && lv.width > 0 && lv.height > 0 && lv.depth > 0 &&
      lv.width < (1u << 24) && lv.height < (1u << 24);
  if (!fits || v.wrap[0] != v.wrap[1]) return kFastNone;
  if (v.wrap[0] == kWrapClampToEdge) return kFastBilinearRgba8Clamp;
  if (v.wrap[0] == kWrapRepeat) return kFastBilinearRgba8Repeat;
#else
  (void)v;
#endif
  return kFastNone;
}

namespace detail {

#if defined(__SSE2__)
#define TESSERA_TEXTURE_FAST inline __attribute__((always_inline))

// The constants of a lookup, as memory operands: GCC otherwise builds each splat with two
// instructions per call, and a lookup is a call of its own in a program.
struct alignas(16) FastConstants {
  float one[4], half[4], minus_one[4], k256[4], abs_mask_bits[4], k2_23[4], next[4], scale[4];
};
inline constexpr FastConstants kFast = {
    {1.f, 1.f, 1.f, 1.f},     {.5f, .5f, .5f, .5f},
    {-1.f, -1.f, -1.f, -1.f}, {256.f, 256.f, 256.f, 256.f},
    {-0.f, -0.f, -0.f, -0.f}, {8388608.f, 8388608.f, 8388608.f, 8388608.f},
    {0.f, 0.f, 1.f, 1.f},     {255.f * 65536.f, 255.f * 65536.f, 255.f * 65536.f, 255.f * 65536.f},
};
TESSERA_TEXTURE_FAST __m128 Const(const float (&c)[4]) { return _mm_load_ps(c); }

// floor of each lane for |x| < 2^31.
TESSERA_TEXTURE_FAST __m128 FloorLanes(__m128 x) {
  const __m128 t = _mm_cvtepi32_ps(_mm_cvttps_epi32(x));
  return _mm_sub_ps(t, _mm_and_ps(_mm_cmpgt_ps(t, x), Const(kFast.one)));
}

// The lookup at (x, y) into out[4]; lanes 0 and 1 hold the x and y axes. The steps are those of
// detail::AxisAt for normalized coordinates:
//   NaN reads as 0; repeat takes frac(c) (0 beyond 2^23, where every float is an integer);
//   t = c * n - 0.5, clamped to [-1, n]; i = floor(t); alpha = round((t - i) * 256);
//   repeat wraps i and i + 1 into [0, n), clamp to edge clamps them.
// The two texels of a row blend in integers (pmaddwd: texel * (256 - a) + texel' * a, below
// 2^16), the two rows in floats (below 2^24, exact), and one division ends it, as in FilterLevel.
template <bool kRepeat>
TESSERA_TEXTURE_FAST void FastBilinearRgba8(const TesseraTextureView& v, float x, float y,
                                            float out[4]) {
  const TesseraTextureLevel& lv = v.levels[0];
  const __m128 size = _mm_unpacklo_ps(_mm_cvtsi32_ss(_mm_setzero_ps(), int(lv.width)),
                                      _mm_cvtsi32_ss(_mm_setzero_ps(), int(lv.height)));
  __m128 c = _mm_unpacklo_ps(_mm_set_ss(x), _mm_set_ss(y));
  c = _mm_and_ps(c, _mm_cmpord_ps(c, c));
  if constexpr (kRepeat) {
    const __m128 abs_c = _mm_andnot_ps(Const(kFast.abs_mask_bits), c);
    c = _mm_and_ps(_mm_sub_ps(c, FloorLanes(c)), _mm_cmplt_ps(abs_c, Const(kFast.k2_23)));
  }
  __m128 t = _mm_sub_ps(_mm_mul_ps(c, size), Const(kFast.half));
  t = _mm_min_ps(_mm_max_ps(t, Const(kFast.minus_one)), size);
  const __m128 i = FloorLanes(t);
  const __m128 alpha = _mm_cvtepi32_ps(_mm_cvttps_epi32(
      _mm_add_ps(_mm_mul_ps(_mm_sub_ps(t, i), Const(kFast.k256)), Const(kFast.half))));
  // Texel indices (i, j, i + 1, j + 1), wrapped or clamped.
  const __m128 size4 = _mm_movelh_ps(size, size);
  __m128 index = _mm_add_ps(_mm_movelh_ps(i, i), Const(kFast.next));
  if constexpr (kRepeat) {
    const __m128 below = _mm_and_ps(_mm_cmplt_ps(index, _mm_setzero_ps()), size4);
    const __m128 above = _mm_and_ps(_mm_cmpge_ps(index, size4), size4);
    index = _mm_add_ps(index, _mm_sub_ps(below, above));
  }
  index = _mm_min_ps(_mm_max_ps(index, _mm_setzero_ps()), _mm_sub_ps(size4, Const(kFast.one)));
  alignas(16) int at[4];
  _mm_store_si128(reinterpret_cast<__m128i*>(at), _mm_cvttps_epi32(index));
  const auto* base = static_cast<const unsigned char*>(lv.data);
  const std::size_t row = std::size_t(lv.pitch != 0 ? lv.pitch : lv.width) * 4;
  const unsigned char* r0 = base + std::size_t(at[1]) * row;
  const unsigned char* r1 = base + std::size_t(at[3]) * row;
  const std::size_t x0 = std::size_t(at[0]) * 4, x1 = std::size_t(at[2]) * 4;
  int b00, b10, b01, b11;
  std::memcpy(&b00, r0 + x0, 4);
  std::memcpy(&b10, r0 + x1, 4);
  std::memcpy(&b01, r1 + x0, 4);
  std::memcpy(&b11, r1 + x1, 4);
  // (256 - a, a) as 16-bit pairs, one per channel.
  const int a = _mm_cvttss_si32(alpha);
  const __m128i wx = _mm_set1_epi32(a * 65535 + 256);
  const __m128i zero = _mm_setzero_si128();
  // Channels of a row's two texels interleaved: r r' g g' b b' a a', in 16 bits.
  const __m128i p0 =
      _mm_unpacklo_epi8(_mm_unpacklo_epi8(_mm_cvtsi32_si128(b00), _mm_cvtsi32_si128(b10)), zero);
  const __m128i p1 =
      _mm_unpacklo_epi8(_mm_unpacklo_epi8(_mm_cvtsi32_si128(b01), _mm_cvtsi32_si128(b11)), zero);
  const __m128 row0 = _mm_cvtepi32_ps(_mm_madd_epi16(p0, wx));
  const __m128 row1 = _mm_cvtepi32_ps(_mm_madd_epi16(p1, wx));
  const __m128 b = _mm_shuffle_ps(alpha, alpha, 0x55);
  const __m128 sum =
      _mm_add_ps(_mm_mul_ps(row0, _mm_sub_ps(Const(kFast.k256), b)), _mm_mul_ps(row1, b));
  _mm_storeu_ps(out, _mm_div_ps(sum, Const(kFast.scale)));
}
#undef TESSERA_TEXTURE_FAST
#endif

}  // namespace detail
}  // namespace tessera::texture

#endif  // TESSERA_DETAIL_TEXTURE_FAST_H_

/* Texture addressing (tessera/detail/texture_sampling.h): which texels one axis of a lookup
 * reads and with what weights (wrap modes, CUDA's 9-bit linear weights), what a lookup asks for
 * (coordinates, layer, cube face) and where its plane of texels starts in a level. */
#ifndef TESSERA_DETAIL_TEXTURE_ADDRESSING_H_
#define TESSERA_DETAIL_TEXTURE_ADDRESSING_H_

#include <cmath>
#include <cstddef>

#include "tessera/detail/texture_formats.h"

namespace tessera::texture {
namespace detail {

// ---- Addressing ------------------------------------------------------------------------------

// floor for |x| < 2^31 (callers clamp first): std::floor is a library call at -O2 on x86-64.
TESSERA_TEXTURE_INLINE int FloorToInt(float x) {
  const int i = static_cast<int>(x);
  return i - (static_cast<float>(i) > x ? 1 : 0);
}

// x - floor(x) for any float: beyond 2^23 every float is an integer (0), NaN and inf give 0.
TESSERA_TEXTURE_INLINE float Frac(float x, bool* odd_floor) {
  if (!(std::fabs(x) < 8388608.f)) {
    *odd_floor = false;
    return 0.f;
  }
  const int i = FloorToInt(x);
  *odd_floor = (i & 1) != 0;
  return x - static_cast<float>(i);
}

// The texels one axis contributes: indices, weights (in 1/256 for linear, 0 or 1 for nearest;
// 0 for a border texel) and whether each index is inside (not a border texel, for gather).
struct Axis {
  int index[2];
  int weight[2];
  int inside[2];
};

TESSERA_TEXTURE_INLINE int ClampIndex(int i, int n) {
  i = i < n ? i : n - 1;
  return i > 0 ? i : 0;
}

// One axis of a lookup at coordinate x on an n-texel axis.
// Nearest (CUDA guide): T[floor(x)]. Linear: xB = x - 0.5, i = floor(xB), alpha = frac(xB) in
// 9-bit fixed point with 8 fractional bits. Rounding alpha to the nearest 1/256 (ties up) is an
// assumption: the guide says how alpha is stored, not how it is rounded (docs/textures.md).
// Normalized coordinates are scaled by n; repeat and mirror apply to them only (with array
// indices they clamp, as in CUDA), first to the coordinate as the guide states (repeat: frac(x);
// mirror: frac(x), or 1 - frac(x) where floor(x) is odd), then to the neighbor past an edge. NaN
// reads as 0; every index ends inside [0, n) whatever the input.
template <bool kLinear>
TESSERA_TEXTURE_INLINE Axis AxisAt(float x, int n, unsigned wrap, bool normalized) {
  x = x == x ? x : 0.f;
  const float size = static_cast<float>(n);
  constexpr float kOffset = kLinear ? 0.5f : 0.f;
  int i, i0, i1;
  float t;
  Axis a;
  if (normalized && (wrap == kWrapRepeat || wrap == kWrapMirror)) {
    bool odd;
    float f = Frac(x, &odd);
    if (wrap == kWrapMirror && odd) f = 1.f - f;
    t = f * size - kOffset;  // in [-0.5, n]: i in [-1, n]
    i = FloorToInt(t);
    if (wrap == kWrapRepeat) {
      i0 = i < 0 ? i + n : (i >= n ? i - n : i);
      i1 = i + 1 >= n ? i + 1 - n : i + 1;
    } else {
      i0 = i;  // -1 mirrors to 0 and n to n - 1: the clamp below
      i1 = i + 1;
    }
    a.inside[0] = a.inside[1] = 1;
  } else {
    t = (normalized ? x * size : x) - kOffset;
    t = t > -1.f ? t : -1.f;  // inf lands on an edge and the int conversion is defined
    t = t < size ? t : size;
    i = FloorToInt(t);
    i0 = i;
    i1 = i + 1;
    const bool border = wrap == kWrapClampToBorder;
    a.inside[0] = !border || static_cast<unsigned>(i) < static_cast<unsigned>(n);
    a.inside[1] = !border || static_cast<unsigned>(i + 1) < static_cast<unsigned>(n);
  }
  a.index[0] = ClampIndex(i0, n);
  if (kLinear) {
    const int alpha = static_cast<int>((t - static_cast<float>(i)) * 256.f + 0.5f);
    a.index[1] = ClampIndex(i1, n);
    a.weight[0] = (256 - alpha) * a.inside[0];
    a.weight[1] = alpha * a.inside[1];
  } else {
    a.inside[1] = a.inside[0];
    a.index[1] = a.index[0];
    a.weight[0] = a.inside[0];
    a.weight[1] = 0;
  }
  return a;
}

// What one lookup asks for, independent of the level: coordinates (normalized or texels), the
// layer and cube face (a plane of depth = layer * faces + face), and the wrap mode per axis.
struct Request {
  float x[3];
  int layer;
  int face;
  int faces;
  unsigned wrap[3];
  bool normalized;
};

inline Request MakeRequest(const TesseraTextureView& v, float x, float y, float z, int layer) {
  Request r;
  r.x[0] = x;
  r.x[1] = y;
  r.x[2] = z;
  r.layer = layer;
  r.face = 0;
  r.faces = 1;
  r.normalized = v.index_mode == kIndexNormalizedCoordinates;
  r.wrap[0] = v.wrap[0];
  r.wrap[1] = v.wrap[1];
  r.wrap[2] = v.wrap[2];
  return r;
}

// CUDA's cubemap fetch (guide, table "Cubemap Fetch"): the face is the major axis of (x, y, z)
// and its sign; (s, t) = ((sc / |ma| + 1) / 2, (tc / |ma| + 1) / 2) with
//   +x: sc = -z, tc = -y   -x: sc = z, tc = -y   +y: sc = x, tc = z
//   -y: sc = x, tc = -z    +z: sc = x, tc = -y   -z: sc = -x, tc = -y
// Ties, which the table leaves open, go to x, then y. Faces are sampled with normalized
// coordinates clamped to their edges (no filtering across faces).
inline Request CubeRequest(const TesseraTextureView& v, float x, float y, float z, int layer) {
  x = x == x ? x : 0.f;
  y = y == y ? y : 0.f;
  z = z == z ? z : 0.f;
  const float ax = std::fabs(x), ay = std::fabs(y), az = std::fabs(z);
  Request r = MakeRequest(v, 0.f, 0.f, 0.f, layer);
  float sc, tc, ma;
  if (ax >= ay && ax >= az) {
    ma = ax;
    r.face = x >= 0.f ? 0 : 1;
    sc = x >= 0.f ? -z : z;
    tc = -y;
  } else if (ay >= az) {
    ma = ay;
    r.face = y >= 0.f ? 2 : 3;
    sc = x;
    tc = y >= 0.f ? z : -z;
  } else {
    ma = az;
    r.face = z >= 0.f ? 4 : 5;
    sc = z >= 0.f ? x : -x;
    tc = -y;
  }
  // A zero vector gives 0/0: NaN, which the addressing reads as 0.
  r.x[0] = (sc / ma + 1.f) * 0.5f;
  r.x[1] = (tc / ma + 1.f) * 0.5f;
  r.faces = 6;
  r.normalized = true;
  r.wrap[0] = r.wrap[1] = r.wrap[2] = kWrapClampToEdge;
  return r;
}

// The first texel of the request's plane in a level, or null when the level holds no texels.
// Layers (and cube layers) past the last read the last one, before the first the first.
template <typename F, int D>
TESSERA_TEXTURE_INLINE const typename F::Scalar* PlaneBase(const TesseraTextureLevel& lv,
                                                           const Request& r) {
  if (lv.data == nullptr || lv.width == 0 || lv.height == 0 || lv.depth == 0) return nullptr;
  const auto* base = static_cast<const typename F::Scalar*>(lv.data);
  if constexpr (D == 3) {
    return base;
  } else {
    if (r.layer == 0 && r.face == 0) return base;  // plane 0: no layer arithmetic
    // A division by a constant: a plain `depth / faces` costs a hardware divide per lookup.
    const int depth = static_cast<int>(lv.depth);
    const int planes = r.faces == 1 ? depth : depth / 6;
    if (planes == 0) return nullptr;
    int layer = r.layer < planes ? r.layer : planes - 1;
    layer = layer > 0 ? layer : 0;
    const std::size_t plane = static_cast<std::size_t>(layer) * r.faces + r.face;
    return base + plane * RowTexels(lv) * lv.height * F::kChannels;
  }
}

}  // namespace detail
}  // namespace tessera::texture

#endif  // TESSERA_DETAIL_TEXTURE_ADDRESSING_H_

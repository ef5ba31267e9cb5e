/* Texture sampling for programs: what tex1D/tex2D/tex3D, their Lod/Grad/Layered/Cubemap forms,
 * tex2Dgather and the integer fetches compute, following the arithmetic of the CUDA Programming
 * Guide's "Texture Fetching" appendix so that images match a GPU's (docs/textures.md says how,
 * and where they may still differ). Header-only and allocation-free: a program module inlines it
 * and reads texels straight from the engine's memory through a TesseraTextureView.
 *
 * Everything a view says (format, read mode, filters, wrap modes) is read per call; the format and
 * read mode pick one instantiation with a single switch, so the texel loops below carry no
 * per-texel branch on them. */
#ifndef TESSERA_DETAIL_TEXTURE_SAMPLING_H_
#define TESSERA_DETAIL_TEXTURE_SAMPLING_H_

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <type_traits>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "optixu/optixu_vector_types.h"
#include "tessera/detail/texture_view.h"
#include "tessera/rt.h"

// The addressing and texel loops are forced inline into the one function per format and read
// mode that uses them: left to itself GCC calls them, and a lookup then pays for passing its
// request through memory.
#define TESSERA_TEXTURE_INLINE inline __attribute__((always_inline))

namespace tessera::texture {
namespace detail {

// ---- Result types: the program's declared element type ----------------------------------------

// kN components of type Scalar; Make builds T from the first kN of four values.
template <typename T>
struct Result;

#define TESSERA_TEX_SCALAR_RESULT(T)                \
  template <>                                       \
  struct Result<T> {                                \
    using Scalar = T;                               \
    static constexpr int kN = 1;                    \
    static T Make(const Scalar* c) { return c[0]; } \
  };
#define TESSERA_TEX_VECTOR_RESULTS(V, S)                                        \
  template <>                                                                   \
  struct Result<V##1> {                                                         \
    using Scalar = S;                                                           \
    static constexpr int kN = 1;                                                \
    static V##1 Make(const Scalar* c) { return V##1 {c[0]}; }                   \
  };                                                                            \
  template <>                                                                   \
  struct Result<V##2> {                                                         \
    using Scalar = S;                                                           \
    static constexpr int kN = 2;                                                \
    static V##2 Make(const Scalar* c) { return V##2 {c[0], c[1]}; }             \
  };                                                                            \
  template <>                                                                   \
  struct Result<V##3> {                                                         \
    using Scalar = S;                                                           \
    static constexpr int kN = 3;                                                \
    static V##3 Make(const Scalar* c) { return V##3 {c[0], c[1], c[2]}; }       \
  };                                                                            \
  template <>                                                                   \
  struct Result<V##4> {                                                         \
    using Scalar = S;                                                           \
    static constexpr int kN = 4;                                                \
    static V##4 Make(const Scalar* c) { return V##4 {c[0], c[1], c[2], c[3]}; } \
  };
TESSERA_TEX_SCALAR_RESULT(float)
TESSERA_TEX_SCALAR_RESULT(int)
TESSERA_TEX_SCALAR_RESULT(unsigned int)
TESSERA_TEX_SCALAR_RESULT(char)
TESSERA_TEX_SCALAR_RESULT(signed char)
TESSERA_TEX_SCALAR_RESULT(unsigned char)
TESSERA_TEX_SCALAR_RESULT(short)
TESSERA_TEX_SCALAR_RESULT(unsigned short)
TESSERA_TEX_VECTOR_RESULTS(float, float)
TESSERA_TEX_VECTOR_RESULTS(int, int)
TESSERA_TEX_VECTOR_RESULTS(uint, unsigned int)
TESSERA_TEX_VECTOR_RESULTS(char, signed char)
TESSERA_TEX_VECTOR_RESULTS(uchar, unsigned char)
TESSERA_TEX_VECTOR_RESULTS(short, short)
TESSERA_TEX_VECTOR_RESULTS(ushort, unsigned short)
#undef TESSERA_TEX_SCALAR_RESULT
#undef TESSERA_TEX_VECTOR_RESULTS

// A float result in an integer T saturates (NaN gives 0): a plain cast of an out-of-range float
// is undefined behavior.
template <typename D>
inline D FromFloat(float f) {
  if constexpr (std::is_floating_point_v<D>) {
    return f;
  } else {
    constexpr float kLow = static_cast<float>(std::numeric_limits<D>::min());
    constexpr float kHighExclusive =
        static_cast<float>(1ull << std::numeric_limits<D>::digits);  // a power of two: exact
    if (!(f == f)) return D(0);
    if (f <= kLow) return std::numeric_limits<D>::min();
    if (f >= kHighExclusive) return std::numeric_limits<D>::max();
    return static_cast<D>(f);
  }
}

// ---- Texel formats ---------------------------------------------------------------------------

// An IEEE binary16 texel channel (RT_FORMAT_HALF*), as stored.
struct Half {
  std::uint16_t bits;
};

// binary16 to float is exact: every half is a float.
inline float HalfToFloat(Half h) {
  const std::uint32_t sign = static_cast<std::uint32_t>(h.bits & 0x8000u) << 16;
  const std::uint32_t exponent = (h.bits >> 10) & 0x1fu, mantissa = h.bits & 0x3ffu;
  std::uint32_t bits;
  if (exponent == 0x1f) {
    bits = sign | 0x7f800000u | (mantissa << 13);  // inf, NaN
  } else if (exponent != 0) {
    bits = sign | ((exponent + 112) << 23) | (mantissa << 13);
  } else {
    // Zero and subnormals: mantissa * 2^-24, exact in float.
    const float magnitude = static_cast<float>(mantissa) * 5.9604644775390625e-8f;
    return sign != 0 ? -magnitude : magnitude;
  }
  float f;
  std::memcpy(&f, &bits, sizeof f);
  return f;
}

// C channels of type S per texel, packed (3-channel formats hold 3 elements, no padding).
template <typename S, int C>
struct Format {
  using Scalar = S;
  static constexpr int kChannels = C;
};

// Calls op(Format<S, C>{}) for the view's RTformat; a format with no texels (USER, BUFFER_ID,
// unknown) or an element_size that disagrees with it gives T{} (zeros) instead of a wild read.
template <typename T, typename Op>
inline T WithFormat(const TesseraTextureView& v, Op&& op) {
#define TESSERA_TEX_FORMAT_CASE(name, S, C) \
  case name:                                \
    return v.element_size == sizeof(S) * (C) ? op(Format<S, C>{}) : T{};
  switch (v.format) {
    TESSERA_TEX_FORMAT_CASE(RT_FORMAT_FLOAT, float, 1)
    TESSERA_TEX_FORMAT_CASE(RT_FORMAT_FLOAT2, float, 2)
    TESSERA_TEX_FORMAT_CASE(RT_FORMAT_FLOAT3, float, 3)
    TESSERA_TEX_FORMAT_CASE(RT_FORMAT_FLOAT4, float, 4)
    TESSERA_TEX_FORMAT_CASE(RT_FORMAT_BYTE, signed char, 1)
    TESSERA_TEX_FORMAT_CASE(RT_FORMAT_BYTE2, signed char, 2)
    TESSERA_TEX_FORMAT_CASE(RT_FORMAT_BYTE3, signed char, 3)
    TESSERA_TEX_FORMAT_CASE(RT_FORMAT_BYTE4, signed char, 4)
    TESSERA_TEX_FORMAT_CASE(RT_FORMAT_UNSIGNED_BYTE, unsigned char, 1)
    TESSERA_TEX_FORMAT_CASE(RT_FORMAT_UNSIGNED_BYTE2, unsigned char, 2)
    TESSERA_TEX_FORMAT_CASE(RT_FORMAT_UNSIGNED_BYTE3, unsigned char, 3)
    TESSERA_TEX_FORMAT_CASE(RT_FORMAT_UNSIGNED_BYTE4, unsigned char, 4)
    TESSERA_TEX_FORMAT_CASE(RT_FORMAT_SHORT, short, 1)
    TESSERA_TEX_FORMAT_CASE(RT_FORMAT_SHORT2, short, 2)
    TESSERA_TEX_FORMAT_CASE(RT_FORMAT_SHORT3, short, 3)
    TESSERA_TEX_FORMAT_CASE(RT_FORMAT_SHORT4, short, 4)
    TESSERA_TEX_FORMAT_CASE(RT_FORMAT_UNSIGNED_SHORT, unsigned short, 1)
    TESSERA_TEX_FORMAT_CASE(RT_FORMAT_UNSIGNED_SHORT2, unsigned short, 2)
    TESSERA_TEX_FORMAT_CASE(RT_FORMAT_UNSIGNED_SHORT3, unsigned short, 3)
    TESSERA_TEX_FORMAT_CASE(RT_FORMAT_UNSIGNED_SHORT4, unsigned short, 4)
    TESSERA_TEX_FORMAT_CASE(RT_FORMAT_INT, int, 1)
    TESSERA_TEX_FORMAT_CASE(RT_FORMAT_INT2, int, 2)
    TESSERA_TEX_FORMAT_CASE(RT_FORMAT_INT3, int, 3)
    TESSERA_TEX_FORMAT_CASE(RT_FORMAT_INT4, int, 4)
    TESSERA_TEX_FORMAT_CASE(RT_FORMAT_UNSIGNED_INT, unsigned int, 1)
    TESSERA_TEX_FORMAT_CASE(RT_FORMAT_UNSIGNED_INT2, unsigned int, 2)
    TESSERA_TEX_FORMAT_CASE(RT_FORMAT_UNSIGNED_INT3, unsigned int, 3)
    TESSERA_TEX_FORMAT_CASE(RT_FORMAT_UNSIGNED_INT4, unsigned int, 4)
    TESSERA_TEX_FORMAT_CASE(RT_FORMAT_HALF, Half, 1)
    TESSERA_TEX_FORMAT_CASE(RT_FORMAT_HALF2, Half, 2)
    TESSERA_TEX_FORMAT_CASE(RT_FORMAT_HALF3, Half, 3)
    TESSERA_TEX_FORMAT_CASE(RT_FORMAT_HALF4, Half, 4)
    default:
      return T{};
  }
#undef TESSERA_TEX_FORMAT_CASE
}

// sRGB-encoded 8-bit value to linear: the IEC 61966-2-1 curve evaluated in double precision and
// rounded once to float (a table, not std::pow, so every machine computes the same bits).
inline constexpr float kSrgbToLinear[256] = {
    0.0f,           0.000303526991f, 0.000607053982f, 0.000910580973f, 0.00121410796f,
    0.00151763496f, 0.00182116195f,  0.00212468882f,  0.00242821593f,  0.0027317428f,
    0.00303526991f, 0.00334653584f,  0.00367650739f,  0.00402471703f,  0.00439144205f,
    0.00477695325f, 0.00518151652f,  0.00560539169f,  0.00604883302f,  0.00651209056f,
    0.00699541019f, 0.00749903219f,  0.00802319311f,  0.00856812578f,  0.00913405884f,
    0.00972121768f, 0.010329823f,    0.0109600937f,   0.0116122449f,   0.012286488f,
    0.0129830325f,  0.0137020834f,   0.0144438436f,   0.0152085144f,   0.0159962941f,
    0.0168073755f,  0.0176419541f,   0.01850022f,     0.0193823613f,   0.0202885624f,
    0.0212190095f,  0.0221738853f,   0.0231533665f,   0.0241576321f,   0.0251868591f,
    0.0262412224f,  0.0273208916f,   0.02842604f,     0.0295568351f,   0.0307134446f,
    0.0318960324f,  0.0331047662f,   0.0343398079f,   0.0356013142f,   0.0368894488f,
    0.0382043719f,  0.0395462364f,   0.0409151986f,   0.0423114114f,   0.043735031f,
    0.045186203f,   0.0466650873f,   0.0481718257f,   0.0497065671f,   0.0512694567f,
    0.0528606474f,  0.054480277f,    0.0561284907f,   0.0578054301f,   0.0595112368f,
    0.0612460524f,  0.0630100146f,   0.064803265f,    0.0666259378f,   0.0684781671f,
    0.0703600943f,  0.0722718537f,   0.0742135718f,   0.0761853829f,   0.078187421f,
    0.0802198201f,  0.0822827071f,   0.0843762085f,   0.0865004584f,   0.0886555836f,
    0.0908417106f,  0.0930589661f,   0.0953074694f,   0.097587347f,    0.0998987257f,
    0.102241732f,   0.104616486f,    0.107023105f,    0.10946171f,     0.111932427f,
    0.114435375f,   0.116970666f,    0.119538426f,    0.122138776f,    0.124771819f,
    0.127437681f,   0.130136475f,    0.13286832f,     0.135633335f,    0.138431609f,
    0.141263291f,   0.144128472f,    0.147027269f,    0.149959788f,    0.152926147f,
    0.155926466f,   0.158960834f,    0.162029371f,    0.165132195f,    0.168269396f,
    0.171441108f,   0.174647406f,    0.177888423f,    0.18116425f,     0.18447499f,
    0.187820777f,   0.191201687f,    0.194617838f,    0.198069319f,    0.20155625f,
    0.205078736f,   0.208636865f,    0.212230757f,    0.215860501f,    0.219526201f,
    0.223227963f,   0.226965874f,    0.230740055f,    0.23455058f,     0.238397568f,
    0.242281124f,   0.246201321f,    0.25015828f,     0.254152089f,    0.258182853f,
    0.262250662f,   0.266355604f,    0.270497799f,    0.274677306f,    0.278894275f,
    0.283148736f,   0.287440836f,    0.291770637f,    0.296138257f,    0.300543785f,
    0.304987311f,   0.309468925f,    0.313988715f,    0.318546772f,    0.323143214f,
    0.327778101f,   0.332451522f,    0.337163627f,    0.341914415f,    0.346704066f,
    0.351532608f,   0.356400132f,    0.361306787f,    0.366252601f,    0.371237695f,
    0.376262128f,   0.38132602f,     0.386429429f,    0.391572475f,    0.396755219f,
    0.401977777f,   0.407240212f,    0.412542611f,    0.417885065f,    0.423267663f,
    0.428690493f,   0.434153646f,    0.439657182f,    0.445201188f,    0.450785786f,
    0.456411034f,   0.462076992f,    0.467783809f,    0.473531485f,    0.479320168f,
    0.48514995f,    0.491020858f,    0.496932983f,    0.502886474f,    0.50888133f,
    0.514917672f,   0.520995557f,    0.527115107f,    0.533276379f,    0.539479494f,
    0.545724452f,   0.55201143f,     0.558340371f,    0.564711511f,    0.571124852f,
    0.577580452f,   0.584078431f,    0.590618849f,    0.597201765f,    0.603827357f,
    0.610495567f,   0.617206573f,    0.623960376f,    0.630757153f,    0.637596846f,
    0.644479692f,   0.651405632f,    0.658374846f,    0.665387273f,    0.672443151f,
    0.679542482f,   0.686685324f,    0.693871737f,    0.701101899f,    0.708375752f,
    0.715693474f,   0.723055124f,    0.730460763f,    0.73791039f,     0.745404184f,
    0.752942204f,   0.760524511f,    0.768151164f,    0.775822222f,    0.783537805f,
    0.791297913f,   0.799102724f,    0.806952238f,    0.814846575f,    0.822785735f,
    0.830769897f,   0.838799f,       0.846873224f,    0.854992628f,    0.863157213f,
    0.871367097f,   0.8796224f,      0.887923121f,    0.896269381f,    0.904661179f,
    0.913098633f,   0.921581864f,    0.930110872f,    0.938685715f,    0.947306514f,
    0.955973327f,   0.964686275f,    0.973445296f,    0.982250571f,    0.991102099f,
    1.0f,
};

// ---- Read modes ------------------------------------------------------------------------------

// How texels become results, decided once per call from the format and view.read_mode:
// Element returns integer texels as stored (no filtering: CUDA filters only float results);
// Float, Unorm (c / max), Snorm (max(c / max, -1)) and Srgb (unsigned bytes, R, G, B decoded to
// linear, alpha as Unorm) produce floats that may be filtered.
struct ModeElement {};
struct ModeFloat {};
struct ModeUnorm {};
struct ModeSnorm {};
struct ModeSrgb {};

inline bool ReadsNormalized(const TesseraTextureView& v) {
  return v.read_mode == 1 || v.read_mode == 3;
}
inline bool ReadsSrgb(const TesseraTextureView& v) { return v.read_mode == 2 || v.read_mode == 3; }

// Normalized-float reads exist for 8- and 16-bit integers only (as in CUDA); 32-bit integers are
// returned by value. sRGB decoding applies to unsigned bytes read as normalized float: an
// element-type read returns the stored integers, which cannot hold linear values.
template <typename F, typename Op>
inline auto WithMode(const TesseraTextureView& v, Op&& op) {
  using S = typename F::Scalar;
  if constexpr (std::is_same_v<S, float> || std::is_same_v<S, Half>) {
    return op(ModeFloat{});
  } else if constexpr (sizeof(S) <= 2) {
    if (!ReadsNormalized(v)) return op(ModeElement{});
    if constexpr (std::is_signed_v<S>) {
      return op(ModeSnorm{});
    } else if constexpr (sizeof(S) == 1) {
      if (ReadsSrgb(v)) return op(ModeSrgb{});
      return op(ModeUnorm{});
    } else {
      return op(ModeUnorm{});
    }
  } else {
    return op(ModeElement{});
  }
}

// Per-channel arithmetic of a float-producing mode. Texel weights are integers (products of the
// per-axis 9-bit weights, 2^kBits for a full texel): Weighted() gives weight * value in the
// accumulator type, Finish<kBits>() the float of the sum. Integer texels accumulate exactly and
// are divided once, so the result is the exact weighted sum rounded once to float.
template <typename F, typename Mode>
struct Channels;

inline float FloatValue(float f) { return f; }
inline float FloatValue(Half h) { return HalfToFloat(h); }

// Float and half texels (halves read as the floats they are, in either read mode, as CUDA's
// 16-bit float textures do).
template <typename F>
struct Channels<F, ModeFloat> {
  template <int kBits>
  using Acc = double;  // weight (<= 2^24) * float fits a double's 53 bits exactly
  // A zero weight contributes nothing even when the texel is inf or NaN, so an exactly hit texel
  // does not turn into NaN because of its neighbor.
  template <int kBits>
  TESSERA_TEXTURE_INLINE static double Weighted(int w, const typename F::Scalar* t, int c) {
    return w != 0 ? w * double(FloatValue(t[c])) : 0.0;
  }
  template <int kBits>
  TESSERA_TEXTURE_INLINE static float Finish(double a) {
    return static_cast<float>(a * (1.0 / double(1u << kBits)));
  }
};

template <typename F>
struct Channels<F, ModeSrgb> {
  template <int kBits>
  using Acc = double;
  template <int kBits>
  TESSERA_TEXTURE_INLINE static double Weighted(int w, const unsigned char* t, int c) {
    return w * (c < 3 ? double(kSrgbToLinear[t[c]]) : double(t[c]) / 255.0);
  }
  template <int kBits>
  TESSERA_TEXTURE_INLINE static float Finish(double a) {
    return static_cast<float>(a * (1.0 / double(1u << kBits)));
  }
};

template <typename F, bool kSigned>
struct IntegerChannels {
  using S = typename F::Scalar;
  static constexpr std::int64_t kMax = std::numeric_limits<S>::max();
  // The weights of a lookup sum to 2^kBits, so no partial sum exceeds kMax << kBits: below 2^24
  // a float holds every product and sum exactly (and float arithmetic vectorizes best).
  template <int kBits>
  using Acc = std::conditional_t<(kMax << kBits) < (std::int64_t(1) << 24), float, std::int64_t>;
  // Signed normalized: the most negative value reads as -1 like the one above it (CUDA's
  // max(c / max, -1)).
  template <int kBits>
  TESSERA_TEXTURE_INLINE static Acc<kBits> Weighted(int w, const S* t, int c) {
    const int value = kSigned && t[c] < -kMax ? int(-kMax) : int(t[c]);
    return Acc<kBits>(w) * Acc<kBits>(value);
  }
  template <int kBits, typename A>
  TESSERA_TEXTURE_INLINE static float Finish(A a) {
    constexpr std::int64_t kDenominator = kMax << kBits;
    if constexpr (kDenominator < (std::int64_t(1) << 24)) {
      // Both sides exact in float: one correctly rounded division.
      return static_cast<float>(a) / static_cast<float>(kDenominator);
    } else {
      return static_cast<float>(static_cast<double>(a) / static_cast<double>(kDenominator));
    }
  }
};
template <typename F>
struct Channels<F, ModeUnorm> : IntegerChannels<F, false> {};
template <typename F>
struct Channels<F, ModeSnorm> : IntegerChannels<F, true> {};

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
  if (normalized && (wrap == RT_WRAP_REPEAT || wrap == RT_WRAP_MIRROR)) {
    bool odd;
    float f = Frac(x, &odd);
    if (wrap == RT_WRAP_MIRROR && odd) f = 1.f - f;
    t = f * size - kOffset;  // in [-0.5, n]: i in [-1, n]
    i = FloorToInt(t);
    if (wrap == RT_WRAP_REPEAT) {
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
    const bool border = wrap == RT_WRAP_CLAMP_TO_BORDER;
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
  r.normalized = v.index_mode == RT_TEXTURE_INDEX_NORMALIZED_COORDINATES;
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
  r.wrap[0] = r.wrap[1] = r.wrap[2] = RT_WRAP_CLAMP_TO_EDGE;
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
    return base + plane * lv.width * lv.height * F::kChannels;
  }
}

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
  const std::size_t row = lv.width, slice = std::size_t(lv.width) * lv.height;
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
  const bool linear = (Magnifies(lod) ? v.mag_filter : v.min_filter) == RT_FILTER_LINEAR;
  const int count = LevelCount(v);
  int level = 0, q = 0;  // q: the weight of level + 1, in 1/256
  if (count > 1 && v.mip_filter != RT_FILTER_NONE) {
    const float top = static_cast<float>(count - 1);
    lod = lod > 0.f ? (lod < top ? lod : top) : 0.f;
    if (v.mip_filter == RT_FILTER_LINEAR) {
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
  if (LevelCount(v) > 1 && v.mip_filter != RT_FILTER_NONE) {
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
  const std::size_t texel = ax[0].index[0] + ax[1].index[0] * std::size_t(lv.width) +
                            ax[2].index[0] * std::size_t(lv.width) * lv.height;
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

// RGBA8 read as normalized float from one level with one filter: the commonest texture gets a
// path without the format, read mode and mip dispatch. Same arithmetic as the general path.
inline bool IsPlainRgba8(const TesseraTextureView& v) {
  return v.format == RT_FORMAT_UNSIGNED_BYTE4 && v.element_size == 4 && v.read_mode == 1 &&
         (v.level_count <= 1 || v.mip_filter == RT_FILTER_NONE) && v.mag_filter == v.min_filter;
}

template <typename T, int D>
inline T SampleLod(const TesseraTextureView& v, const Request& r, float lod) {
  if (IsPlainRgba8(v)) {
    using F = Format<unsigned char, 4>;
    float f[4];
    const bool ok = v.mag_filter == RT_FILTER_LINEAR
                        ? FilterLevel<F, ModeUnorm, D, true>(v.levels[0], r, f)
                        : FilterLevel<F, ModeUnorm, D, false>(v.levels[0], r, f);
    return ok ? FromFloats<T>(f) : T{};
  }
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
      const auto* t =
          base + (ax[0].index[i] + ax[1].index[j] * std::size_t(lv.width)) * F::kChannels;
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
      x + std::size_t(lv.width) * (y + std::size_t(lv.height) * static_cast<std::size_t>(z));
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
  return detail::SampleLod<T, 2>(v, detail::MakeRequest(v, x, y, 0.f, 0), level);
}
template <typename T>
inline T Sample3DLod(const TesseraTextureView& v, float x, float y, float z, float level) {
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

/* Texel formats and read modes of texture sampling (tessera/detail/texture_sampling.h): the
 * result types a program declares, the RTformats a texture holds, how texels become results
 * (element type, normalized, sRGB) and the exact per-channel arithmetic of filtering. */
#ifndef TESSERA_DETAIL_TEXTURE_FORMATS_H_
#define TESSERA_DETAIL_TEXTURE_FORMATS_H_

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <type_traits>

#include "tessera/detail/half.h"
#include "tessera/detail/texture_modes.h"
#include "tessera/detail/texture_vector_types.h"
#include "tessera/detail/texture_view.h"

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

// Texels from one row of a level to the next: the width, unless the level is pitched
// (TesseraTextureLevel::pitch).
TESSERA_TEXTURE_INLINE std::size_t RowTexels(const TesseraTextureLevel& lv) {
  return lv.pitch != 0 ? lv.pitch : lv.width;
}

// An IEEE binary16 texel channel (kFormatHalf*), as stored.
struct Half {
  std::uint16_t bits;
};

inline float HalfToFloat(Half h) { return ::tessera::detail::HalfBitsToFloat(h.bits); }

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
    TESSERA_TEX_FORMAT_CASE(kFormatFloat, float, 1)
    TESSERA_TEX_FORMAT_CASE(kFormatFloat2, float, 2)
    TESSERA_TEX_FORMAT_CASE(kFormatFloat3, float, 3)
    TESSERA_TEX_FORMAT_CASE(kFormatFloat4, float, 4)
    TESSERA_TEX_FORMAT_CASE(kFormatByte, signed char, 1)
    TESSERA_TEX_FORMAT_CASE(kFormatByte2, signed char, 2)
    TESSERA_TEX_FORMAT_CASE(kFormatByte3, signed char, 3)
    TESSERA_TEX_FORMAT_CASE(kFormatByte4, signed char, 4)
    TESSERA_TEX_FORMAT_CASE(kFormatUnsignedByte, unsigned char, 1)
    TESSERA_TEX_FORMAT_CASE(kFormatUnsignedByte2, unsigned char, 2)
    TESSERA_TEX_FORMAT_CASE(kFormatUnsignedByte3, unsigned char, 3)
    TESSERA_TEX_FORMAT_CASE(kFormatUnsignedByte4, unsigned char, 4)
    TESSERA_TEX_FORMAT_CASE(kFormatShort, short, 1)
    TESSERA_TEX_FORMAT_CASE(kFormatShort2, short, 2)
    TESSERA_TEX_FORMAT_CASE(kFormatShort3, short, 3)
    TESSERA_TEX_FORMAT_CASE(kFormatShort4, short, 4)
    TESSERA_TEX_FORMAT_CASE(kFormatUnsignedShort, unsigned short, 1)
    TESSERA_TEX_FORMAT_CASE(kFormatUnsignedShort2, unsigned short, 2)
    TESSERA_TEX_FORMAT_CASE(kFormatUnsignedShort3, unsigned short, 3)
    TESSERA_TEX_FORMAT_CASE(kFormatUnsignedShort4, unsigned short, 4)
    TESSERA_TEX_FORMAT_CASE(kFormatInt, int, 1)
    TESSERA_TEX_FORMAT_CASE(kFormatInt2, int, 2)
    TESSERA_TEX_FORMAT_CASE(kFormatInt3, int, 3)
    TESSERA_TEX_FORMAT_CASE(kFormatInt4, int, 4)
    TESSERA_TEX_FORMAT_CASE(kFormatUnsignedInt, unsigned int, 1)
    TESSERA_TEX_FORMAT_CASE(kFormatUnsignedInt2, unsigned int, 2)
    TESSERA_TEX_FORMAT_CASE(kFormatUnsignedInt3, unsigned int, 3)
    TESSERA_TEX_FORMAT_CASE(kFormatUnsignedInt4, unsigned int, 4)
    TESSERA_TEX_FORMAT_CASE(kFormatHalf, Half, 1)
    TESSERA_TEX_FORMAT_CASE(kFormatHalf2, Half, 2)
    TESSERA_TEX_FORMAT_CASE(kFormatHalf3, Half, 3)
    TESSERA_TEX_FORMAT_CASE(kFormatHalf4, Half, 4)
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

}  // namespace detail
}  // namespace tessera::texture

#endif  // TESSERA_DETAIL_TEXTURE_FORMATS_H_

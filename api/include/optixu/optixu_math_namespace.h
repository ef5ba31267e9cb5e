// Vector math for OptiX 3 programs: the operators and functions OptiX's optixu_math_namespace.h
// offers on float2/3/4, int2/3/4 and uint2/3/4 (arithmetic, dot, cross, normalize, reflect,
// refract, clamp, lerp, ...), the M_PIf family of float constants, and conversions such as
// make_float3(float4).
//
// Placement: everything is defined in the global namespace, where float3 itself lives, so
// argument-dependent lookup finds it from any namespace even without `using namespace optix;`.
// It is then re-exported into namespace optix with using-declarations, which name the very same
// functions: `optix::normalize(v)`, `using namespace optix; normalize(v)` and plain
// `normalize(v)` all work and can never be ambiguous with each other.
//
// Scalar fminf, fmaxf, expf, floor... are the C library's; this header only adds vector
// overloads beside them, and never declares anything in namespace std.
#ifndef OPTIXU_OPTIXU_MATH_NAMESPACE_H_
#define OPTIXU_OPTIXU_MATH_NAMESPACE_H_

// clang-format off: before every other #include (see there)
#include "../tessera/detail/program_prelude.h"
// clang-format on

#include <math.h>
#include <sys/types.h>

#include <cmath>

// As OptiX's does: the host API, and under __CUDACC__ the program-side API (optix.h).
#include "../internal/optix_datatypes.h"  // optix::Ray, for intersect_triangle
#include "../optix.h"
#include "../tessera/cuda_compat.h"  // Global min/max for int and unsigned, as CUDA has them.
#include "optixu_vector_types.h"

// ---- Constants ----------------------------------------------------------------------------------
// float versions of the <math.h> M_ constants, so programs do not drag doubles into float math.
#ifndef M_PIf
#define M_Ef 2.71828182845904523536f
#define M_LOG2Ef 1.44269504088896340736f
#define M_LOG10Ef 0.434294481903251827651f
#define M_LN2f 0.693147180559945309417f
#define M_LN10f 2.30258509299404568402f
#define M_PIf 3.14159265358979323846f
#define M_PI_2f 1.57079632679489661923f
#define M_PI_4f 0.785398163397448309616f
#define M_1_PIf 0.318309886183790671538f
#define M_2_PIf 0.636619772367581343076f
#define M_2_SQRTPIf 1.12837916709551257390f
#define M_SQRT2f 1.41421356237309504880f
#define M_SQRT1_2f 0.707106781186547524401f
#endif

// ---- Scalar helpers -----------------------------------------------------------------------------
namespace optixu_detail {
// fminf and fmaxf as C defines them (a NaN argument yields the other one), but inline: -O2 keeps
// the library's as calls, since minss and maxss treat a NaN differently.
inline float Fminf(float a, float b) { return (a < b || b != b) ? a : b; }
inline float Fmaxf(float a, float b) { return (a > b || b != b) ? a : b; }
// Float to integer, truncating toward zero as a C cast does, but saturating like the GPU's
// cvt.rzi: NaN gives 0, values beyond the range give its nearest end (a C cast is undefined
// there, and x86 returns 0x80000000 or wraps).
template <typename S>
inline S FloatToInt(float x) {
  return tessera::cuda_compat_detail::SaturatingCast<S>(std::trunc(x));
}
}  // namespace optixu_detail

inline float clamp(float f, float a, float b) {
  return optixu_detail::Fmaxf(a, optixu_detail::Fminf(f, b));
}
inline int clamp(int f, int a, int b) { return ::max(a, ::min(f, b)); }
inline unsigned int clamp(unsigned int f, unsigned int a, unsigned int b) {
  return ::max(a, ::min(f, b));
}
inline long long clamp(long long f, long long a, long long b) { return ::max(a, ::min(f, b)); }
inline unsigned long long clamp(unsigned long long f, unsigned long long a, unsigned long long b) {
  return ::max(a, ::min(f, b));
}
// Linear interpolation: a at t == 0, b at t == 1. In C++20 libstdc++'s <math.h> already puts
// std::lerp(float, float, float) into the global namespace (a second definition would not
// compile); that one is exact at t == 0 and t == 1 as well, so it serves instead.
#if !(defined(__GLIBCXX__) && __cplusplus > 201703L)
inline float lerp(float a, float b, float t) { return a + t * (b - a); }
#endif
// Bilinear interpolation of a cell's corners x<u><v>: lerp along u, then along v.
inline float bilerp(float x00, float x10, float x01, float x11, float u, float v) {
  return lerp(lerp(x00, x10, u), lerp(x01, x11, u), v);
}
// Hermite step: 0 below edge0, 1 above edge1, smooth (zero slope at both ends) between.
inline float smoothstep(float edge0, float edge1, float x) {
  const float t = clamp((x - edge0) / (edge1 - edge0), 0.0f, 1.0f);
  return t * t * (3.0f - 2.0f * t);
}

// ---- Component-wise operations, generated -------------------------------------------------------
// Nine vector types share the same component-wise operators and functions; writing them out would
// be ~1500 lines of near-identical code where a typo in one component hides easily. The macros
// below expand one expression per component instead. OPTIXU_MAP<N>_(E, arg) expands E(c, arg) for
// each component c of an N-vector, comma-separated (for a braced initializer); OPTIXU_SUM<N>_ joins
// them with +.
#define OPTIXU_MAP2_(E, arg) E(x, arg), E(y, arg)
#define OPTIXU_MAP3_(E, arg) E(x, arg), E(y, arg), E(z, arg)
#define OPTIXU_MAP4_(E, arg) E(x, arg), E(y, arg), E(z, arg), E(w, arg)
#define OPTIXU_SUM2_(E, arg) (E(x, arg) + E(y, arg))
#define OPTIXU_SUM3_(E, arg) (E(x, arg) + E(y, arg) + E(z, arg))
#define OPTIXU_SUM4_(E, arg) (E(x, arg) + E(y, arg) + E(z, arg) + E(w, arg))
#define OPTIXU_ALL2_(E, arg) (E(x, arg) && E(y, arg))
#define OPTIXU_ALL3_(E, arg) (E(x, arg) && E(y, arg) && E(z, arg))
#define OPTIXU_ALL4_(E, arg) (E(x, arg) && E(y, arg) && E(z, arg) && E(w, arg))

// Per-component expressions over the parameters a, b (vectors), s (scalar), lo and hi (bounds).
#define OPTIXU_VV_(c, op) a.c op b.c
#define OPTIXU_VS_(c, op) a.c op s
#define OPTIXU_SV_(c, op) s op a.c
#define OPTIXU_NEG_(c, unused) -a.c
#define OPTIXU_FN_(c, fn) fn(a.c)
#define OPTIXU_FN2_(c, fn) fn(a.c, b.c)
#define OPTIXU_FN_SCALAR_BOUNDS_(c, fn) fn(a.c, lo, hi)
#define OPTIXU_FN_VECTOR_BOUNDS_(c, fn) fn(a.c, lo.c, hi.c)
#define OPTIXU_FRAC_(c, unused) a.c - std::floor(a.c)
#define OPTIXU_EQ_(c, unused) a.c == b.c

// + - * / between vectors, vector and scalar (either order), and the compound forms.
#define OPTIXU_ARITHMETIC_(V, S, N, op)                                                       \
  inline V operator op(const V& a, const V& b) { return {OPTIXU_MAP##N##_(OPTIXU_VV_, op)}; } \
  inline V operator op(const V& a, S s) { return {OPTIXU_MAP##N##_(OPTIXU_VS_, op)}; }        \
  inline V operator op(S s, const V& a) { return {OPTIXU_MAP##N##_(OPTIXU_SV_, op)}; }        \
  inline V& operator op##=(V& a, const V& b) { return a = a op b; }                           \
  inline V& operator op##=(V& a, S s) { return a = a op s; }

#define OPTIXU_ALL_ARITHMETIC_(V, S, N) \
  OPTIXU_ARITHMETIC_(V, S, N, +)        \
  OPTIXU_ARITHMETIC_(V, S, N, -)        \
  OPTIXU_ARITHMETIC_(V, S, N, *)        \
  OPTIXU_ARITHMETIC_(V, S, N, /)

// float2/3/4.
#define OPTIXU_FLOAT_VECTOR_(V, N)                                                             \
  OPTIXU_ALL_ARITHMETIC_(V, float, N)                                                          \
  inline V operator-(const V& a) { return {OPTIXU_MAP##N##_(OPTIXU_NEG_, _)}; }                \
  inline V fminf(const V& a, const V& b) {                                                     \
    return {OPTIXU_MAP##N##_(OPTIXU_FN2_, optixu_detail::Fminf)};                              \
  }                                                                                            \
  inline V fmaxf(const V& a, const V& b) {                                                     \
    return {OPTIXU_MAP##N##_(OPTIXU_FN2_, optixu_detail::Fmaxf)};                              \
  }                                                                                            \
  inline V fmodf(const V& a, const V& b) { return {OPTIXU_MAP##N##_(OPTIXU_FN2_, ::fmodf)}; }  \
  inline V copysignf(const V& a, const V& b) {                                                 \
    return {OPTIXU_MAP##N##_(OPTIXU_FN2_, ::copysignf)};                                       \
  }                                                                                            \
  inline V fabs(const V& a) { return {OPTIXU_MAP##N##_(OPTIXU_FN_, std::fabs)}; }              \
  inline V floor(const V& a) { return {OPTIXU_MAP##N##_(OPTIXU_FN_, std::floor)}; }            \
  inline V ceil(const V& a) { return {OPTIXU_MAP##N##_(OPTIXU_FN_, std::ceil)}; }              \
  inline V expf(const V& a) { return {OPTIXU_MAP##N##_(OPTIXU_FN_, ::expf)}; }                 \
  /* Fractional part, a - floor(a): in [0, 1) also for negative components. */                 \
  inline V frac(const V& a) { return {OPTIXU_MAP##N##_(OPTIXU_FRAC_, _)}; }                    \
  inline V clamp(const V& a, float lo, float hi) {                                             \
    return {OPTIXU_MAP##N##_(OPTIXU_FN_SCALAR_BOUNDS_, ::clamp)};                              \
  }                                                                                            \
  inline V clamp(const V& a, const V& lo, const V& hi) {                                       \
    return {OPTIXU_MAP##N##_(OPTIXU_FN_VECTOR_BOUNDS_, ::clamp)};                              \
  }                                                                                            \
  inline V lerp(const V& a, const V& b, float t) { return a + t * (b - a); }                   \
  inline V bilerp(const V& x00, const V& x10, const V& x01, const V& x11, float u, float v) {  \
    return lerp(lerp(x00, x10, u), lerp(x01, x11, u), v);                                      \
  }                                                                                            \
  inline float dot(const V& a, const V& b) { return OPTIXU_SUM##N##_(OPTIXU_VV_, *); }         \
  inline float length(const V& a) { return tessera_detail::Sqrt(dot(a, a)); }                  \
  /* A zero vector has no direction and normalizes to NaNs, as on the GPU. */                  \
  inline V normalize(const V& a) { return a * (1.0f / tessera_detail::Sqrt(dot(a, a))); }      \
  /* Mirror direction of i about the plane with normal n (n unit length). */                   \
  inline V reflect(const V& i, const V& n) { return i - 2.0f * n * dot(n, i); }                \
  /* n where dot(i, nref) > 0, -n where it is < 0. Programs pass i = -ray.direction and the */ \
  /* geometric normal as nref, which turns the shading normal toward the viewer. */            \
  inline V faceforward(const V& n, const V& i, const V& nref) {                                \
    return n * ::copysignf(1.0f, dot(i, nref));                                                \
  }

// int2/3/4 and uint2/3/4.
#define OPTIXU_INTEGER_VECTOR_(V, S, N)                                                      \
  OPTIXU_ALL_ARITHMETIC_(V, S, N)                                                            \
  inline bool operator==(const V& a, const V& b) { return OPTIXU_ALL##N##_(OPTIXU_EQ_, _); } \
  inline bool operator!=(const V& a, const V& b) { return !(a == b); }                       \
  inline V min(const V& a, const V& b) { return {OPTIXU_MAP##N##_(OPTIXU_FN2_, ::min)}; }    \
  inline V max(const V& a, const V& b) { return {OPTIXU_MAP##N##_(OPTIXU_FN2_, ::max)}; }    \
  inline V clamp(const V& a, S lo, S hi) {                                                   \
    return {OPTIXU_MAP##N##_(OPTIXU_FN_SCALAR_BOUNDS_, ::clamp)};                            \
  }                                                                                          \
  inline V clamp(const V& a, const V& lo, const V& hi) {                                     \
    return {OPTIXU_MAP##N##_(OPTIXU_FN_VECTOR_BOUNDS_, ::clamp)};                            \
  }

OPTIXU_FLOAT_VECTOR_(float2, 2)
OPTIXU_FLOAT_VECTOR_(float3, 3)
OPTIXU_FLOAT_VECTOR_(float4, 4)
OPTIXU_INTEGER_VECTOR_(int2, int, 2)
OPTIXU_INTEGER_VECTOR_(int3, int, 3)
OPTIXU_INTEGER_VECTOR_(int4, int, 4)
OPTIXU_INTEGER_VECTOR_(uint2, unsigned int, 2)
OPTIXU_INTEGER_VECTOR_(uint3, unsigned int, 3)
OPTIXU_INTEGER_VECTOR_(uint4, unsigned int, 4)
// OptiX 6 adds the 64-bit families.
OPTIXU_INTEGER_VECTOR_(longlong2, long long, 2)
OPTIXU_INTEGER_VECTOR_(longlong3, long long, 3)
OPTIXU_INTEGER_VECTOR_(longlong4, long long, 4)
OPTIXU_INTEGER_VECTOR_(ulonglong2, unsigned long long, 2)
OPTIXU_INTEGER_VECTOR_(ulonglong3, unsigned long long, 3)
OPTIXU_INTEGER_VECTOR_(ulonglong4, unsigned long long, 4)

// Unsigned vectors get no unary minus: it would silently wrap every component.
inline int2 operator-(const int2& a) { return {-a.x, -a.y}; }
inline int3 operator-(const int3& a) { return {-a.x, -a.y, -a.z}; }
inline int4 operator-(const int4& a) { return {-a.x, -a.y, -a.z, -a.w}; }
inline longlong2 operator-(const longlong2& a) { return {-a.x, -a.y}; }
inline longlong3 operator-(const longlong3& a) { return {-a.x, -a.y, -a.z}; }
inline longlong4 operator-(const longlong4& a) { return {-a.x, -a.y, -a.z, -a.w}; }

#undef OPTIXU_INTEGER_VECTOR_
#undef OPTIXU_FLOAT_VECTOR_
#undef OPTIXU_ALL_ARITHMETIC_
#undef OPTIXU_ARITHMETIC_
#undef OPTIXU_EQ_
#undef OPTIXU_FRAC_
#undef OPTIXU_FN_VECTOR_BOUNDS_
#undef OPTIXU_FN_SCALAR_BOUNDS_
#undef OPTIXU_FN2_
#undef OPTIXU_FN_
#undef OPTIXU_NEG_
#undef OPTIXU_SV_
#undef OPTIXU_VS_
#undef OPTIXU_VV_
#undef OPTIXU_ALL4_
#undef OPTIXU_ALL3_
#undef OPTIXU_ALL2_
#undef OPTIXU_SUM4_
#undef OPTIXU_SUM3_
#undef OPTIXU_SUM2_
#undef OPTIXU_MAP4_
#undef OPTIXU_MAP3_
#undef OPTIXU_MAP2_

// ---- Reductions ---------------------------------------------------------------------------------
// fminf/fmaxf of a single vector give its smallest/largest component.
inline float fminf(const float2& a) { return optixu_detail::Fminf(a.x, a.y); }
inline float fminf(const float3& a) {
  return optixu_detail::Fminf(optixu_detail::Fminf(a.x, a.y), a.z);
}
inline float fminf(const float4& a) {
  return optixu_detail::Fminf(optixu_detail::Fminf(a.x, a.y), optixu_detail::Fminf(a.z, a.w));
}
inline float fmaxf(const float2& a) { return optixu_detail::Fmaxf(a.x, a.y); }
inline float fmaxf(const float3& a) {
  return optixu_detail::Fmaxf(optixu_detail::Fmaxf(a.x, a.y), a.z);
}
inline float fmaxf(const float4& a) {
  return optixu_detail::Fmaxf(optixu_detail::Fmaxf(a.x, a.y), optixu_detail::Fmaxf(a.z, a.w));
}

// ---- float3 geometry ----------------------------------------------------------------------------
// Right-handed: cross(x, y) == z.
inline float3 cross(const float3& a, const float3& b) {
  return make_float3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}

// Refraction of the incident direction i (pointing toward the surface) at a surface with unit
// normal n, where ior is the index of refraction inside (the side n points away from) over
// outside. i may arrive from either side: if it travels along n it is leaving the medium, so n
// is flipped and the ratio inverted. Writes the transmitted direction to r, normalized as in
// OptiX (unit length whatever the length of i), and returns true, or, on total internal
// reflection, writes zero and returns false.
inline bool refract(float3& r, const float3& i, const float3& n, const float ior) {
  float3 nn = n;
  float cos_i = -dot(i, n);  // Cosine of the incidence angle, against the facing normal.
  float eta = 1.0f / ior;    // Ratio of the index being left over the index being entered.
  if (cos_i < 0.0f) {
    nn = -n;
    cos_i = -cos_i;
    eta = ior;
  }
  const float k = 1.0f - eta * eta * (1.0f - cos_i * cos_i);
  if (k < 0.0f) {
    r = make_float3(0.0f, 0.0f, 0.0f);
    return false;
  }
  // Unit length, as in OptiX.
  r = normalize(eta * i + (eta * cos_i - tessera_detail::Sqrt(k)) * nn);
  return true;
}

// Luminance of a linear RGB color: NTSC weights, and the Rec. 709 weights CIE Y uses.
inline float luminance(const float3& rgb) { return dot(rgb, make_float3(0.30f, 0.59f, 0.11f)); }
inline float luminanceCIE(const float3& rgb) {
  return dot(rgb, make_float3(0.2126f, 0.7152f, 0.0722f));
}

// Schlick's approximation of Fresnel reflectance: `minimum` at normal incidence rising to
// `maximum` at grazing angles.
inline float fresnel_schlick(float cos_theta, float exponent = 5.0f, float minimum = 0.0f,
                             float maximum = 1.0f) {
  float f =
      minimum + (maximum - minimum) * powf(optixu_detail::Fmaxf(0.0f, 1.0f - cos_theta), exponent);
  return ::clamp(f, minimum, maximum);  // max(minimum, min(f, maximum)), as OptiX clamps.
}
inline float3 fresnel_schlick(float cos_theta, float exponent, const float3& minimum,
                              const float3& maximum) {
  return make_float3(fresnel_schlick(cos_theta, exponent, minimum.x, maximum.x),
                     fresnel_schlick(cos_theta, exponent, minimum.y, maximum.y),
                     fresnel_schlick(cos_theta, exponent, minimum.z, maximum.z));
}

// ---- Sampling and local frames (path tracers) ---------------------------------------------------
// A direction on the +z hemisphere with density proportional to cos(theta), from two uniform
// numbers in [0, 1): a point of the unit disk (radius sqrt(u1), angle 2 pi u2) lifted onto it.
inline void cosine_sample_hemisphere(float u1, float u2, float3& p) {
  const float r = tessera_detail::Sqrt(u1), phi = 2.0f * M_PIf * u2;
  p.x = r * cosf(phi);
  p.y = r * sinf(phi);
  p.z = tessera_detail::Sqrt(optixu_detail::Fmaxf(0.0f, 1.0f - p.x * p.x - p.y * p.y));
}

// Shirley and Chiu's concentric map from [0, 1)^2 to the unit disk: squares around the centre go
// to circles, so stratified samples stay stratified.
inline float2 square_to_disk(const float2& sample) {
  const float a = 2.0f * sample.x - 1.0f, b = 2.0f * sample.y - 1.0f;
  if (a == 0.0f && b == 0.0f) return make_float2(0.0f, 0.0f);
  float r, phi;
  if (std::fabs(a) > std::fabs(b)) {
    r = a;
    phi = M_PI_4f * (b / a);
  } else {
    r = b;
    phi = 2.0f * M_PI_4f - M_PI_4f * (a / b);
  }
  return make_float2(r * cosf(phi), r * sinf(phi));
}

// A color ramp over [0, 1] (blue, cyan, green, yellow, red) for false-color output: heat maps of
// time or counts. Blue rises over [-0.25, 0.25] and falls over [0.25, 0.5], green rises over
// [0, 0.5] and falls over [0.75, 1], red rises over [0.5, 0.75].
inline float3 temperature(float t) {
  const float b = t < 0.25f ? smoothstep(-0.25f, 0.25f, t) : 1.0f - smoothstep(0.25f, 0.5f, t);
  const float g =
      t < 0.5f ? smoothstep(0.0f, 0.5f, t) : (t < 0.75f ? 1.0f : 1.0f - smoothstep(0.75f, 1.0f, t));
  const float r = smoothstep(0.5f, 0.75f, t);
  return make_float3(r, g, b);
}

// Cartesian to polar: (azimuth in [0, 2 pi) measured from +x toward +y, elevation in
// [-pi/2, pi/2] from the xy plane, radius). On the z axis the azimuth is 0 and the elevation
// +-pi/2 (-pi/2 also for the origin).
inline float3 cart_to_pol(const float3& v) {
  const float radius = length(v);
  const float r = tessera_detail::Sqrt(v.x * v.x + v.y * v.y);
  if (!(r > 0.0f)) return make_float3(0.0f, v.z > 0.0f ? M_PI_2f : -M_PI_2f, radius);
  float azimuth = atanf(v.y / v.x);
  const float elevation = atanf(v.z / r);
  if (v.x < 0.0f) {
    azimuth += M_PIf;
  } else if (v.y < 0.0f) {
    azimuth += 2.0f * M_PIf;
  }
  return make_float3(azimuth, elevation, radius);
}

// ---- Component access by index ------------------------------------------------------------------
// i must be in [0, N); out-of-range indices read or write the last component. Selecting the member,
// rather than indexing past x, keeps this defined behavior in C++.
#define OPTIXU_BY_INDEX_(V, S)                                               \
  inline S getByIndex(const V& v, int i) { return OPTIXU_COMPONENT_(v, i); } \
  inline void setByIndex(V& v, int i, S x) { OPTIXU_COMPONENT_(v, i) = x; }
#define OPTIXU_COMPONENT_(v, i) ((void)(i), v.x)  // i can only be 0.
OPTIXU_BY_INDEX_(float1, float)
OPTIXU_BY_INDEX_(int1, int)
OPTIXU_BY_INDEX_(uint1, unsigned int)
OPTIXU_BY_INDEX_(longlong1, long long)
OPTIXU_BY_INDEX_(ulonglong1, unsigned long long)
#undef OPTIXU_COMPONENT_
#define OPTIXU_COMPONENT_(v, i) ((i) == 0 ? v.x : v.y)
OPTIXU_BY_INDEX_(float2, float)
OPTIXU_BY_INDEX_(int2, int)
OPTIXU_BY_INDEX_(uint2, unsigned int)
OPTIXU_BY_INDEX_(longlong2, long long)
OPTIXU_BY_INDEX_(ulonglong2, unsigned long long)
#undef OPTIXU_COMPONENT_
#define OPTIXU_COMPONENT_(v, i) ((i) == 0 ? v.x : (i) == 1 ? v.y : v.z)
OPTIXU_BY_INDEX_(float3, float)
OPTIXU_BY_INDEX_(int3, int)
OPTIXU_BY_INDEX_(uint3, unsigned int)
OPTIXU_BY_INDEX_(longlong3, long long)
OPTIXU_BY_INDEX_(ulonglong3, unsigned long long)
#undef OPTIXU_COMPONENT_
#define OPTIXU_COMPONENT_(v, i) ((i) == 0 ? v.x : (i) == 1 ? v.y : (i) == 2 ? v.z : v.w)
OPTIXU_BY_INDEX_(float4, float)
OPTIXU_BY_INDEX_(int4, int)
OPTIXU_BY_INDEX_(uint4, unsigned int)
OPTIXU_BY_INDEX_(longlong4, long long)
OPTIXU_BY_INDEX_(ulonglong4, unsigned long long)
#undef OPTIXU_COMPONENT_
#undef OPTIXU_BY_INDEX_

// ---- Conversions --------------------------------------------------------------------------------
// From one scalar (all components), from a smaller vector plus components (a missing last component
// is 0), from a larger vector (dropping the tail), and between float, int and unsigned vectors of
// one size (float to integer truncates toward zero, like a C cast, and saturates like the GPU:
// NaN gives 0, a value out of range the nearest representable one).
inline float2 make_float2(float s) { return make_float2(s, s); }
inline float2 make_float2(const float3& a) { return make_float2(a.x, a.y); }
inline float2 make_float2(const float4& a) { return make_float2(a.x, a.y); }
inline float2 make_float2(const int2& a) {
  return make_float2(static_cast<float>(a.x), static_cast<float>(a.y));
}
inline float2 make_float2(const uint2& a) {
  return make_float2(static_cast<float>(a.x), static_cast<float>(a.y));
}

inline float3 make_float3(float s) { return make_float3(s, s, s); }
inline float3 make_float3(const float2& a) { return make_float3(a.x, a.y, 0.0f); }
inline float3 make_float3(const float2& a, float z) { return make_float3(a.x, a.y, z); }
inline float3 make_float3(const float4& a) { return make_float3(a.x, a.y, a.z); }
inline float3 make_float3(const int3& a) {
  return make_float3(static_cast<float>(a.x), static_cast<float>(a.y), static_cast<float>(a.z));
}
inline float3 make_float3(const uint3& a) {
  return make_float3(static_cast<float>(a.x), static_cast<float>(a.y), static_cast<float>(a.z));
}

inline float4 make_float4(float s) { return make_float4(s, s, s, s); }
inline float4 make_float4(const float3& a) { return make_float4(a.x, a.y, a.z, 0.0f); }
inline float4 make_float4(const float3& a, float w) { return make_float4(a.x, a.y, a.z, w); }
inline float4 make_float4(const float2& a, float z, float w) { return make_float4(a.x, a.y, z, w); }
inline float3 make_float3(float x, const float2& yz) { return make_float3(x, yz.x, yz.y); }
inline float4 make_float4(float x, const float3& yzw) {
  return make_float4(x, yzw.x, yzw.y, yzw.z);
}
inline float4 make_float4(const float2& xy, const float2& zw) {
  return make_float4(xy.x, xy.y, zw.x, zw.y);
}
inline float4 make_float4(float x, float y, const float2& zw) {
  return make_float4(x, y, zw.x, zw.y);
}
inline float4 make_float4(float x, const float2& yz, float w) {
  return make_float4(x, yz.x, yz.y, w);
}
inline float4 make_float4(const int4& a) {
  return make_float4(static_cast<float>(a.x), static_cast<float>(a.y), static_cast<float>(a.z),
                     static_cast<float>(a.w));
}
inline float4 make_float4(const uint4& a) {
  return make_float4(static_cast<float>(a.x), static_cast<float>(a.y), static_cast<float>(a.z),
                     static_cast<float>(a.w));
}

// int and unsigned vectors share one shape: V is the family, S its scalar, Other the other family.
#define OPTIXU_INTEGER_CONVERSIONS_(V, S, Other)                                                 \
  inline V##2 make_##V##2(S s) { return make_##V##2(s, s); }                                     \
  inline V##2 make_##V##2(const V##3 & a) { return make_##V##2(a.x, a.y); }                      \
  inline V##2 make_##V##2(const V##4 & a) { return make_##V##2(a.x, a.y); }                      \
  inline V##2 make_##V##2(const float2& a) {                                                     \
    return make_##V##2(optixu_detail::FloatToInt<S>(a.x), optixu_detail::FloatToInt<S>(a.y));    \
  }                                                                                              \
  inline V##2 make_##V##2(const Other##2 & a) {                                                  \
    return make_##V##2(static_cast<S>(a.x), static_cast<S>(a.y));                                \
  }                                                                                              \
  inline V##3 make_##V##3(S s) { return make_##V##3(s, s, s); }                                  \
  inline V##3 make_##V##3(const V##2 & a) { return make_##V##3(a.x, a.y, 0); }                   \
  inline V##3 make_##V##3(const V##2 & a, S z) { return make_##V##3(a.x, a.y, z); }              \
  inline V##3 make_##V##3(const V##4 & a) { return make_##V##3(a.x, a.y, a.z); }                 \
  inline V##3 make_##V##3(const float3& a) {                                                     \
    return make_##V##3(optixu_detail::FloatToInt<S>(a.x), optixu_detail::FloatToInt<S>(a.y),     \
                       optixu_detail::FloatToInt<S>(a.z));                                       \
  }                                                                                              \
  inline V##3 make_##V##3(const Other##3 & a) {                                                  \
    return make_##V##3(static_cast<S>(a.x), static_cast<S>(a.y), static_cast<S>(a.z));           \
  }                                                                                              \
  inline V##4 make_##V##4(S s) { return make_##V##4(s, s, s, s); }                               \
  inline V##4 make_##V##4(const V##3 & a) { return make_##V##4(a.x, a.y, a.z, 0); }              \
  inline V##4 make_##V##4(const V##3 & a, S w) { return make_##V##4(a.x, a.y, a.z, w); }         \
  inline V##3 make_##V##3(S x, const V##2 & yz) { return make_##V##3(x, yz.x, yz.y); }           \
  inline V##4 make_##V##4(S x, const V##3 & yzw) { return make_##V##4(x, yzw.x, yzw.y, yzw.z); } \
  inline V##4 make_##V##4(const V##2 & xy, const V##2 & zw) {                                    \
    return make_##V##4(xy.x, xy.y, zw.x, zw.y);                                                  \
  }                                                                                              \
  inline V##4 make_##V##4(const V##2 & xy, S z, S w) { return make_##V##4(xy.x, xy.y, z, w); }   \
  inline V##4 make_##V##4(S x, S y, const V##2 & zw) { return make_##V##4(x, y, zw.x, zw.y); }   \
  inline V##4 make_##V##4(S x, const V##2 & yz, S w) { return make_##V##4(x, yz.x, yz.y, w); }   \
  inline V##4 make_##V##4(const float4& a) {                                                     \
    return make_##V##4(optixu_detail::FloatToInt<S>(a.x), optixu_detail::FloatToInt<S>(a.y),     \
                       optixu_detail::FloatToInt<S>(a.z), optixu_detail::FloatToInt<S>(a.w));    \
  }                                                                                              \
  inline V##4 make_##V##4(const Other##4 & a) {                                                  \
    return make_##V##4(static_cast<S>(a.x), static_cast<S>(a.y), static_cast<S>(a.z),            \
                       static_cast<S>(a.w));                                                     \
  }
OPTIXU_INTEGER_CONVERSIONS_(int, int, uint)
OPTIXU_INTEGER_CONVERSIONS_(uint, unsigned int, int)
OPTIXU_INTEGER_CONVERSIONS_(longlong, long long, ulonglong)
OPTIXU_INTEGER_CONVERSIONS_(ulonglong, unsigned long long, longlong)
#undef OPTIXU_INTEGER_CONVERSIONS_

// ---- Re-export into namespace optix -------------------------------------------------------------
// A using-declaration brings in the overloads declared before it, so this block stays last.
// saturate(x): x clamped to [0, 1], for float and the float vectors, as HLSL and CUDA programs
// spell __saturatef. A function template, so that a program's own non-template saturate() (many
// define one) is preferred over it instead of colliding with it.
template <typename T>
inline T saturate(const T& x) {
  return clamp(x, 0.0f, 1.0f);
}

namespace optix {
// The <sys/types.h> names OptiX programs use for unsigned scalars (rtBuffer<uint>, ...).
using ::uint;
using ::ushort;
// Bit-preserving casts under OptiX's names (CUDA spells them __float_as_int, __int_as_float).
inline int float_as_int(float f) { return ::__float_as_int(f); }
inline float int_as_float(int i) { return ::__int_as_float(i); }
using ::operator+;
using ::operator-;
using ::operator*;
using ::operator/;
using ::operator+=;
using ::operator-=;
using ::operator*=;
using ::operator/=;
using ::operator==;
using ::operator!=;
using ::bilerp;
using ::cart_to_pol;
using ::ceil;
using ::clamp;
using ::copysignf;
using ::cross;
using ::dot;
using ::expf;
using ::fabs;
using ::faceforward;
using ::floor;
using ::fmaxf;
using ::fminf;
using ::fmodf;
using ::frac;
using ::fresnel_schlick;
using ::getByIndex;
using ::length;
using ::lerp;
using ::luminance;
using ::luminanceCIE;
using ::max;
using ::min;
using ::normalize;
using ::reflect;
using ::refract;
using ::saturate;
using ::setByIndex;
using ::smoothstep;
using ::temperature;
// Repeating these using-declarations picks up the conversion overloads added above.
using ::cosine_sample_hemisphere;
using ::make_float2;
using ::make_float3;
using ::make_float4;
using ::make_int2;
using ::make_int3;
using ::make_int4;
using ::make_longlong2;
using ::make_longlong3;
using ::make_longlong4;
using ::make_uint2;
using ::make_uint3;
using ::make_uint4;
using ::make_ulonglong2;
using ::make_ulonglong3;
using ::make_ulonglong4;
using ::square_to_disk;

// An orthonormal frame around `normal` (unit length): inverse_transform takes a vector given in
// the frame (z along the normal), such as a hemisphere sample, to the normal's space. The
// binormal is perpendicular to the normal and to the axis, x or z, the normal leans from most.
struct Onb {
  Onb(const float3& normal)  // NOLINT(google-explicit-constructor): implicit, as in OptiX
      : m_normal(normal) {
    m_binormal = std::fabs(normal.x) > std::fabs(normal.z)
                     ? normalize(make_float3(-normal.y, normal.x, 0.0f))
                     : normalize(make_float3(0.0f, -normal.z, normal.y));
    m_tangent = cross(m_binormal, m_normal);
  }
  void inverse_transform(float3& p) const {
    p = p.x * m_tangent + p.y * m_binormal + p.z * m_normal;
  }
  float3 m_tangent, m_binormal, m_normal;
};

// Ray against the triangle p0 p1 p2: true when the ray meets its interior at a distance strictly
// between tmin and tmax. Sets t, the weights beta and gamma of p1 and p2 (p0's is 1 - beta -
// gamma), and the unnormalized normal n = (p1 - p0) x (p2 - p0), whatever the result. A ray in
// the triangle's plane (or a degenerate triangle) gives NaNs, which compare false: no hit.
// Found from optix::Ray by argument-dependent lookup, as with the SDK's header.
inline bool intersect_triangle(const Ray& ray, const float3& p0, const float3& p1, const float3& p2,
                               float3& n, float& t, float& beta, float& gamma) {
  const float3 e1 = p1 - p0, e2 = p2 - p0;
  n = cross(e1, e2);
  const float3 to_origin = ray.origin - p0;
  const float3 across = cross(to_origin, ray.direction);
  const float inv = 1.0f / dot(n, ray.direction);  // Cramer's rule over (d, e1, e2)
  t = -dot(n, to_origin) * inv;
  beta = -dot(across, e2) * inv;
  gamma = dot(across, e1) * inv;
  return (t > ray.tmin) & (t < ray.tmax) & (beta >= 0.0f) & (gamma >= 0.0f) &
         (beta + gamma <= 1.0f);
}
// The SDK's variants compute the same; they differ only in how their GPU code branches.
inline bool intersect_triangle_branchless(const Ray& ray, const float3& p0, const float3& p1,
                                          const float3& p2, float3& n, float& t, float& beta,
                                          float& gamma) {
  return intersect_triangle(ray, p0, p1, p2, n, t, beta, gamma);
}
inline bool intersect_triangle_earlyexit(const Ray& ray, const float3& p0, const float3& p1,
                                         const float3& p2, float3& n, float& t, float& beta,
                                         float& gamma) {
  return intersect_triangle(ray, p0, p1, p2, n, t, beta, gamma);
}
}  // namespace optix

#endif  // OPTIXU_OPTIXU_MATH_NAMESPACE_H_

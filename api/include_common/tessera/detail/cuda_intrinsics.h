// CUDA's device intrinsics as inline functions with the documented CUDA semantics, for program
// modules compiled as plain C++ by g++, whichever OptiX generation they are written for: the OptiX
// 3 root (tessera/cuda_compat.h) and the OptiX 7 root (optix_device.h) both include this.
// Reinterpretation (__float_as_uint ...), conversions with a rounding mode (__float2int_rn ...),
// single-precision intrinsics (__saturatef, rsqrtf, __fdividef, __expf ...), integer intrinsics
// (__popc, __clz, __ffs ...), CUDA's global min/max, fences, __ldg and clock64. Everything is in
// the global namespace, where CUDA puts it.
#ifndef TESSERA_DETAIL_CUDA_INTRINSICS_H_
#define TESSERA_DETAIL_CUDA_INTRINSICS_H_

// <math.h> first: its float overloads in the global namespace, and glibc's declarations of __expf,
// __sinf etc., which the definitions below redeclare compatibly.
#include <math.h>

#include <chrono>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#if defined(__SSE__)
#include <xmmintrin.h>
#endif

namespace tessera {
namespace cuda_compat_detail {

// PTX float-to-integer conversions saturate: NaN gives 0 and out-of-range values clamp to the
// destination's range, instead of being undefined behavior as a C++ cast would be.
template <typename Int, typename Float>
inline Int SaturatingCast(Float rounded) {
  if (rounded != rounded) return 0;
  constexpr Int kLow = std::numeric_limits<Int>::min();
  constexpr Int kHigh = std::numeric_limits<Int>::max();
  if (rounded <= static_cast<Float>(kLow)) return kLow;
  // kHigh rounds up to a power of two as a float, so >= catches every value that does not fit.
  if (rounded >= static_cast<Float>(kHigh)) return kHigh;
  return static_cast<Int>(rounded);
}

}  // namespace cuda_compat_detail
}  // namespace tessera

// ---- Reinterpretation ---------------------------------------------------------------------------
// memcpy is the defined way to reinterpret bits in C++17; g++ compiles it to a register move.
inline int __float_as_int(float x) {
  int i;
  std::memcpy(&i, &x, sizeof i);
  return i;
}
inline unsigned int __float_as_uint(float x) {
  unsigned int u;
  std::memcpy(&u, &x, sizeof u);
  return u;
}
inline float __int_as_float(int i) {
  float x;
  std::memcpy(&x, &i, sizeof x);
  return x;
}
inline float __uint_as_float(unsigned int u) {
  float x;
  std::memcpy(&x, &u, sizeof x);
  return x;
}
inline long long __double_as_longlong(double x) {
  long long i;
  std::memcpy(&i, &x, sizeof i);
  return i;
}
inline double __longlong_as_double(long long i) {
  double x;
  std::memcpy(&x, &i, sizeof x);
  return x;
}

// ---- Conversions with an explicit rounding mode -------------------------------------------------
// _rn rounds to nearest even (nearbyint in the default floating-point environment), _rz toward
// zero, _ru up, _rd down. Results saturate like the PTX instructions they stand for.
inline int __float2int_rn(float x) {
  return tessera::cuda_compat_detail::SaturatingCast<int>(std::nearbyint(x));
}
inline int __float2int_rz(float x) {
  return tessera::cuda_compat_detail::SaturatingCast<int>(std::trunc(x));
}
inline int __float2int_ru(float x) {
  return tessera::cuda_compat_detail::SaturatingCast<int>(std::ceil(x));
}
inline int __float2int_rd(float x) {
  return tessera::cuda_compat_detail::SaturatingCast<int>(std::floor(x));
}
inline unsigned int __float2uint_rn(float x) {
  return tessera::cuda_compat_detail::SaturatingCast<unsigned int>(std::nearbyint(x));
}
inline unsigned int __float2uint_rz(float x) {
  return tessera::cuda_compat_detail::SaturatingCast<unsigned int>(std::trunc(x));
}
inline unsigned int __float2uint_ru(float x) {
  return tessera::cuda_compat_detail::SaturatingCast<unsigned int>(std::ceil(x));
}
inline unsigned int __float2uint_rd(float x) {
  return tessera::cuda_compat_detail::SaturatingCast<unsigned int>(std::floor(x));
}
inline long long __float2ll_rn(float x) {
  return tessera::cuda_compat_detail::SaturatingCast<long long>(std::nearbyint(x));
}
inline long long __float2ll_rz(float x) {
  return tessera::cuda_compat_detail::SaturatingCast<long long>(std::trunc(x));
}
inline long long __float2ll_ru(float x) {
  return tessera::cuda_compat_detail::SaturatingCast<long long>(std::ceil(x));
}
inline long long __float2ll_rd(float x) {
  return tessera::cuda_compat_detail::SaturatingCast<long long>(std::floor(x));
}
inline unsigned long long __float2ull_rn(float x) {
  return tessera::cuda_compat_detail::SaturatingCast<unsigned long long>(std::nearbyint(x));
}
inline unsigned long long __float2ull_rz(float x) {
  return tessera::cuda_compat_detail::SaturatingCast<unsigned long long>(std::trunc(x));
}
inline unsigned long long __float2ull_ru(float x) {
  return tessera::cuda_compat_detail::SaturatingCast<unsigned long long>(std::ceil(x));
}
inline unsigned long long __float2ull_rd(float x) {
  return tessera::cuda_compat_detail::SaturatingCast<unsigned long long>(std::floor(x));
}
inline unsigned int __double2uint_rn(double x) {
  return tessera::cuda_compat_detail::SaturatingCast<unsigned int>(std::nearbyint(x));
}
inline unsigned int __double2uint_rz(double x) {
  return tessera::cuda_compat_detail::SaturatingCast<unsigned int>(std::trunc(x));
}
inline int __double2int_rn(double x) {
  return tessera::cuda_compat_detail::SaturatingCast<int>(std::nearbyint(x));
}
inline int __double2int_rz(double x) {
  return tessera::cuda_compat_detail::SaturatingCast<int>(std::trunc(x));
}
// int-to-float and double-to-float conversions round to nearest in the default environment,
// which is what _rn asks for.
inline float __int2float_rn(int i) { return static_cast<float>(i); }
inline float __uint2float_rn(unsigned int u) { return static_cast<float>(u); }
inline float __ll2float_rn(long long i) { return static_cast<float>(i); }
inline float __ull2float_rn(unsigned long long u) { return static_cast<float>(u); }
inline double __int2double_rn(int i) { return i; }
inline double __uint2double_rn(unsigned int u) { return u; }
inline float __double2float_rn(double x) { return static_cast<float>(x); }

// ---- Single-precision intrinsics ----------------------------------------------------------------
// CUDA's fast versions trade accuracy for speed on the GPU; on a CPU the accurate libm function
// is the sensible stand-in, and programs only ever get more precision than they asked for.
inline float __saturatef(float x) {
  // NaN fails both comparisons and becomes 0, as CUDA specifies.
  return x > 0.0f ? (x < 1.0f ? x : 1.0f) : 0.0f;
}
inline float __fdividef(float x, float y) { return x / y; }
inline float __fadd_rn(float x, float y) { return x + y; }
inline float __fsub_rn(float x, float y) { return x - y; }
inline float __fmul_rn(float x, float y) { return x * y; }
inline float __fdiv_rn(float x, float y) { return x / y; }
inline float __fmaf_rn(float x, float y, float z) { return std::fma(x, y, z); }
inline float __frcp_rn(float x) { return 1.0f / x; }
namespace tessera_detail {
// The IEEE square root, as sqrtf, without libm's errno path: g++ sets errno by default
// (-fmath-errno), so each sqrtf carries a branch to a library call for negative arguments and
// spills the registers live across it, on the path of every normalize. sqrtss is the same
// correctly rounded operation (also for NaN and negative inputs), and CUDA's sqrtf sets no errno.
inline float Sqrt(float x) {
#if defined(__SSE__)
  return _mm_cvtss_f32(_mm_sqrt_ss(_mm_set_ss(x)));
#else
  return std::sqrt(x);
#endif
}
}  // namespace tessera_detail
inline float __fsqrt_rn(float x) { return tessera_detail::Sqrt(x); }
inline float __frsqrt_rn(float x) { return 1.0f / tessera_detail::Sqrt(x); }
inline float rsqrtf(float x) { return 1.0f / tessera_detail::Sqrt(x); }
inline double rsqrt(double x) { return 1.0 / std::sqrt(x); }
inline float rcbrtf(float x) { return 1.0f / std::cbrt(x); }
inline double rcbrt(double x) { return 1.0 / std::cbrt(x); }
inline float fdividef(float x, float y) { return x / y; }
// Lengths of 3- and 4-vectors given as components (CUDA math API), and their reciprocals.
inline float norm3df(float a, float b, float c) {
  return tessera_detail::Sqrt(a * a + b * b + c * c);
}
inline float rnorm3df(float a, float b, float c) { return 1.0f / norm3df(a, b, c); }
inline float norm4df(float a, float b, float c, float d) {
  return tessera_detail::Sqrt(a * a + b * b + c * c + d * d);
}
inline float rnorm4df(float a, float b, float c, float d) { return 1.0f / norm4df(a, b, c, d); }
inline float rhypotf(float x, float y) { return 1.0f / hypotf(x, y); }

#if !defined(__USE_GNU)
// glibc declares sincosf only for _GNU_SOURCE (which g++ defines by default); CUDA always has it.
inline void sincosf(float x, float* s, float* c) {
  *s = std::sin(x);
  *c = std::cos(x);
}
#endif

// glibc's <math.h> declares __expf, __sinf, ... as internal extern "C" functions that libm does
// not export, so a program calling them would fail to load. Redeclaring them inline, with the
// same C linkage and noexcept, gives them bodies without conflicting with those declarations.
extern "C" {
inline float __expf(float x) noexcept { return expf(x); }
inline float __exp10f(float x) noexcept { return powf(10.0f, x); }
inline float __logf(float x) noexcept { return logf(x); }
inline float __log2f(float x) noexcept { return log2f(x); }
inline float __log10f(float x) noexcept { return log10f(x); }
inline float __powf(float x, float y) noexcept { return powf(x, y); }
inline float __sinf(float x) noexcept { return sinf(x); }
inline float __cosf(float x) noexcept { return cosf(x); }
inline float __tanf(float x) noexcept { return tanf(x); }
inline void __sincosf(float x, float* s, float* c) noexcept {
  *s = sinf(x);
  *c = cosf(x);
}
// sin(pi x) and cos(pi x), CUDA math API (C23 names: a C library that declares them gets these
// definitions for its declarations). pi x is rounded to float first, so large x loses what
// CUDA's exact reduction keeps.
inline float sinpif(float x) noexcept { return sinf(static_cast<float>(M_PI) * x); }
inline float cospif(float x) noexcept { return cosf(static_cast<float>(M_PI) * x); }
inline double sinpi(double x) noexcept { return sin(M_PI * x); }
inline double cospi(double x) noexcept { return cos(M_PI * x); }
inline void sincospif(float x, float* s, float* c) noexcept {
  *s = sinpif(x);
  *c = cospif(x);
}
}  // extern "C"

// ---- Integer intrinsics -------------------------------------------------------------------------
inline int __popc(unsigned int x) { return __builtin_popcount(x); }
inline int __popcll(unsigned long long x) { return __builtin_popcountll(x); }
// __builtin_clz is undefined for 0; CUDA defines the count as the full width.
inline int __clz(int x) { return x == 0 ? 32 : __builtin_clz(static_cast<unsigned int>(x)); }
inline int __clzll(long long x) {
  return x == 0 ? 64 : __builtin_clzll(static_cast<unsigned long long>(x));
}
inline int __ffs(int x) { return __builtin_ffs(x); }
inline int __ffsll(long long x) { return __builtin_ffsll(x); }
inline unsigned int __brev(unsigned int x) {
  // Swap ever larger groups of bits: neighbours, pairs, nibbles, bytes, halves.
  x = ((x >> 1) & 0x55555555u) | ((x & 0x55555555u) << 1);
  x = ((x >> 2) & 0x33333333u) | ((x & 0x33333333u) << 2);
  x = ((x >> 4) & 0x0F0F0F0Fu) | ((x & 0x0F0F0F0Fu) << 4);
  x = ((x >> 8) & 0x00FF00FFu) | ((x & 0x00FF00FFu) << 8);
  return (x >> 16) | (x << 16);
}
inline unsigned long long __brevll(unsigned long long x) {
  return (static_cast<unsigned long long>(__brev(static_cast<unsigned int>(x))) << 32) |
         __brev(static_cast<unsigned int>(x >> 32));
}
// 24-bit multiplies: only the low 24 bits of each operand take part (sign-extended for the
// signed form), and the low 32 bits of the product are returned.
inline int __mul24(int x, int y) {
  const int64_t x24 = static_cast<int32_t>(static_cast<uint32_t>(x) << 8) >> 8;
  const int64_t y24 = static_cast<int32_t>(static_cast<uint32_t>(y) << 8) >> 8;
  return static_cast<int>(static_cast<uint32_t>(x24 * y24));
}
inline unsigned int __umul24(unsigned int x, unsigned int y) {
  return static_cast<unsigned int>(static_cast<uint64_t>(x & 0xFFFFFFu) * (y & 0xFFFFFFu));
}
// High halves of full-width products.
inline int __mulhi(int x, int y) { return static_cast<int>((static_cast<int64_t>(x) * y) >> 32); }
inline unsigned int __umulhi(unsigned int x, unsigned int y) {
  return static_cast<unsigned int>((static_cast<uint64_t>(x) * y) >> 32);
}
inline long long __mul64hi(long long x, long long y) {
  __extension__ typedef __int128 Wide;  // __extension__ keeps -pedantic quiet.
  return static_cast<long long>((static_cast<Wide>(x) * y) >> 64);
}
inline unsigned long long __umul64hi(unsigned long long x, unsigned long long y) {
  __extension__ typedef unsigned __int128 Wide;
  return static_cast<unsigned long long>((static_cast<Wide>(x) * y) >> 64);
}

// ---- min / max ----------------------------------------------------------------------------------
// CUDA declares these overloads globally; std::min/std::max stay untouched in namespace std.
// Under `using namespace std;` these non-templates win over the std templates for exact matches.
// Mixed signed/unsigned pairs compare as unsigned and mixed float/double as double, following
// the usual arithmetic conversions the way CUDA's overloads do.
inline int min(int a, int b) { return a < b ? a : b; }
inline unsigned int min(unsigned int a, unsigned int b) { return a < b ? a : b; }
inline unsigned int min(int a, unsigned int b) { return min(static_cast<unsigned int>(a), b); }
inline unsigned int min(unsigned int a, int b) { return min(a, static_cast<unsigned int>(b)); }
inline long min(long a, long b) { return a < b ? a : b; }
inline unsigned long min(unsigned long a, unsigned long b) { return a < b ? a : b; }
inline unsigned long min(long a, unsigned long b) { return min(static_cast<unsigned long>(a), b); }
inline unsigned long min(unsigned long a, long b) { return min(a, static_cast<unsigned long>(b)); }
inline long long min(long long a, long long b) { return a < b ? a : b; }
inline unsigned long long min(unsigned long long a, unsigned long long b) { return a < b ? a : b; }
inline unsigned long long min(long long a, unsigned long long b) {
  return min(static_cast<unsigned long long>(a), b);
}
inline unsigned long long min(unsigned long long a, long long b) {
  return min(a, static_cast<unsigned long long>(b));
}
inline float min(float a, float b) { return fminf(a, b); }
inline double min(double a, double b) { return fmin(a, b); }
inline double min(float a, double b) { return fmin(a, b); }
inline double min(double a, float b) { return fmin(a, b); }

inline int max(int a, int b) { return a > b ? a : b; }
inline unsigned int max(unsigned int a, unsigned int b) { return a > b ? a : b; }
inline unsigned int max(int a, unsigned int b) { return max(static_cast<unsigned int>(a), b); }
inline unsigned int max(unsigned int a, int b) { return max(a, static_cast<unsigned int>(b)); }
inline long max(long a, long b) { return a > b ? a : b; }
inline unsigned long max(unsigned long a, unsigned long b) { return a > b ? a : b; }
inline unsigned long max(long a, unsigned long b) { return max(static_cast<unsigned long>(a), b); }
inline unsigned long max(unsigned long a, long b) { return max(a, static_cast<unsigned long>(b)); }
inline long long max(long long a, long long b) { return a > b ? a : b; }
inline unsigned long long max(unsigned long long a, unsigned long long b) { return a > b ? a : b; }
inline unsigned long long max(long long a, unsigned long long b) {
  return max(static_cast<unsigned long long>(a), b);
}
inline unsigned long long max(unsigned long long a, long long b) {
  return max(a, static_cast<unsigned long long>(b));
}
inline float max(float a, float b) { return fmaxf(a, b); }
inline double max(double a, double b) { return fmax(a, b); }
inline double max(float a, double b) { return fmax(a, b); }
inline double max(double a, float b) { return fmax(a, b); }

// ---- Fences, barriers, memory, time -------------------------------------------------------------
// Every CUDA fence scope (block, device, system) is the whole process here.
inline void __threadfence() { __atomic_thread_fence(__ATOMIC_SEQ_CST); }
inline void __threadfence_block() { __atomic_thread_fence(__ATOMIC_SEQ_CST); }
inline void __threadfence_system() { __atomic_thread_fence(__ATOMIC_SEQ_CST); }
// OptiX forbids __syncthreads() in programs (its guide: "it will lock up your machine") and a
// launch index has no thread block to wait for, so it does nothing; it exists so that code
// sharing helpers with plain CUDA kernels still compiles.
inline void __syncthreads() {}

// Read-only cache loads are ordinary loads on a CPU.
template <typename T>
inline T __ldg(const T* address) {
  return *address;
}

// A monotonic counter in nanoseconds. Like CUDA's cycle counter it is only meaningful as a
// difference between two readings; unlike it, it is comparable across threads. clock() in
// program modules is the same counter (top of this file).
inline long long clock64() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

#endif  // TESSERA_DETAIL_CUDA_INTRINSICS_H_

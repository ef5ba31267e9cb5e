// Tests of the CUDA qualifiers and device intrinsics in tessera/cuda_compat.h.
#include "tessera/cuda_compat.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <climits>
#include <cmath>
#include <cstdint>
#include <limits>
#include <thread>
#include <type_traits>
#include <vector>

namespace {

// ---- Qualifiers compile away -------------------------------------------------------------------
__device__ __forceinline__ int Twice(int x) { return 2 * x; }
__host__ __device__ __noinline__ int Thrice(int x) { return 3 * x; }
__constant__ float kConstant = 1.5f;
__device__ int g_device_variable = 4;
struct __align__(16) Aligned16 {
  float x;
};
static_assert(alignof(Aligned16) == 16);

TEST(CudaQualifiersTest, CompileToPlainCpp) {
  __shared__ int shared_value;
  shared_value = Twice(Thrice(1));
  EXPECT_EQ(shared_value, 6);
  EXPECT_EQ(kConstant, 1.5f);
  EXPECT_EQ(g_device_variable, 4);
}

// ---- Bit reinterpretation ----------------------------------------------------------------------
TEST(CudaIntrinsicsTest, FloatBitPatterns) {
  EXPECT_EQ(__float_as_int(1.0f), 0x3F800000);
  EXPECT_EQ(__float_as_int(-0.0f), INT_MIN);
  EXPECT_EQ(__float_as_int(0.0f), 0);
  EXPECT_EQ(__float_as_uint(-2.0f), 0xC0000000u);
  EXPECT_EQ(__float_as_uint(std::numeric_limits<float>::infinity()), 0x7F800000u);
  EXPECT_EQ(__int_as_float(0x40490FDB), 3.14159274101257324f);
  EXPECT_EQ(__uint_as_float(0x3F000000u), 0.5f);
  EXPECT_TRUE(std::isnan(__uint_as_float(0x7FC00000u)));
  for (float x : {1.0f, -3.5f, 1e-40f, 123456.789f}) {
    EXPECT_EQ(__int_as_float(__float_as_int(x)), x);
    EXPECT_EQ(__uint_as_float(__float_as_uint(x)), x);
  }
  EXPECT_EQ(__double_as_longlong(1.0), 0x3FF0000000000000LL);
  EXPECT_EQ(__longlong_as_double(0x4000000000000000LL), 2.0);
}

// ---- Conversions -------------------------------------------------------------------------------
TEST(CudaIntrinsicsTest, FloatToIntRounding) {
  EXPECT_EQ(__float2int_rn(2.5f), 2);  // Ties to even.
  EXPECT_EQ(__float2int_rn(3.5f), 4);
  EXPECT_EQ(__float2int_rn(-2.5f), -2);
  EXPECT_EQ(__float2int_rn(2.6f), 3);
  EXPECT_EQ(__float2int_rz(-2.7f), -2);
  EXPECT_EQ(__float2int_rz(2.7f), 2);
  EXPECT_EQ(__float2int_ru(2.1f), 3);
  EXPECT_EQ(__float2int_ru(-2.9f), -2);
  EXPECT_EQ(__float2int_rd(-2.1f), -3);
  EXPECT_EQ(__float2int_rd(2.9f), 2);
  EXPECT_EQ(__float2uint_rn(2.5f), 2u);
  EXPECT_EQ(__float2uint_rz(7.9f), 7u);
  EXPECT_EQ(__float2uint_ru(7.1f), 8u);
  EXPECT_EQ(__float2uint_rd(7.9f), 7u);
  EXPECT_EQ(__float2ll_rn(1e12f + 0.0f), 999999995904LL);
  EXPECT_EQ(__float2ll_rz(-1.5f), -1LL);
  EXPECT_EQ(__double2int_rn(-0.5), 0);
  EXPECT_EQ(__double2int_rz(-1.99), -1);
}

TEST(CudaIntrinsicsTest, FloatToIntSaturates) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  EXPECT_EQ(__float2int_rn(1e10f), INT_MAX);
  EXPECT_EQ(__float2int_rn(-1e10f), INT_MIN);
  EXPECT_EQ(__float2int_rz(inf), INT_MAX);
  EXPECT_EQ(__float2int_rz(-inf), INT_MIN);
  EXPECT_EQ(__float2int_rn(nan), 0);
  EXPECT_EQ(__float2int_rn(2147483520.0f), 2147483520);  // Largest float below 2^31 fits.
  EXPECT_EQ(__float2uint_rn(-1.0f), 0u);
  EXPECT_EQ(__float2uint_rz(-0.9f), 0u);
  EXPECT_EQ(__float2uint_rn(5e9f), UINT_MAX);
  EXPECT_EQ(__float2uint_rn(nan), 0u);
  EXPECT_EQ(__float2ll_rn(1e30f), LLONG_MAX);
}

TEST(CudaIntrinsicsTest, IntToFloat) {
  EXPECT_EQ(__int2float_rn(-7), -7.0f);
  EXPECT_EQ(__int2float_rn(16777217), 16777216.0f);  // Nearest even of 2^24 + 1.
  EXPECT_EQ(__uint2float_rn(0xFFFFFFFFu), 4294967296.0f);
  EXPECT_EQ(__ll2float_rn(1LL << 40), 1099511627776.0f);
  EXPECT_EQ(__double2float_rn(0.1), 0.1f);
}

// ---- Float intrinsics --------------------------------------------------------------------------
TEST(CudaIntrinsicsTest, SaturateAndArithmetic) {
  EXPECT_EQ(__saturatef(-1.0f), 0.0f);
  EXPECT_EQ(__saturatef(2.0f), 1.0f);
  EXPECT_EQ(__saturatef(0.25f), 0.25f);
  EXPECT_EQ(__saturatef(std::numeric_limits<float>::quiet_NaN()), 0.0f);
  EXPECT_EQ(__fdividef(1.0f, 4.0f), 0.25f);
  EXPECT_EQ(__fadd_rn(1.0f, 2.0f), 3.0f);
  EXPECT_EQ(__fsub_rn(1.0f, 2.0f), -1.0f);
  EXPECT_EQ(__fmul_rn(1.5f, 2.0f), 3.0f);
  EXPECT_EQ(__fdiv_rn(1.0f, 8.0f), 0.125f);
  EXPECT_EQ(__fmaf_rn(2.0f, 3.0f, 1.0f), 7.0f);
  EXPECT_EQ(__frcp_rn(4.0f), 0.25f);
  EXPECT_EQ(__fsqrt_rn(16.0f), 4.0f);
  EXPECT_EQ(__frsqrt_rn(16.0f), 0.25f);
  EXPECT_EQ(rsqrtf(4.0f), 0.5f);
  EXPECT_EQ(rsqrt(4.0), 0.5);
  EXPECT_FLOAT_EQ(rcbrtf(8.0f), 0.5f);
  EXPECT_DOUBLE_EQ(rcbrt(27.0), 1.0 / 3.0);
}

TEST(CudaIntrinsicsTest, FastMathMatchesLibm) {
  for (float x : {0.1f, 0.5f, 1.0f, 2.0f, 3.0f}) {
    EXPECT_FLOAT_EQ(__expf(x), std::exp(x));
    EXPECT_FLOAT_EQ(__exp10f(x), std::pow(10.0f, x));
    EXPECT_FLOAT_EQ(__logf(x), std::log(x));
    EXPECT_FLOAT_EQ(__log2f(x), std::log2(x));
    EXPECT_FLOAT_EQ(__log10f(x), std::log10(x));
    EXPECT_FLOAT_EQ(__powf(x, 1.5f), std::pow(x, 1.5f));
    EXPECT_FLOAT_EQ(__sinf(x), std::sin(x));
    EXPECT_FLOAT_EQ(__cosf(x), std::cos(x));
    EXPECT_FLOAT_EQ(__tanf(x), std::tan(x));
    float s = 0.0f;
    float c = 0.0f;
    __sincosf(x, &s, &c);
    EXPECT_FLOAT_EQ(s, std::sin(x));
    EXPECT_FLOAT_EQ(c, std::cos(x));
    sincosf(x, &s, &c);
    EXPECT_FLOAT_EQ(s, std::sin(x));
    EXPECT_FLOAT_EQ(c, std::cos(x));
  }
}

// The square root behind normalize, length, rsqrtf and __fsqrt_rn is sqrtss rather than a libm
// call (no errno branch on the path): it must give libm's bits for every kind of input, since
// outputs are bit-identical across devices, and leave errno alone, as CUDA does.
TEST(CudaIntrinsicsTest, SquareRootIsLibmsBitsWithoutErrno) {
  auto bits = [](float x) { return __float_as_int(x); };
  std::vector<float> inputs = {0.0f,
                               -0.0f,
                               1.0f,
                               2.0f,
                               0.5f,
                               3.0e38f,
                               1.0e-38f,
                               1.0e-45f,
                               -1.0f,
                               -1.0e-45f,
                               std::numeric_limits<float>::infinity(),
                               -std::numeric_limits<float>::infinity(),
                               std::numeric_limits<float>::quiet_NaN(),
                               std::numeric_limits<float>::max(),
                               std::numeric_limits<float>::denorm_min()};
  // A sweep over many exponents and mantissas, negative ones included.
  for (uint32_t u = 0; u < 0xffffffffu - 0x01000193u; u += 0x01000193u) {
    inputs.push_back(__int_as_float(static_cast<int>(u)));
  }
  for (float x : inputs) {
    SCOPED_TRACE(::testing::Message() << "x = " << x << " (bits " << std::hex << bits(x) << ")");
    const float libm = std::sqrt(x);
    if (std::isnan(libm)) {
      EXPECT_TRUE(std::isnan(__fsqrt_rn(x)));
      EXPECT_TRUE(std::isnan(rsqrtf(x)));
    } else {
      EXPECT_EQ(bits(__fsqrt_rn(x)), bits(libm));
      EXPECT_EQ(bits(rsqrtf(x)), bits(1.0f / libm));
      EXPECT_EQ(bits(__frsqrt_rn(x)), bits(1.0f / libm));
    }
  }
  errno = 0;
  volatile float negative = -4.0f;
  EXPECT_TRUE(std::isnan(__fsqrt_rn(negative)));
  EXPECT_EQ(errno, 0);
}

// ---- Integer intrinsics ------------------------------------------------------------------------
TEST(CudaIntrinsicsTest, BitCounting) {
  EXPECT_EQ(__popc(0u), 0);
  EXPECT_EQ(__popc(0xF0F0u), 8);
  EXPECT_EQ(__popc(0xFFFFFFFFu), 32);
  EXPECT_EQ(__popcll(0xFFFFFFFFFFFFFFFFull), 64);
  EXPECT_EQ(__clz(0), 32);
  EXPECT_EQ(__clz(1), 31);
  EXPECT_EQ(__clz(-1), 0);
  EXPECT_EQ(__clz(0x00010000), 15);
  EXPECT_EQ(__clzll(0), 64);
  EXPECT_EQ(__clzll(1), 63);
  EXPECT_EQ(__ffs(0), 0);
  EXPECT_EQ(__ffs(1), 1);
  EXPECT_EQ(__ffs(8), 4);
  EXPECT_EQ(__ffs(INT_MIN), 32);
  EXPECT_EQ(__ffsll(1LL << 40), 41);
  EXPECT_EQ(__brev(1u), 0x80000000u);
  EXPECT_EQ(__brev(0x12345678u), 0x1E6A2C48u);
  EXPECT_EQ(__brev(__brev(0xDEADBEEFu)), 0xDEADBEEFu);
  EXPECT_EQ(__brevll(1ull), 1ull << 63);
  EXPECT_EQ(__brevll(0x00000000000000F0ull), 0x0F00000000000000ull);
}

TEST(CudaIntrinsicsTest, Multiplies) {
  EXPECT_EQ(__mul24(1000, 1000), 1000000);
  EXPECT_EQ(__mul24(-3, 7), -21);
  EXPECT_EQ(__mul24(0x00FFFFFF, 2), -2);  // 0xFFFFFF is -1 as a 24-bit integer.
  EXPECT_EQ(__mul24(0x7F000003, 2), 6);   // Bits 24-31 are ignored.
  EXPECT_EQ(__umul24(0x01000003u, 2u), 6u);
  EXPECT_EQ(__umul24(0xFFFFFFu, 0xFFFFFFu), 0xFE000001u);  // Low 32 bits of the product.
  EXPECT_EQ(__umulhi(0xFFFFFFFFu, 0xFFFFFFFFu), 0xFFFFFFFEu);
  EXPECT_EQ(__umulhi(0x10000u, 0x10000u), 1u);
  EXPECT_EQ(__mulhi(-1, 1), -1);
  EXPECT_EQ(__mulhi(0x40000000, 8), 2);
  EXPECT_EQ(__umul64hi(~0ull, 2ull), 1ull);
  EXPECT_EQ(__mul64hi(-1LL, 1LL), -1LL);
  EXPECT_EQ(__mul64hi(1LL << 62, 8LL), 2LL);
}

TEST(CudaIntrinsicsTest, MinMaxOverloads) {
  EXPECT_EQ(min(3, 5), 3);
  EXPECT_EQ(max(3, 5), 5);
  EXPECT_EQ(min(3u, 5u), 3u);
  EXPECT_EQ(max(-1L, 2L), 2L);
  EXPECT_EQ(min(1ull << 40, 5ull), 5ull);
  EXPECT_EQ(max(-7LL, -8LL), -7LL);
  EXPECT_EQ(min(1.5f, 2.5f), 1.5f);
  EXPECT_EQ(max(1.5, -2.5), 1.5);
  // Mixed signedness follows the usual arithmetic conversions: -1 becomes UINT_MAX.
  EXPECT_EQ(max(-1, 1u), 0xFFFFFFFFu);
  EXPECT_EQ(min(1u, -1), 1u);
  static_assert(std::is_same_v<decltype(max(1.0f, 2.0)), double>);
  static_assert(std::is_same_v<decltype(min(1.0f, 2.0f)), float>);
  static_assert(std::is_same_v<decltype(min(1, 2u)), unsigned int>);
  // NaN is ignored, like fminf/fmaxf.
  EXPECT_EQ(max(std::numeric_limits<float>::quiet_NaN(), 1.0f), 1.0f);
}

TEST(CudaIntrinsicsTest, MinMaxWinOverStdUnderUsingDirective) {
  using namespace std;
  // std::min/std::max are templates; the exact-match non-template overloads are preferred.
  EXPECT_EQ(min(4, 2), 2);
  EXPECT_EQ(max(4.0f, 2.0f), 4.0f);
}

// ---- Atomics -----------------------------------------------------------------------------------
constexpr int kThreads = 8;
constexpr int kIterations = 20000;

template <typename Body>
void RunConcurrently(Body body) {
  std::vector<std::thread> threads;
  for (int t = 0; t < kThreads; ++t) threads.emplace_back(body, t);
  for (std::thread& thread : threads) thread.join();
}

TEST(CudaAtomicsTest, ConcurrentAddsGiveExactSums) {
  int i = 0;
  unsigned int u = 0;
  unsigned long long ull = 0;
  float f = 0.0f;
  double d = 0.0;
  RunConcurrently([&](int) {
    for (int k = 0; k < kIterations; ++k) {
      atomicAdd(&i, 1);
      atomicAdd(&u, 2u);
      atomicAdd(&ull, 1ull << 33);
      atomicAdd(&f, 1.0f);  // Sums below 2^24 are exact in float, so any lost update shows.
      atomicAdd(&d, 0.5);
    }
  });
  const int total = kThreads * kIterations;
  EXPECT_EQ(i, total);
  EXPECT_EQ(u, 2u * total);
  EXPECT_EQ(ull, static_cast<unsigned long long>(total) << 33);
  EXPECT_EQ(f, static_cast<float>(total));
  EXPECT_EQ(d, 0.5 * total);
}

TEST(CudaAtomicsTest, ReturnOldValues) {
  int i = 10;
  EXPECT_EQ(atomicAdd(&i, 5), 10);
  EXPECT_EQ(atomicSub(&i, 3), 15);
  EXPECT_EQ(i, 12);
  unsigned int u = 1;
  EXPECT_EQ(atomicSub(&u, 2u), 1u);
  EXPECT_EQ(u, 0xFFFFFFFFu);  // Wraps, as in CUDA.
  EXPECT_EQ(atomicExch(&i, 99), 12);
  EXPECT_EQ(i, 99);
  EXPECT_EQ(atomicExch(&u, 3u), 0xFFFFFFFFu);
  unsigned long long ull = 5;
  EXPECT_EQ(atomicExch(&ull, 6ull), 5ull);
  float f = 1.5f;
  EXPECT_EQ(atomicExch(&f, 2.5f), 1.5f);
  EXPECT_EQ(f, 2.5f);
  EXPECT_EQ(atomicAdd(&f, 0.5f), 2.5f);
  EXPECT_EQ(f, 3.0f);
  double d = 1.0;
  EXPECT_EQ(atomicAdd(&d, 1.0), 1.0);
}

TEST(CudaAtomicsTest, CompareAndSwap) {
  int i = 5;
  EXPECT_EQ(atomicCAS(&i, 4, 9), 5);  // Mismatch: unchanged, returns current.
  EXPECT_EQ(i, 5);
  EXPECT_EQ(atomicCAS(&i, 5, 9), 5);  // Match: swapped, returns old.
  EXPECT_EQ(i, 9);
  unsigned int u = 1;
  EXPECT_EQ(atomicCAS(&u, 1u, 2u), 1u);
  EXPECT_EQ(u, 2u);
  unsigned long long ull = 1ull << 40;
  EXPECT_EQ(atomicCAS(&ull, 1ull << 40, 7ull), 1ull << 40);
  EXPECT_EQ(ull, 7ull);
}

TEST(CudaAtomicsTest, MinMaxUnderContention) {
  int lo = INT_MAX;
  int hi = INT_MIN;
  unsigned int ulo = UINT_MAX;
  unsigned long long uhi = 0;
  long long llo = LLONG_MAX;
  RunConcurrently([&](int t) {
    for (int k = 0; k < kIterations; ++k) {
      const int v = (k * 7919 + t * 104729) % 100003 - 50000;
      atomicMin(&lo, v);
      atomicMax(&hi, v);
      atomicMin(&ulo, static_cast<unsigned int>(v + 50000));
      atomicMax(&uhi, static_cast<unsigned long long>(v + 50000) << 20);
      atomicMin(&llo, static_cast<long long>(v) * 3);
    }
  });
  int expected_lo = INT_MAX;
  int expected_hi = INT_MIN;
  for (int t = 0; t < kThreads; ++t) {
    for (int k = 0; k < kIterations; ++k) {
      const int v = (k * 7919 + t * 104729) % 100003 - 50000;
      expected_lo = std::min(expected_lo, v);
      expected_hi = std::max(expected_hi, v);
    }
  }
  EXPECT_EQ(lo, expected_lo);
  EXPECT_EQ(hi, expected_hi);
  EXPECT_EQ(ulo, static_cast<unsigned int>(expected_lo + 50000));
  EXPECT_EQ(uhi, static_cast<unsigned long long>(expected_hi + 50000) << 20);
  EXPECT_EQ(llo, static_cast<long long>(expected_lo) * 3);
  EXPECT_EQ(atomicMin(&lo, expected_lo - 1), expected_lo);  // Returns the old value.
}

TEST(CudaAtomicsTest, WrappingIncrementAndDecrement) {
  unsigned int counter = 0;
  std::vector<unsigned int> seen;
  for (int k = 0; k < 6; ++k) seen.push_back(atomicInc(&counter, 3u));
  EXPECT_EQ(seen, (std::vector<unsigned int>{0, 1, 2, 3, 0, 1}));
  EXPECT_EQ(counter, 2u);

  counter = 1;
  seen.clear();
  for (int k = 0; k < 4; ++k) seen.push_back(atomicDec(&counter, 2u));
  EXPECT_EQ(seen, (std::vector<unsigned int>{1, 0, 2, 1}));
  counter = 9;  // Above the limit: reset to it.
  EXPECT_EQ(atomicDec(&counter, 2u), 9u);
  EXPECT_EQ(counter, 2u);

  // A ring index shared by all threads stays in range and counts every increment.
  unsigned int ring = 0;
  RunConcurrently([&](int) {
    for (int k = 0; k < kIterations; ++k) atomicInc(&ring, 999u);
  });
  EXPECT_EQ(ring, static_cast<unsigned int>(kThreads * kIterations) % 1000u);
}

TEST(CudaAtomicsTest, BitwiseOperations) {
  unsigned int bits = 0;
  RunConcurrently([&](int t) {
    for (int k = 0; k < 4; ++k) atomicOr(&bits, 1u << (t * 4 + k));
  });
  EXPECT_EQ(bits, 0xFFFFFFFFu);
  RunConcurrently([&](int t) { atomicAnd(&bits, ~(1u << t)); });
  EXPECT_EQ(bits, 0xFFFFFF00u);
  int flips = 0;
  RunConcurrently([&](int) {
    for (int k = 0; k < 1001; ++k) atomicXor(&flips, 1);
  });
  EXPECT_EQ(flips, 0);  // 8 threads * 1001 flips is even.
  unsigned long long wide = 0;
  EXPECT_EQ(atomicOr(&wide, 1ull << 50), 0ull);
  EXPECT_EQ(atomicXor(&wide, 3ull), 1ull << 50);
  EXPECT_EQ(atomicAnd(&wide, 1ull), (1ull << 50) | 3ull);
  EXPECT_EQ(wide, 1ull);
  int i = 6;
  EXPECT_EQ(atomicAnd(&i, 3), 6);
  EXPECT_EQ(i, 2);
}

TEST(CudaAtomicsTest, SpinLockWithCasAndFences) {
  // The CUDA idiom for a critical section: CAS to acquire, fence, work, fence, exchange to
  // release. The protected counter is a plain int; any broken exclusion loses increments.
  int lock = 0;
  long long protected_sum = 0;
  RunConcurrently([&](int) {
    for (int k = 0; k < kIterations / 4; ++k) {
      while (atomicCAS(&lock, 0, 1) != 0) {
      }
      __threadfence();
      protected_sum += 3;
      __threadfence();
      atomicExch(&lock, 0);
    }
  });
  EXPECT_EQ(protected_sum, 3LL * kThreads * (kIterations / 4));
}

// ---- Fences, barriers, loads, time -------------------------------------------------------------
TEST(CudaMiscTest, BarriersAndLoads) {
  __syncthreads();  // A no-op that must still compile.
  __threadfence_block();
  __threadfence_system();
  const float values[2] = {1.0f, 2.0f};
  EXPECT_EQ(__ldg(&values[1]), 2.0f);
}

TEST(CudaMiscTest, Clock64IsMonotonicAndAdvances) {
  long long previous = clock64();
  const long long start = previous;
  for (int k = 0; k < 1000; ++k) {
    const long long now = clock64();
    EXPECT_GE(now, previous);
    previous = now;
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(2));
  EXPECT_GE(clock64() - start, 2000000LL);  // Nanoseconds.
  static_assert(std::is_same_v<decltype(clock64()), long long>);
}

// The 64-bit and double conversions: each rounding mode, and saturation (NaN gives 0).
TEST(CudaIntrinsicsTest, WideConversions) {
  EXPECT_EQ(__float2ull_rn(2.5f), 2ull);
  EXPECT_EQ(__float2ull_rz(2.7f), 2ull);
  EXPECT_EQ(__float2ull_ru(2.1f), 3ull);
  EXPECT_EQ(__float2ull_rd(2.9f), 2ull);
  EXPECT_EQ(__float2ull_rz(-3.0f), 0ull);
  EXPECT_EQ(__float2ull_rn(1e30f), ~0ull);
  EXPECT_EQ(__float2ull_rn(std::nanf("")), 0ull);
  EXPECT_EQ(__float2ll_ru(-2.5f), -2ll);
  EXPECT_EQ(__float2ll_rd(-2.5f), -3ll);
  EXPECT_EQ(__double2uint_rn(3.5), 4u);
  EXPECT_EQ(__double2uint_rz(-1.0), 0u);
  EXPECT_EQ(__ull2float_rn(1ull << 40), 1099511627776.0f);
  EXPECT_EQ(__int2double_rn(-7), -7.0);
  EXPECT_EQ(__uint2double_rn(7u), 7.0);
}

// CUDA math API functions glibc lacks.
TEST(CudaIntrinsicsTest, MathApiExtras) {
  EXPECT_EQ(fdividef(1.0f, 4.0f), 0.25f);
  EXPECT_EQ(norm3df(2.0f, 3.0f, 6.0f), 7.0f);
  EXPECT_EQ(rnorm3df(0.0f, 3.0f, 4.0f), 0.2f);
  EXPECT_EQ(norm4df(1.0f, 1.0f, 1.0f, 1.0f), 2.0f);
  EXPECT_EQ(rnorm4df(2.0f, 2.0f, 2.0f, 2.0f), 0.25f);
  EXPECT_FLOAT_EQ(rhypotf(3.0f, 4.0f), 0.2f);
  EXPECT_NEAR(sinpif(0.5f), 1.0f, 1e-6f);
  EXPECT_NEAR(cospif(1.0f), -1.0f, 1e-6f);
  EXPECT_NEAR(sinpi(1.0 / 6.0), 0.5, 1e-12);
  EXPECT_NEAR(cospi(1.0 / 3.0), 0.5, 1e-12);
  float s = 0.0f, c = 0.0f;
  sincospif(0.25f, &s, &c);
  EXPECT_NEAR(s, std::sqrt(0.5f), 1e-6f);
  EXPECT_NEAR(c, std::sqrt(0.5f), 1e-6f);
}

// The scoped atomics (atomicAdd_block, atomicCAS_system, ...) are the same operations.
TEST(CudaAtomicsTest, ScopedFormsAreTheSameOperations) {
  unsigned int u = 5;
  EXPECT_EQ(atomicAdd_block(&u, 2u), 5u);
  EXPECT_EQ(atomicAdd_system(&u, 3u), 7u);
  EXPECT_EQ(u, 10u);
  unsigned long long l = 1;
  EXPECT_EQ(atomicCAS_system(&l, 1ull, 9ull), 1ull);
  EXPECT_EQ(atomicMax_block(&l, 4ull), 9ull);
  EXPECT_EQ(l, 9ull);
  float f = 1.0f;
  EXPECT_EQ(atomicExch_block(&f, 2.0f), 1.0f);
  EXPECT_EQ(atomicInc_system(&u, 10u), 10u);
  EXPECT_EQ(u, 0u);
  int i = 6;
  EXPECT_EQ(atomicXor_block(&i, 3), 6);
  EXPECT_EQ(i, 5);
}

}  // namespace

// Numeric tests of the vector math in optixu_math_namespace.h, and of how its names resolve.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <sstream>
#include <type_traits>

#include "optix_math.h"
#include "optixu/optixu_math.h"
#include "optixu/optixu_math_namespace.h"
#include "optixu/optixu_math_stream_namespace.h"

namespace {

constexpr float kEps = 1e-6f;

#define EXPECT_FLOAT2_EQ(v, ex, ey) \
  do {                              \
    EXPECT_FLOAT_EQ((v).x, ex);     \
    EXPECT_FLOAT_EQ((v).y, ey);     \
  } while (0)
#define EXPECT_FLOAT3_EQ(v, ex, ey, ez) \
  do {                                  \
    EXPECT_FLOAT_EQ((v).x, ex);         \
    EXPECT_FLOAT_EQ((v).y, ey);         \
    EXPECT_FLOAT_EQ((v).z, ez);         \
  } while (0)
#define EXPECT_FLOAT4_EQ(v, ex, ey, ez, ew) \
  do {                                      \
    EXPECT_FLOAT_EQ((v).x, ex);             \
    EXPECT_FLOAT_EQ((v).y, ey);             \
    EXPECT_FLOAT_EQ((v).z, ez);             \
    EXPECT_FLOAT_EQ((v).w, ew);             \
  } while (0)
#define EXPECT_FLOAT3_NEAR(v, ex, ey, ez, eps) \
  do {                                         \
    EXPECT_NEAR((v).x, ex, eps);               \
    EXPECT_NEAR((v).y, ey, eps);               \
    EXPECT_NEAR((v).z, ez, eps);               \
  } while (0)

TEST(MathTest, Constants) {
  EXPECT_FLOAT_EQ(M_PIf, static_cast<float>(M_PI));
  EXPECT_FLOAT_EQ(M_PI_2f, static_cast<float>(M_PI / 2));
  EXPECT_FLOAT_EQ(M_PI_4f, static_cast<float>(M_PI / 4));
  EXPECT_FLOAT_EQ(M_1_PIf, static_cast<float>(1 / M_PI));
  EXPECT_FLOAT_EQ(M_2_PIf, static_cast<float>(2 / M_PI));
  EXPECT_FLOAT_EQ(M_Ef, static_cast<float>(M_E));
  EXPECT_FLOAT_EQ(M_SQRT2f, static_cast<float>(M_SQRT2));
  EXPECT_FLOAT_EQ(M_SQRT1_2f, static_cast<float>(M_SQRT1_2));
  EXPECT_FLOAT_EQ(M_LN2f, static_cast<float>(M_LN2));
  static_assert(std::is_same_v<decltype(M_PIf), float>);
}

TEST(MathTest, Float3Arithmetic) {
  const float3 a = make_float3(1.0f, 2.0f, 3.0f);
  const float3 b = make_float3(4.0f, -5.0f, 0.5f);
  EXPECT_FLOAT3_EQ(a + b, 5.0f, -3.0f, 3.5f);
  EXPECT_FLOAT3_EQ(a - b, -3.0f, 7.0f, 2.5f);
  EXPECT_FLOAT3_EQ(a * b, 4.0f, -10.0f, 1.5f);
  EXPECT_FLOAT3_EQ(a / b, 0.25f, -0.4f, 6.0f);
  EXPECT_FLOAT3_EQ(-a, -1.0f, -2.0f, -3.0f);
  EXPECT_FLOAT3_EQ(a + 1.0f, 2.0f, 3.0f, 4.0f);
  EXPECT_FLOAT3_EQ(1.0f + a, 2.0f, 3.0f, 4.0f);
  EXPECT_FLOAT3_EQ(a - 1.0f, 0.0f, 1.0f, 2.0f);
  EXPECT_FLOAT3_EQ(1.0f - a, 0.0f, -1.0f, -2.0f);
  EXPECT_FLOAT3_EQ(a * 2.0f, 2.0f, 4.0f, 6.0f);
  EXPECT_FLOAT3_EQ(2.0f * a, 2.0f, 4.0f, 6.0f);
  EXPECT_FLOAT3_EQ(a / 2.0f, 0.5f, 1.0f, 1.5f);
  EXPECT_FLOAT3_EQ(6.0f / a, 6.0f, 3.0f, 2.0f);

  float3 c = a;
  c += b;
  EXPECT_FLOAT3_EQ(c, 5.0f, -3.0f, 3.5f);
  c -= b;
  EXPECT_FLOAT3_EQ(c, 1.0f, 2.0f, 3.0f);
  c *= b;
  EXPECT_FLOAT3_EQ(c, 4.0f, -10.0f, 1.5f);
  c /= b;
  EXPECT_FLOAT3_EQ(c, 1.0f, 2.0f, 3.0f);
  c += 1.0f;
  c -= 0.5f;
  c *= 2;  // An int scalar converts to float, as in OptiX code like `PP *= 2`.
  c /= 4.0f;
  EXPECT_FLOAT3_EQ(c, 0.75f, 1.25f, 1.75f);
  // Compound assignment yields the left operand.
  float3 d = a;
  (d *= 2.0f) += 1.0f;
  EXPECT_FLOAT3_EQ(d, 3.0f, 5.0f, 7.0f);
}

TEST(MathTest, Float2AndFloat4Arithmetic) {
  const float2 a = make_float2(1.0f, -2.0f);
  const float2 b = make_float2(3.0f, 4.0f);
  EXPECT_FLOAT2_EQ(a + b, 4.0f, 2.0f);
  EXPECT_FLOAT2_EQ(a - b, -2.0f, -6.0f);
  EXPECT_FLOAT2_EQ(a * b, 3.0f, -8.0f);
  EXPECT_FLOAT2_EQ(b / a, 3.0f, -2.0f);
  EXPECT_FLOAT2_EQ(-a, -1.0f, 2.0f);
  EXPECT_FLOAT2_EQ(0.5f * b - 1.0f, 0.5f, 1.0f);
  EXPECT_FLOAT2_EQ(1.0f / b, 1.0f / 3.0f, 0.25f);
  float2 c = a;
  c *= b;
  c -= 1.0f;
  EXPECT_FLOAT2_EQ(c, 2.0f, -9.0f);

  const float4 p = make_float4(1.0f, 2.0f, 3.0f, 4.0f);
  const float4 q = make_float4(2.0f, 2.0f, 2.0f, 2.0f);
  EXPECT_FLOAT4_EQ(p + q, 3.0f, 4.0f, 5.0f, 6.0f);
  EXPECT_FLOAT4_EQ(p - q, -1.0f, 0.0f, 1.0f, 2.0f);
  EXPECT_FLOAT4_EQ(p * q, 2.0f, 4.0f, 6.0f, 8.0f);
  EXPECT_FLOAT4_EQ(p / q, 0.5f, 1.0f, 1.5f, 2.0f);
  EXPECT_FLOAT4_EQ(-p, -1.0f, -2.0f, -3.0f, -4.0f);
  EXPECT_FLOAT4_EQ(12.0f / p, 12.0f, 6.0f, 4.0f, 3.0f);
  float4 r = p;
  r /= 2.0f;
  r += q;
  EXPECT_FLOAT4_EQ(r, 2.5f, 3.0f, 3.5f, 4.0f);
}

TEST(MathTest, IntegerVectorArithmeticAndComparison) {
  const int3 a = make_int3(7, -7, 0);
  const int3 b = make_int3(2, 2, 5);
  EXPECT_TRUE(a + b == make_int3(9, -5, 5));
  EXPECT_TRUE(a - b == make_int3(5, -9, -5));
  EXPECT_TRUE(a * b == make_int3(14, -14, 0));
  EXPECT_TRUE(a / b == make_int3(3, -3, 0));  // Truncating division, as in C.
  EXPECT_TRUE(-a == make_int3(-7, 7, 0));
  EXPECT_TRUE(a * 2 == make_int3(14, -14, 0));
  EXPECT_TRUE(2 * a == make_int3(14, -14, 0));
  EXPECT_TRUE(14 / b == make_int3(7, 7, 2));
  EXPECT_TRUE(a != b);
  EXPECT_FALSE(a != a);
  EXPECT_FALSE(make_int3(1, 2, 3) == make_int3(1, 2, 4));
  int3 c = a;
  c += b;
  c -= 1;
  c *= 2;
  c /= make_int3(2, 2, 2);
  EXPECT_TRUE(c == make_int3(8, -6, 4));

  const int2 i2 = make_int2(3, 4);
  EXPECT_TRUE(i2 * i2 == make_int2(9, 16));
  EXPECT_TRUE(-i2 == make_int2(-3, -4));
  const int4 i4 = make_int4(1, 2, 3, 4);
  EXPECT_TRUE(i4 + i4 == make_int4(2, 4, 6, 8));
  EXPECT_TRUE(-i4 == make_int4(-1, -2, -3, -4));
  EXPECT_TRUE(i4 != make_int4(1, 2, 3, 5));

  const uint2 u = make_uint2(640, 480);
  EXPECT_TRUE(u / 2u == make_uint2(320, 240));
  EXPECT_TRUE(u - make_uint2(1, 1) == make_uint2(639, 479));
  // Unsigned arithmetic wraps, as in CUDA.
  EXPECT_TRUE(make_uint3(0, 1, 2) - 1u == make_uint3(0xFFFFFFFFu, 0, 1));
  uint4 v = make_uint4(1, 2, 3, 4);
  v *= 3u;
  EXPECT_TRUE(v == make_uint4(3, 6, 9, 12));
  EXPECT_FALSE(v != make_uint4(3, 6, 9, 12));
}

TEST(MathTest, IntegerMinMaxClamp) {
  EXPECT_TRUE(min(make_int2(1, 5), make_int2(3, -2)) == make_int2(1, -2));
  EXPECT_TRUE(max(make_int3(1, 5, 0), make_int3(3, -2, 0)) == make_int3(3, 5, 0));
  EXPECT_TRUE(min(make_uint4(1, 9, 3, 4), make_uint4(2, 2, 2, 2)) == make_uint4(1, 2, 2, 2));
  EXPECT_TRUE(clamp(make_int3(-5, 5, 15), 0, 10) == make_int3(0, 5, 10));
  EXPECT_TRUE(clamp(make_uint2(1, 50), make_uint2(2, 2), make_uint2(4, 40)) == make_uint2(2, 40));
  EXPECT_EQ(clamp(15, 0, 10), 10);
  EXPECT_EQ(clamp(-15, 0, 10), 0);
  EXPECT_EQ(clamp(5u, 6u, 10u), 6u);
}

TEST(MathTest, ScalarHelpers) {
  EXPECT_EQ(clamp(1.5f, 0.0f, 1.0f), 1.0f);
  EXPECT_EQ(clamp(-0.5f, 0.0f, 1.0f), 0.0f);
  EXPECT_EQ(clamp(0.25f, 0.0f, 1.0f), 0.25f);
  // fminf/fmaxf semantics: a NaN argument yields the other one, so a NaN clamps to the upper end
  // (fmaxf(lo, fminf(NaN, hi)) == hi), and a vector's NaN components likewise.
  const float nan = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(clamp(nan, 0.0f, 1.0f), 1.0f);
  const float3 lo = fminf(make_float3(nan, 2.0f, 3.0f), make_float3(1.0f, nan, 0.5f));
  EXPECT_EQ(lo.x, 1.0f);
  EXPECT_EQ(lo.y, 2.0f);
  EXPECT_EQ(lo.z, 0.5f);
  const float2 hi = fmaxf(make_float2(nan, -2.0f), make_float2(-1.0f, nan));
  EXPECT_EQ(hi.x, -1.0f);
  EXPECT_EQ(hi.y, -2.0f);
  EXPECT_EQ(fminf(make_float3(4.0f, nan, 3.0f)), 3.0f);
  EXPECT_EQ(fmaxf(make_float4(nan, 1.0f, 7.0f, nan)), 7.0f);
  EXPECT_FLOAT_EQ(lerp(2.0f, 4.0f, 0.25f), 2.5f);
  EXPECT_FLOAT_EQ(lerp(2.0f, 4.0f, 0.0f), 2.0f);
  EXPECT_FLOAT_EQ(lerp(2.0f, 4.0f, 1.0f), 4.0f);
  // Corners 0, 1 (along u), 2 (along v), 3 (both): the centre is their mean.
  EXPECT_FLOAT_EQ(bilerp(0.0f, 1.0f, 2.0f, 3.0f, 0.5f, 0.5f), 1.5f);
  EXPECT_FLOAT_EQ(bilerp(0.0f, 1.0f, 2.0f, 3.0f, 1.0f, 0.0f), 1.0f);
  EXPECT_FLOAT_EQ(bilerp(0.0f, 1.0f, 2.0f, 3.0f, 0.0f, 1.0f), 2.0f);
  EXPECT_EQ(smoothstep(1.0f, 2.0f, 0.5f), 0.0f);
  EXPECT_EQ(smoothstep(1.0f, 2.0f, 2.5f), 1.0f);
  EXPECT_FLOAT_EQ(smoothstep(1.0f, 2.0f, 1.5f), 0.5f);
  EXPECT_FLOAT_EQ(smoothstep(0.0f, 1.0f, 0.25f), 0.15625f);
  float previous = 0.0f;
  for (float x = 0.0f; x <= 1.0f; x += 0.0625f) {
    const float s = smoothstep(0.0f, 1.0f, x);
    EXPECT_GE(s, previous);
    previous = s;
  }
}

TEST(MathTest, ComponentwiseFunctions) {
  const float3 a = make_float3(-1.5f, 2.25f, 0.0f);
  const float3 b = make_float3(1.0f, -3.0f, -0.5f);
  EXPECT_FLOAT3_EQ(fminf(a, b), -1.5f, -3.0f, -0.5f);
  EXPECT_FLOAT3_EQ(fmaxf(a, b), 1.0f, 2.25f, 0.0f);
  EXPECT_FLOAT3_EQ(fabs(a), 1.5f, 2.25f, 0.0f);
  EXPECT_FLOAT3_EQ(floor(a), -2.0f, 2.0f, 0.0f);
  EXPECT_FLOAT3_EQ(ceil(a), -1.0f, 3.0f, 0.0f);
  EXPECT_FLOAT3_EQ(frac(a), 0.5f, 0.25f, 0.0f);
  EXPECT_FLOAT3_NEAR(expf(a), std::exp(-1.5f), std::exp(2.25f), 1.0f, 1e-5f);
  EXPECT_FLOAT3_EQ(fmodf(make_float3(5.5f, -5.5f, 1.0f), make_float3(2.0f, 2.0f, 3.0f)), 1.5f,
                   -1.5f, 1.0f);
  EXPECT_FLOAT3_EQ(copysignf(make_float3(1.0f, 2.0f, 3.0f), b), 1.0f, -2.0f, -3.0f);
  EXPECT_FLOAT3_EQ(clamp(a, -1.0f, 1.0f), -1.0f, 1.0f, 0.0f);
  EXPECT_FLOAT3_EQ(clamp(a, make_float3(0.0f), make_float3(1.0f, 2.0f, 3.0f)), 0.0f, 2.0f, 0.0f);

  const float2 c = make_float2(-0.25f, 3.75f);
  EXPECT_FLOAT2_EQ(frac(c), 0.75f, 0.75f);
  EXPECT_FLOAT2_EQ(floor(c), -1.0f, 3.0f);
  EXPECT_FLOAT2_EQ(fabs(c), 0.25f, 3.75f);
  EXPECT_FLOAT2_EQ(fmaxf(c, make_float2(0.0f)), 0.0f, 3.75f);
  EXPECT_FLOAT2_EQ(clamp(c, 0.0f, 1.0f), 0.0f, 1.0f);

  const float4 d = make_float4(-1.0f, 0.5f, 1.5f, -2.5f);
  EXPECT_FLOAT4_EQ(fabs(d), 1.0f, 0.5f, 1.5f, 2.5f);
  EXPECT_FLOAT4_EQ(ceil(d), -1.0f, 1.0f, 2.0f, -2.0f);
  EXPECT_FLOAT4_EQ(fminf(d, make_float4(0.0f)), -1.0f, 0.0f, 0.0f, -2.5f);
  EXPECT_FLOAT4_EQ(clamp(d, -2.0f, 1.0f), -1.0f, 0.5f, 1.0f, -2.0f);
}

TEST(MathTest, Reductions) {
  EXPECT_EQ(fmaxf(make_float3(1.0f, 7.0f, -2.0f)), 7.0f);
  EXPECT_EQ(fminf(make_float3(1.0f, 7.0f, -2.0f)), -2.0f);
  EXPECT_EQ(fmaxf(make_float2(-1.0f, -3.0f)), -1.0f);
  EXPECT_EQ(fminf(make_float2(-1.0f, -3.0f)), -3.0f);
  EXPECT_EQ(fmaxf(make_float4(1.0f, 2.0f, 9.0f, 3.0f)), 9.0f);
  EXPECT_EQ(fminf(make_float4(1.0f, 2.0f, 9.0f, -3.0f)), -3.0f);
}

TEST(MathTest, LerpAndBilerpOnVectors) {
  const float3 a = make_float3(0.0f, 10.0f, -4.0f);
  const float3 b = make_float3(2.0f, 20.0f, 4.0f);
  EXPECT_FLOAT3_EQ(lerp(a, b, 0.5f), 1.0f, 15.0f, 0.0f);
  EXPECT_FLOAT3_EQ(lerp(a, b, 0.0f), 0.0f, 10.0f, -4.0f);
  const float2 c = bilerp(make_float2(0.0f), make_float2(1.0f), make_float2(2.0f),
                          make_float2(3.0f, 7.0f), 1.0f, 1.0f);
  EXPECT_FLOAT2_EQ(c, 3.0f, 7.0f);
  const float4 d = lerp(make_float4(0.0f), make_float4(4.0f), 0.25f);
  EXPECT_FLOAT4_EQ(d, 1.0f, 1.0f, 1.0f, 1.0f);
}

TEST(MathTest, DotLengthNormalize) {
  EXPECT_FLOAT_EQ(dot(make_float3(1.0f, 2.0f, 3.0f), make_float3(4.0f, -5.0f, 6.0f)), 12.0f);
  EXPECT_FLOAT_EQ(dot(make_float2(1.0f, 2.0f), make_float2(3.0f, 4.0f)), 11.0f);
  EXPECT_FLOAT_EQ(dot(make_float4(1.0f, 2.0f, 3.0f, 4.0f), make_float4(1.0f)), 10.0f);
  EXPECT_FLOAT_EQ(length(make_float3(3.0f, 4.0f, 12.0f)), 13.0f);
  EXPECT_FLOAT_EQ(length(make_float2(3.0f, 4.0f)), 5.0f);
  EXPECT_FLOAT_EQ(length(make_float4(1.0f, 1.0f, 1.0f, 1.0f)), 2.0f);

  const float3 n = normalize(make_float3(3.0f, 0.0f, -4.0f));
  EXPECT_FLOAT3_EQ(n, 0.6f, 0.0f, -0.8f);
  EXPECT_NEAR(length(normalize(make_float3(1e-20f, 3e-20f, -2e-20f))), 1.0f, 1e-5f);
  EXPECT_NEAR(length(normalize(make_float3(1e18f, -3e18f, 2e18f))), 1.0f, 1e-5f);
  EXPECT_NEAR(length(normalize(make_float2(-7.0f, 0.5f))), 1.0f, kEps);
  EXPECT_NEAR(length(normalize(make_float4(1.0f, 2.0f, 3.0f, 4.0f))), 1.0f, kEps);
  // A zero vector has no direction: NaN, not a made-up unit vector.
  EXPECT_TRUE(std::isnan(normalize(make_float3(0.0f)).x));
  // The same bits as the IEEE formula with libm's root (outputs match across devices).
  for (float s : {1e-20f, 0.3f, 1.0f, 7.25f, 1e18f}) {
    const float3 v = make_float3(s, -2.5f * s, 0.75f * s);
    const float inv = 1.0f / std::sqrt(dot(v, v));
    const float3 u = normalize(v);
    EXPECT_EQ(__float_as_int(length(v)), __float_as_int(std::sqrt(dot(v, v))));
    EXPECT_EQ(__float_as_int(u.x), __float_as_int(v.x * inv));
    EXPECT_EQ(__float_as_int(u.y), __float_as_int(v.y * inv));
    EXPECT_EQ(__float_as_int(u.z), __float_as_int(v.z * inv));
  }
}

TEST(MathTest, CrossIsRightHandedAndOrthogonal) {
  const float3 x = make_float3(1.0f, 0.0f, 0.0f);
  const float3 y = make_float3(0.0f, 1.0f, 0.0f);
  const float3 z = make_float3(0.0f, 0.0f, 1.0f);
  EXPECT_FLOAT3_EQ(cross(x, y), 0.0f, 0.0f, 1.0f);
  EXPECT_FLOAT3_EQ(cross(y, z), 1.0f, 0.0f, 0.0f);
  EXPECT_FLOAT3_EQ(cross(z, x), 0.0f, 1.0f, 0.0f);
  const float3 a = make_float3(1.0f, 2.0f, 3.0f);
  const float3 b = make_float3(-4.0f, 0.5f, 2.0f);
  const float3 c = cross(a, b);
  EXPECT_NEAR(dot(c, a), 0.0f, 1e-5f);
  EXPECT_NEAR(dot(c, b), 0.0f, 1e-5f);
  EXPECT_FLOAT3_EQ(cross(b, a), -c.x, -c.y, -c.z);
}

TEST(MathTest, ReflectAndFaceforward) {
  const float3 up = make_float3(0.0f, 1.0f, 0.0f);
  EXPECT_FLOAT3_EQ(reflect(make_float3(1.0f, -1.0f, 0.0f), up), 1.0f, 1.0f, 0.0f);
  EXPECT_FLOAT3_EQ(reflect(make_float3(0.0f, -1.0f, 0.0f), up), 0.0f, 1.0f, 0.0f);
  EXPECT_FLOAT2_EQ(reflect(make_float2(1.0f, -2.0f), make_float2(0.0f, 1.0f)), 1.0f, 2.0f);

  // A ray coming down (direction -y) sees an up-facing normal unchanged...
  const float3 down = make_float3(0.0f, -1.0f, 0.0f);
  EXPECT_FLOAT3_EQ(faceforward(up, -down, up), 0.0f, 1.0f, 0.0f);
  // ...and a ray going up through the same surface sees it flipped toward itself.
  EXPECT_FLOAT3_EQ(faceforward(up, down, up), 0.0f, -1.0f, 0.0f);
  // nref decides, not n: a shading normal is flipped by the geometric normal's side.
  const float3 shading = normalize(make_float3(0.1f, 1.0f, 0.0f));
  const float3 ff = faceforward(shading, down, up);
  EXPECT_FLOAT3_EQ(ff, -shading.x, -shading.y, 0.0f);
}

TEST(MathTest, RefractFollowsSnellsLaw) {
  const float3 n = make_float3(0.0f, 1.0f, 0.0f);
  float3 t;
  // Normal incidence passes straight through.
  ASSERT_TRUE(refract(t, make_float3(0.0f, -1.0f, 0.0f), n, 1.5f));
  EXPECT_FLOAT3_NEAR(t, 0.0f, -1.0f, 0.0f, kEps);

  // Entering glass at 45 degrees: sin(out) = sin(in) / 1.5, bending toward the normal.
  const float3 i = normalize(make_float3(1.0f, -1.0f, 0.0f));
  ASSERT_TRUE(refract(t, i, n, 1.5f));
  EXPECT_NEAR(length(t), 1.0f, 1e-5f);
  EXPECT_NEAR(t.x, std::sin(M_PI_4f) / 1.5f, 1e-5f);
  EXPECT_LT(t.y, 0.0f);
  EXPECT_NEAR(t.z, 0.0f, kEps);

  // Leaving glass (i travels along n) below the critical angle: the ray bends away.
  const float3 out_i = normalize(make_float3(0.3f, 1.0f, 0.0f));
  ASSERT_TRUE(refract(t, out_i, n, 1.5f));
  const float sin_in = out_i.x;
  EXPECT_NEAR(t.x, sin_in * 1.5f, 1e-5f);
  EXPECT_GT(t.y, 0.0f);
  EXPECT_NEAR(length(t), 1.0f, 1e-5f);
}

// OptiX normalizes the transmitted direction, so r is unit length whatever the length of i: for
// i = (2, -2, 0) the unnormalized result would be (4/3, -1.5275, 0).
TEST(MathTest, RefractNormalizesItsResult) {
  const float3 n = make_float3(0.0f, 1.0f, 0.0f);
  float3 r;
  ASSERT_TRUE(refract(r, make_float3(2.0f, -2.0f, 0.0f), n, 1.5f));
  EXPECT_NEAR(length(r), 1.0f, 1e-6f);
  const float k = 1.0f + 3.0f / 2.25f;  // 1 - eta^2 (1 - cos^2) with eta = 1/1.5, cos = 2.
  const float3 expected = normalize(make_float3(4.0f / 3.0f, -std::sqrt(k), 0.0f));
  EXPECT_FLOAT3_NEAR(r, expected.x, expected.y, expected.z, 1e-6f);
}

TEST(MathTest, RefractReportsTotalInternalReflection) {
  const float3 n = make_float3(0.0f, 1.0f, 0.0f);
  // Leaving glass of index 1.5 at 60 degrees: past the critical angle of asin(1/1.5) ~ 41.8.
  const float3 i = make_float3(std::sin(M_PIf / 3.0f), std::cos(M_PIf / 3.0f), 0.0f);
  float3 t = make_float3(7.0f);
  EXPECT_FALSE(refract(t, i, n, 1.5f));
  EXPECT_FLOAT3_EQ(t, 0.0f, 0.0f, 0.0f);
  // The same direction entering the denser medium always refracts.
  EXPECT_TRUE(refract(t, -i, n, 1.5f));
}

// Clamped as OptiX clamps, max(minimum, min(f, maximum)): with the bounds swapped (a "1 - F"
// weight) the result is minimum.
TEST(MathTest, FresnelSchlickClampOrder) {
  EXPECT_FLOAT_EQ(fresnel_schlick(1.0f), 0.0f);
  EXPECT_FLOAT_EQ(fresnel_schlick(0.0f), 1.0f);
  EXPECT_FLOAT_EQ(fresnel_schlick(0.5f, 5.0f, 1.0f, 0.0f), 1.0f);
}

TEST(MathTest, StreamOperators) {
  std::ostringstream out;
  out << make_float3(1.5f, 2.0f, 3.0f) << ' ' << make_int2(-1, 2) << ' ' << make_uint4(1, 2, 3, 4);
  EXPECT_EQ(out.str(), "[1.5, 2, 3] [-1, 2] [1, 2, 3, 4]");
  std::istringstream in("[4, 5, 6]");
  float3 v;
  in >> v;
  EXPECT_FLOAT3_EQ(v, 4.0f, 5.0f, 6.0f);
}

TEST(MathTest, Luminance) {
  EXPECT_FLOAT_EQ(luminance(make_float3(1.0f)), 1.0f);
  EXPECT_FLOAT_EQ(luminanceCIE(make_float3(1.0f)), 1.0f);
  EXPECT_FLOAT_EQ(luminance(make_float3(0.0f, 1.0f, 0.0f)), 0.59f);
  EXPECT_FLOAT_EQ(luminanceCIE(make_float3(0.0f, 0.0f, 1.0f)), 0.0722f);
  EXPECT_FLOAT_EQ(luminance(make_float3(2.0f, 0.0f, 0.0f)), 0.6f);
}

TEST(MathTest, GetAndSetByIndex) {
  float3 v = make_float3(1.0f, 2.0f, 3.0f);
  EXPECT_EQ(getByIndex(v, 0), 1.0f);
  EXPECT_EQ(getByIndex(v, 1), 2.0f);
  EXPECT_EQ(getByIndex(v, 2), 3.0f);
  setByIndex(v, 1, 9.0f);
  EXPECT_FLOAT3_EQ(v, 1.0f, 9.0f, 3.0f);

  float4 f4 = make_float4(0.0f);
  for (int i = 0; i < 4; ++i) setByIndex(f4, i, static_cast<float>(i * 10));
  EXPECT_FLOAT4_EQ(f4, 0.0f, 10.0f, 20.0f, 30.0f);
  float2 f2 = make_float2(0.0f);
  setByIndex(f2, 1, 5.0f);
  EXPECT_EQ(getByIndex(f2, 1), 5.0f);
  float1 f1 = make_float1(4.0f);
  setByIndex(f1, 0, 8.0f);
  EXPECT_EQ(getByIndex(f1, 0), 8.0f);

  int4 i4 = make_int4(1, 2, 3, 4);
  setByIndex(i4, 3, -4);
  EXPECT_EQ(getByIndex(i4, 3), -4);
  EXPECT_EQ(getByIndex(i4, 2), 3);
  uint3 u3 = make_uint3(1, 2, 3);
  setByIndex(u3, 0, 7u);
  EXPECT_EQ(getByIndex(u3, 0), 7u);
  int2 i2 = make_int2(5, 6);
  EXPECT_EQ(getByIndex(i2, 1), 6);
  uint1 u1 = make_uint1(3);
  EXPECT_EQ(getByIndex(u1, 0), 3u);
}

TEST(MathTest, Conversions) {
  const float4 f4 = make_float4(1.0f, 2.0f, 3.0f, 4.0f);
  EXPECT_FLOAT3_EQ(make_float3(f4), 1.0f, 2.0f, 3.0f);
  EXPECT_FLOAT2_EQ(make_float2(f4), 1.0f, 2.0f);
  EXPECT_FLOAT2_EQ(make_float2(make_float3(f4)), 1.0f, 2.0f);
  EXPECT_FLOAT3_EQ(make_float3(2.5f), 2.5f, 2.5f, 2.5f);
  EXPECT_FLOAT3_EQ(make_float3(0), 0.0f, 0.0f, 0.0f);
  EXPECT_FLOAT3_EQ(make_float3(make_float2(1.0f, 2.0f)), 1.0f, 2.0f, 0.0f);
  EXPECT_FLOAT3_EQ(make_float3(make_float2(1.0f, 2.0f), 5.0f), 1.0f, 2.0f, 5.0f);
  EXPECT_FLOAT4_EQ(make_float4(make_float3(1.0f, 2.0f, 3.0f)), 1.0f, 2.0f, 3.0f, 0.0f);
  EXPECT_FLOAT4_EQ(make_float4(make_float3(1.0f, 2.0f, 3.0f), 1.0f), 1.0f, 2.0f, 3.0f, 1.0f);
  EXPECT_FLOAT4_EQ(make_float4(make_float2(1.0f, 2.0f), 3.0f, 4.0f), 1.0f, 2.0f, 3.0f, 4.0f);
  EXPECT_FLOAT4_EQ(make_float4(-1.0f), -1.0f, -1.0f, -1.0f, -1.0f);
  EXPECT_FLOAT2_EQ(make_float2(7.0f), 7.0f, 7.0f);
  EXPECT_FLOAT2_EQ(make_float2(make_uint2(640, 480)), 640.0f, 480.0f);
  EXPECT_FLOAT2_EQ(make_float2(make_int2(-1, 2)), -1.0f, 2.0f);
  EXPECT_FLOAT3_EQ(make_float3(make_int3(-1, 0, 1)), -1.0f, 0.0f, 1.0f);
  EXPECT_FLOAT3_EQ(make_float3(make_uint3(1, 2, 3)), 1.0f, 2.0f, 3.0f);
  EXPECT_FLOAT4_EQ(make_float4(make_int4(1, 2, 3, -4)), 1.0f, 2.0f, 3.0f, -4.0f);
  EXPECT_FLOAT4_EQ(make_float4(make_uint4(1, 2, 3, 4)), 1.0f, 2.0f, 3.0f, 4.0f);

  // Float to integer truncates toward zero.
  EXPECT_TRUE(make_int3(make_float3(1.9f, -1.9f, 0.5f)) == make_int3(1, -1, 0));
  EXPECT_TRUE(make_int2(make_float2(2.5f, -2.5f)) == make_int2(2, -2));
  EXPECT_TRUE(make_int4(make_float4(1.5f)) == make_int4(1, 1, 1, 1));
  EXPECT_TRUE(make_uint2(make_float2(3.7f, 0.2f)) == make_uint2(3, 0));
  EXPECT_TRUE(make_uint3(make_int3(1, 2, 3)) == make_uint3(1, 2, 3));
  EXPECT_TRUE(make_int4(make_uint4(1, 2, 3, 4)) == make_int4(1, 2, 3, 4));
  EXPECT_TRUE(make_int2(3) == make_int2(3, 3));
  EXPECT_TRUE(make_uint3(4u) == make_uint3(4, 4, 4));
  EXPECT_TRUE(make_int3(make_int2(1, 2)) == make_int3(1, 2, 0));
  EXPECT_TRUE(make_int3(make_int2(1, 2), 3) == make_int3(1, 2, 3));
  EXPECT_TRUE(make_uint4(make_uint3(1, 2, 3), 4u) == make_uint4(1, 2, 3, 4));
  EXPECT_TRUE(make_uint4(make_uint3(1, 2, 3)) == make_uint4(1, 2, 3, 0));
  EXPECT_TRUE(make_int2(make_int4(1, 2, 3, 4)) == make_int2(1, 2));
  EXPECT_TRUE(make_uint3(make_uint4(1, 2, 3, 4)) == make_uint3(1, 2, 3));
  EXPECT_TRUE(make_int3(make_float3(-0.5f)) == make_int3(0, 0, 0));
}

// ---- Name resolution --------------------------------------------------------------------------
// The same function must be reachable qualified, through a using-directive and through ADL;
// these compile only if every spelling resolves without ambiguity.

TEST(MathTest, AssembledVectors) {
  EXPECT_FLOAT3_EQ(make_float3(1.f, make_float2(2.f, 3.f)), 1.f, 2.f, 3.f);
  EXPECT_FLOAT4_EQ(make_float4(1.f, make_float3(2.f, 3.f, 4.f)), 1.f, 2.f, 3.f, 4.f);
  EXPECT_FLOAT4_EQ(make_float4(make_float2(1.f, 2.f), make_float2(3.f, 4.f)), 1.f, 2.f, 3.f, 4.f);
  EXPECT_FLOAT4_EQ(make_float4(1.f, 2.f, make_float2(3.f, 4.f)), 1.f, 2.f, 3.f, 4.f);
  EXPECT_FLOAT4_EQ(make_float4(1.f, make_float2(2.f, 3.f), 4.f), 1.f, 2.f, 3.f, 4.f);
}

// The integer families assemble like the float ones (OptiX has the same set for int and uint).
TEST(MathTest, AssembledIntegerVectors) {
  EXPECT_TRUE(make_int3(1, make_int2(2, 3)) == make_int3(1, 2, 3));
  EXPECT_TRUE(make_int4(1, make_int3(2, 3, 4)) == make_int4(1, 2, 3, 4));
  EXPECT_TRUE(make_int4(make_int2(1, 2), make_int2(3, 4)) == make_int4(1, 2, 3, 4));
  EXPECT_TRUE(make_int4(make_int2(1, 2), 3, 4) == make_int4(1, 2, 3, 4));
  EXPECT_TRUE(make_int4(1, 2, make_int2(3, 4)) == make_int4(1, 2, 3, 4));
  EXPECT_TRUE(make_int4(1, make_int2(2, 3), 4) == make_int4(1, 2, 3, 4));
  EXPECT_TRUE(make_uint3(1u, make_uint2(2, 3)) == make_uint3(1, 2, 3));
  EXPECT_TRUE(make_uint4(make_uint2(1, 2), make_uint2(3, 4)) == make_uint4(1, 2, 3, 4));
  EXPECT_TRUE(make_uint4(1u, make_uint3(2, 3, 4)) == make_uint4(1, 2, 3, 4));
}

// Out-of-range and NaN components saturate as the GPU's conversion does, instead of being
// undefined (x86 gives 0x80000000, or wraps for unsigned). Volatile keeps g++ from folding.
TEST(MathTest, FloatToIntegerVectorsSaturate) {
  volatile float big = 3e9f, nan = std::numeric_limits<float>::quiet_NaN(), minus_one = -1.0f;
  EXPECT_TRUE(make_int2(make_float2(big, nan)) == make_int2(2147483647, 0));
  EXPECT_TRUE(make_int3(make_float3(-big, 2.7f, -2.7f)) == make_int3(-2147483647 - 1, 2, -2));
  EXPECT_TRUE(make_uint2(make_float2(minus_one, big)) == make_uint2(0, 3000000000u));
  EXPECT_TRUE(make_uint4(make_float4(-big, 5e9f, nan, 1.5f)) == make_uint4(0, 0xFFFFFFFFu, 0, 1));
}

TEST(MathTest, OptixScalarNames) {
  const optix::uint u = 3;
  const optix::ushort s = 4;
  EXPECT_EQ(u + s, 7u);
  EXPECT_EQ(optix::float_as_int(1.0f), 0x3f800000);
  EXPECT_EQ(optix::int_as_float(0x3f800000), 1.0f);
}

// The SDK's triangle test: distance, the weights of p1 and p2, and the unnormalized normal.
TEST(MathTest, IntersectTriangle) {
  const float3 p0 = make_float3(0.f, 0.f, 0.f), p1 = make_float3(2.f, 0.f, 0.f),
               p2 = make_float3(0.f, 2.f, 0.f);
  optix::Ray down =
      optix::make_Ray(make_float3(0.5f, 0.5f, 1.f), make_float3(0.f, 0.f, -1.f), 0, 0.f, 10.f);
  float3 n;
  float t, beta, gamma;
  ASSERT_TRUE(intersect_triangle(down, p0, p1, p2, n, t, beta, gamma));  // found through ADL
  EXPECT_FLOAT_EQ(t, 1.f);
  EXPECT_FLOAT_EQ(beta, 0.25f);
  EXPECT_FLOAT_EQ(gamma, 0.25f);
  EXPECT_FLOAT3_EQ(n, 0.f, 0.f, 4.f);
  // From below the same weights; outside the triangle, beyond tmax, or along its plane: no hit.
  optix::Ray up =
      optix::make_Ray(make_float3(0.5f, 1.0f, -2.f), make_float3(0.f, 0.f, 1.f), 0, 0.f, 10.f);
  ASSERT_TRUE(optix::intersect_triangle_branchless(up, p0, p1, p2, n, t, beta, gamma));
  EXPECT_FLOAT_EQ(t, 2.f);
  EXPECT_FLOAT_EQ(beta, 0.25f);
  EXPECT_FLOAT_EQ(gamma, 0.5f);
  optix::Ray outside = down;
  outside.origin = make_float3(1.5f, 1.5f, 1.f);
  EXPECT_FALSE(optix::intersect_triangle_earlyexit(outside, p0, p1, p2, n, t, beta, gamma));
  optix::Ray short_ray = down;
  short_ray.tmax = 0.5f;
  EXPECT_FALSE(intersect_triangle(short_ray, p0, p1, p2, n, t, beta, gamma));
  optix::Ray along =
      optix::make_Ray(make_float3(-1.f, 0.5f, 0.f), make_float3(1.f, 0.f, 0.f), 0, 0.f, 10.f);
  EXPECT_FALSE(intersect_triangle(along, p0, p1, p2, n, t, beta, gamma));
}

TEST(MathTest, SamplingAndOrthonormalBasis) {
  for (float u1 : {0.f, 0.3f, 0.99f}) {
    for (float u2 : {0.f, 0.25f, 0.7f}) {
      float3 p;
      cosine_sample_hemisphere(u1, u2, p);
      EXPECT_NEAR(length(p), 1.f, 1e-5f);
      EXPECT_GE(p.z, 0.f);
      EXPECT_NEAR(p.z, std::sqrt(1.f - u1), 1e-5f);
      const float2 d = square_to_disk(make_float2(u1, u2));
      EXPECT_LE(length(d), 1.f + 1e-5f);
    }
  }
  EXPECT_FLOAT2_EQ(square_to_disk(make_float2(0.5f, 0.5f)), 0.f, 0.f);
  const float2 corner = square_to_disk(make_float2(1.f, 0.5f));  // edge midpoint -> circle
  EXPECT_NEAR(corner.x, 1.f, 1e-6f);
  EXPECT_NEAR(corner.y, 0.f, 1e-6f);
  for (float3 normal : {make_float3(0.f, 0.f, 1.f), normalize(make_float3(1.f, 2.f, 0.5f)),
                        make_float3(-1.f, 0.f, 0.f)}) {
    const optix::Onb onb(normal);
    EXPECT_NEAR(dot(onb.m_tangent, onb.m_binormal), 0.f, 1e-6f);
    EXPECT_NEAR(dot(onb.m_tangent, onb.m_normal), 0.f, 1e-6f);
    EXPECT_NEAR(dot(onb.m_binormal, onb.m_normal), 0.f, 1e-6f);
    EXPECT_NEAR(length(onb.m_tangent), 1.f, 1e-6f);
    float3 z = make_float3(0.f, 0.f, 1.f);
    onb.inverse_transform(z);
    EXPECT_NEAR(length(z - normal), 0.f, 1e-6f);
  }
}

// OptiX 6.5's color ramp: blue at 0, green at 0.5, red at 1, cyan and yellow between.
TEST(MathTest, Temperature) {
  EXPECT_FLOAT3_EQ(optix::temperature(0.0f), 0.0f, 0.0f, 0.5f);
  EXPECT_FLOAT3_EQ(optix::temperature(0.25f), 0.0f, 0.5f, 1.0f);
  EXPECT_FLOAT3_EQ(optix::temperature(0.5f), 0.0f, 1.0f, 0.0f);
  EXPECT_FLOAT3_EQ(optix::temperature(0.75f), 1.0f, 1.0f, 0.0f);
  EXPECT_FLOAT3_EQ(optix::temperature(1.0f), 1.0f, 0.0f, 0.0f);
}

// Azimuth in [0, 2 pi) from +x toward +y, elevation from the xy plane, radius.
TEST(MathTest, CartToPol) {
  EXPECT_FLOAT3_EQ(optix::cart_to_pol(make_float3(2.0f, 0.0f, 0.0f)), 0.0f, 0.0f, 2.0f);
  EXPECT_FLOAT3_EQ(optix::cart_to_pol(make_float3(-1.0f, 0.0f, 0.0f)), M_PIf, 0.0f, 1.0f);
  EXPECT_FLOAT3_EQ(cart_to_pol(make_float3(0.0f, -1.0f, 0.0f)), 1.5f * M_PIf, 0.0f, 1.0f);
  EXPECT_FLOAT3_EQ(cart_to_pol(make_float3(0.0f, 0.0f, 3.0f)), 0.0f, M_PI_2f, 3.0f);
  EXPECT_FLOAT3_EQ(cart_to_pol(make_float3(0.0f, 0.0f, -3.0f)), 0.0f, -M_PI_2f, 3.0f);
  const float3 p = cart_to_pol(make_float3(1.0f, 1.0f, std::sqrt(2.0f)));
  EXPECT_FLOAT3_NEAR(p, M_PI_4f, M_PI_4f, 2.0f, kEps);
}

// OptiX 6's 64-bit vector families: arithmetic, min/max/clamp, comparisons, conversions,
// component access.
TEST(MathTest, LongLongVectors) {
  const longlong3 a = make_longlong3(-5, 10, 1ll << 40);
  EXPECT_EQ((a + make_longlong3(1)).z, (1ll << 40) + 1);
  EXPECT_EQ((-a).x, 5);
  EXPECT_EQ((a * 2ll).y, 20);
  EXPECT_EQ((a / 5ll).x, -1);
  EXPECT_EQ(clamp(a, -2ll, 4ll).x, -2);
  EXPECT_EQ(clamp(a, -2ll, 4ll).z, 4);
  EXPECT_EQ(min(a, make_longlong3(0)).y, 0);
  EXPECT_EQ(max(a, make_longlong3(0)).x, 0);
  EXPECT_TRUE(a == make_longlong3(make_longlong2(-5, 10), 1ll << 40));
  EXPECT_TRUE(a != make_longlong3(0));
  EXPECT_EQ(make_longlong2(make_float2(2.7f, -1e30f)).y, std::numeric_limits<long long>::min());
  EXPECT_EQ(make_longlong4(make_longlong2(1, 2), make_longlong2(3, 4)).w, 4);
  EXPECT_EQ(make_longlong2(a).y, 10);
  const ulonglong4 u = make_ulonglong4(1ull, 2ull, 3ull, ~0ull);
  EXPECT_EQ(getByIndex(u, 3), ~0ull);
  ulonglong4 v = u;
  setByIndex(v, 0, 9ull);
  EXPECT_EQ(v.x, 9ull);
  EXPECT_EQ((u - make_ulonglong4(1ull)).x, 0ull);
  EXPECT_EQ(min(u, make_ulonglong4(2ull)).w, 2ull);
  EXPECT_EQ(optix::clamp(7ull, 1ull, 5ull), 5ull);
  EXPECT_EQ(optix::make_ulonglong3(make_float3(3.9f, -1.0f, 0.0f)).x, 3ull);
  EXPECT_EQ(optix::make_ulonglong3(make_float3(3.9f, -1.0f, 0.0f)).y, 0ull);  // saturates
  longlong1 one = make_longlong1(4);
  setByIndex(one, 0, getByIndex(one, 0) + 1);
  EXPECT_EQ(one.x, 5);
}

TEST(MathNamesTest, QualifiedOptixNamesAreTheGlobalFunctions) {
  const float3 v = make_float3(3.0f, 0.0f, 4.0f);
  EXPECT_FLOAT3_EQ(optix::normalize(v), 0.6f, 0.0f, 0.8f);
  EXPECT_FLOAT_EQ(optix::dot(v, v), 25.0f);
  EXPECT_FLOAT_EQ(optix::length(v), 5.0f);
  EXPECT_FLOAT3_EQ(optix::make_float3(make_float4(1.0f, 2.0f, 3.0f, 4.0f)), 1.0f, 2.0f, 3.0f);
  EXPECT_FLOAT_EQ(optix::clamp(2.0f, 0.0f, 1.0f), 1.0f);
  EXPECT_FLOAT_EQ(optix::fmaxf(1.0f, 2.0f), 2.0f);  // The scalar C function, re-exported too.
  EXPECT_FLOAT_EQ(optix::fmaxf(v), 4.0f);
  EXPECT_EQ(optix::max(3, 4), 4);
  EXPECT_FLOAT3_EQ(optix::operator+(v, v), 6.0f, 0.0f, 8.0f);
  // Same entity: taking the address through either name gives one function.
  float (*global_dot)(const float3&, const float3&) = &::dot;
  float (*optix_dot)(const float3&, const float3&) = &optix::dot;
  EXPECT_EQ(global_dot, optix_dot);
}

TEST(MathNamesTest, UsingDirectiveIsNotAmbiguous) {
  using namespace optix;
  const float3 a = make_float3(1.0f, 0.0f, 0.0f);
  const float3 b = make_float3(0.0f, 1.0f, 0.0f);
  EXPECT_FLOAT3_EQ(normalize(cross(a, b)), 0.0f, 0.0f, 1.0f);
  EXPECT_FLOAT_EQ(clamp(dot(a + b, a), 0.0f, 0.5f), 0.5f);
  EXPECT_FLOAT3_EQ(fminf(a, b), 0.0f, 0.0f, 0.0f);
  EXPECT_FLOAT_EQ(fminf(2.0f, 1.0f), 1.0f);
  EXPECT_EQ(min(2, 1), 1);
  EXPECT_FLOAT_EQ(lerp(0.0f, 2.0f, 0.5f), 1.0f);
  EXPECT_FLOAT3_EQ(floor(make_float3(1.5f)), 1.0f, 1.0f, 1.0f);
  EXPECT_FLOAT_EQ(floor(1.5f), 1.0f);
  EXPECT_FLOAT_EQ(luminance(make_float3(1.0f)), 1.0f);
}

}  // namespace

// A namespace that declares its own normalize/dot hides the global ones from ordinary lookup;
// argument-dependent lookup on the global float3 must still find the vector versions.
namespace shadowing {
float normalize(float x) { return x; }
float dot(float a, float b) { return a * b; }

TEST(MathNamesTest, ArgumentDependentLookupFindsGlobalFunctions) {
  const float3 v = make_float3(0.0f, 2.0f, 0.0f);
  EXPECT_FLOAT3_EQ(normalize(v), 0.0f, 1.0f, 0.0f);
  EXPECT_FLOAT_EQ(dot(v, v), 4.0f);
  EXPECT_FLOAT_EQ(dot(2.0f, 3.0f), 6.0f);
  EXPECT_FLOAT_EQ(normalize(5.0f), 5.0f);
  EXPECT_FLOAT3_EQ(v * 2.0f + v, 0.0f, 6.0f, 0.0f);
}
}  // namespace shadowing

namespace saturate_test {
// A program's own saturate, as many define: preferred over the header's function template.
float saturate(float x) { return x < 0.5f ? 0.25f : 0.75f; }
float Own(float x) { return saturate(x); }
}  // namespace saturate_test

TEST(MathTest, SaturateClampsToTheUnitIntervalAndYieldsToAProgramsOwn) {
  EXPECT_EQ(saturate(-2.0f), 0.0f);
  EXPECT_EQ(saturate(0.3f), 0.3f);
  EXPECT_EQ(saturate(7.0f), 1.0f);
  const float3 v = saturate(make_float3(-1.0f, 0.5f, 3.0f));
  EXPECT_EQ(v.x, 0.0f);
  EXPECT_EQ(v.y, 0.5f);
  EXPECT_EQ(v.z, 1.0f);
  const float4 w = optix::saturate(make_float4(2.0f, -0.5f, 0.25f, 1.0f));
  EXPECT_EQ(w.x, 1.0f);
  EXPECT_EQ(w.y, 0.0f);
  EXPECT_EQ(w.z, 0.25f);
  EXPECT_EQ(w.w, 1.0f);
  EXPECT_EQ(saturate_test::Own(0.9f), 0.75f);
}

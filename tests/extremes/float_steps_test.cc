// NextFloatUp/NextFloatDown (worker/core/float_steps.h) step exactly as std::nextafter towards an
// infinity, over every special value and a sweep of bit patterns.
#include "float_steps.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <vector>

namespace tessera::worker {
namespace {

uint32_t Bits(float v) {
  uint32_t b;
  std::memcpy(&b, &v, sizeof(b));
  return b;
}

void ExpectLikeNextafter(float v) {
  constexpr float kInf = std::numeric_limits<float>::infinity();
  const float up = NextFloatUp(v), down = NextFloatDown(v);
  if (std::isnan(v)) {
    EXPECT_TRUE(std::isnan(up));
    EXPECT_TRUE(std::isnan(down));
    return;
  }
  EXPECT_EQ(Bits(up), Bits(std::nextafter(v, kInf))) << v;
  EXPECT_EQ(Bits(down), Bits(std::nextafter(v, -kInf))) << v;
}

TEST(FloatStepsTest, SpecialValues) {
  constexpr float kInf = std::numeric_limits<float>::infinity();
  const float values[] = {0.f,
                          -0.f,
                          std::numeric_limits<float>::denorm_min(),
                          -std::numeric_limits<float>::denorm_min(),
                          std::numeric_limits<float>::min(),
                          -std::numeric_limits<float>::min(),
                          std::numeric_limits<float>::max(),
                          -std::numeric_limits<float>::max(),
                          kInf,
                          -kInf,
                          std::numeric_limits<float>::quiet_NaN(),
                          1.f,
                          -1.f};
  for (const float v : values) ExpectLikeNextafter(v);
}

TEST(FloatStepsTest, BitPatternSweep) {
  for (uint64_t b = 0; b <= 0xffffffffull; b += 0x10001ull) {
    float v;
    const auto bits = static_cast<uint32_t>(b);
    std::memcpy(&v, &bits, sizeof(v));
    ExpectLikeNextafter(v);
  }
}

}  // namespace
}  // namespace tessera::worker

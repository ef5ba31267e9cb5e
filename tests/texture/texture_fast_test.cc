// The fast bilinear RGBA8 lookup (tessera/detail/texture_fast.h) against the general sampling
// path: which views it takes, and the same bits for every coordinate, special values included.
#include "tessera/detail/texture_fast.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "linear_view.h"
#include "tessera/detail/texture_sampling.h"
#include "tessera/rt.h"

namespace {

using tessera::texture::FastKind;
using tessera::texture::kFastBilinearRgba8Clamp;
using tessera::texture::kFastBilinearRgba8Repeat;
using tessera::texture::kFastNone;
using tessera::texture::Sample2D;
using tessera::texture::Sample2DLod;

// What tex2D of an LDR image reads: RGBA8 as normalized floats, bilinear, normalized coordinates.
TesseraTextureView Rgba8View(const std::vector<uint8_t>& texels, unsigned w, unsigned h,
                             RTwrapmode wrap) {
  return tessera::testing::LinearView(texels.data(), w, h, 1, 2, RT_FORMAT_UNSIGNED_BYTE4, 4,
                                      RT_TEXTURE_READ_NORMALIZED_FLOAT, wrap);
}

TEST(TextureFastKind, TakesOnlyTheLookupItComputes) {
  const std::vector<uint8_t> t(4 * 4 * 4, 7);
  EXPECT_EQ(FastKind(Rgba8View(t, 4, 4, RT_WRAP_CLAMP_TO_EDGE)), kFastBilinearRgba8Clamp);
  EXPECT_EQ(FastKind(Rgba8View(t, 4, 4, RT_WRAP_REPEAT)), kFastBilinearRgba8Repeat);
  const auto changed = [&](auto change) {
    TesseraTextureView v = Rgba8View(t, 4, 4, RT_WRAP_CLAMP_TO_EDGE);
    change(v);
    return FastKind(v);
  };
  EXPECT_EQ(changed([](TesseraTextureView& v) { v.wrap[1] = RT_WRAP_REPEAT; }), kFastNone);
  EXPECT_EQ(changed([](TesseraTextureView& v) { v.wrap[0] = v.wrap[1] = RT_WRAP_MIRROR; }),
            kFastNone);
  EXPECT_EQ(changed([](TesseraTextureView& v) { v.wrap[0] = v.wrap[1] = RT_WRAP_CLAMP_TO_BORDER; }),
            kFastNone);
  EXPECT_EQ(changed([](TesseraTextureView& v) { v.mag_filter = RT_FILTER_NEAREST; }), kFastNone);
  EXPECT_EQ(changed([](TesseraTextureView& v) { v.min_filter = RT_FILTER_NEAREST; }), kFastNone);
  EXPECT_EQ(changed([](TesseraTextureView& v) { v.read_mode = RT_TEXTURE_READ_ELEMENT_TYPE; }),
            kFastNone);
  EXPECT_EQ(changed([](TesseraTextureView& v) { v.read_mode = 3; }), kFastNone);  // sRGB
  EXPECT_EQ(changed([](TesseraTextureView& v) { v.index_mode = RT_TEXTURE_INDEX_ARRAY_INDEX; }),
            kFastNone);
  EXPECT_EQ(changed([](TesseraTextureView& v) { v.format = RT_FORMAT_BYTE4; }), kFastNone);
  EXPECT_EQ(changed([](TesseraTextureView& v) { v.layered = 1; }), kFastNone);
  EXPECT_EQ(changed([](TesseraTextureView& v) { v.dimensionality = 3; }), kFastNone);
  EXPECT_EQ(changed([](TesseraTextureView& v) {
              v.level_count = 2;
              v.mip_filter = RT_FILTER_LINEAR;
            }),
            kFastNone);
  EXPECT_EQ(changed([](TesseraTextureView& v) { v.levels[0].data = nullptr; }), kFastNone);
  // Several levels read with mip filtering off sample level 0 alone: still the fast lookup.
  EXPECT_EQ(changed([](TesseraTextureView& v) { v.level_count = 2; }), kFastBilinearRgba8Clamp);
}

// Every coordinate class: random ones in and around [0, 1], texel centres and edges (where the
// weights' rounding matters), and values no image coordinate should be (NaN, infinities, huge,
// tiny, just below 1).
TEST(TextureFastPath, GivesTheGeneralPathsBits) {
  std::mt19937 rng(2411);
  const float kSpecials[] = {0.f,
                             -0.f,
                             1.f,
                             -1.f,
                             0.5f,
                             1e-30f,
                             1e9f,
                             -1e9f,
                             3e38f,
                             8388607.5f,
                             0.99999994f,
                             1.f / 512.f,
                             -1.f / 512,
                             2.5e-8f,
                             std::numeric_limits<float>::infinity(),
                             -std::numeric_limits<float>::infinity(),
                             std::numeric_limits<float>::quiet_NaN()};
  constexpr int kSpecialCount = sizeof(kSpecials) / sizeof(kSpecials[0]);
  for (unsigned w : {1u, 2u, 3u, 7u, 64u, 1000u}) {
    for (unsigned h : {1u, 5u, 33u}) {
      std::vector<uint8_t> texels(size_t{w} * h * 4);
      for (uint8_t& b : texels) b = static_cast<uint8_t>(rng());
      for (RTwrapmode wrap : {RT_WRAP_CLAMP_TO_EDGE, RT_WRAP_REPEAT}) {
        const TesseraTextureView general = Rgba8View(texels, w, h, wrap);
        TesseraTextureView fast = general;
        fast.fast = FastKind(general);
        ASSERT_NE(fast.fast, kFastNone);
        std::uniform_real_distribution<float> around(-3.f, 3.f);
        int wrong = 0;
        for (int k = 0; k < 20000; ++k) {
          float x, y;
          if (k < kSpecialCount * kSpecialCount) {
            x = kSpecials[k % kSpecialCount];
            y = kSpecials[k / kSpecialCount];
          } else if (k % 3 == 0) {  // quarter-texel steps: centres, edges and midpoints
            x = static_cast<float>(rng() % (8 * w)) / static_cast<float>(4 * w) - 0.5f;
            y = static_cast<float>(rng() % (8 * h)) / static_cast<float>(4 * h) - 0.5f;
          } else {
            x = around(rng);
            y = around(rng);
          }
          const float4 want = Sample2D<float4>(general, x, y);
          const float4 got = Sample2D<float4>(fast, x, y);
          const float4 got_lod = Sample2DLod<float4>(fast, x, y, 3.5f);  // one level: same
          if (std::memcmp(&want, &got, sizeof want) != 0 ||
              std::memcmp(&want, &got_lod, sizeof want) != 0) {
            if (++wrong <= 3) {
              ADD_FAILURE() << w << "x" << h << " wrap " << wrap << " at (" << x << ", " << y
                            << "): general " << want.x << " " << want.y << " " << want.z << " "
                            << want.w << ", fast " << got.x << " " << got.y << " " << got.z << " "
                            << got.w;
            }
          }
        }
        EXPECT_EQ(wrong, 0) << w << "x" << h << " wrap " << wrap;
      }
    }
  }
}

}  // namespace

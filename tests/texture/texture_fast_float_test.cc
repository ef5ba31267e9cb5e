// The fast linear float lookup (tessera/detail/texture_fast_float.h) against the general sampling
// path: which views it takes, and the same bits for every coordinate and texel value, special
// values of both included.
#include "tessera/detail/texture_fast_float.h"

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

using tessera::texture::FastLinearKind;
using tessera::texture::MarkFastLookups;
using tessera::texture::Sample2D;
using tessera::texture::Sample2DLod;
using tessera::texture::Sample3D;

constexpr float kInf = std::numeric_limits<float>::infinity();

RTformat FloatFormat(unsigned channels) {
  return channels == 1 ? RT_FORMAT_FLOAT : channels == 2 ? RT_FORMAT_FLOAT2 : RT_FORMAT_FLOAT4;
}

// A float texture as an HDR image or a noise volume is read: linear, normalized coordinates.
TesseraTextureView FloatView(const std::vector<float>& texels, unsigned channels, unsigned w,
                             unsigned h, unsigned d, unsigned dims, const RTwrapmode wrap[3]) {
  TesseraTextureView v =
      tessera::testing::LinearView(texels.data(), w, h, d, dims, FloatFormat(channels),
                                   4 * channels, RT_TEXTURE_READ_NORMALIZED_FLOAT, wrap[0]);
  for (int a = 0; a < 3; ++a) v.wrap[a] = wrap[a];
  return v;
}

TEST(TextureFastLinearKind, TakesOnlyTheLookupItComputes) {
  const std::vector<float> t(4 * 4 * 4 * 4, 0.25f);
  const RTwrapmode mixed[3] = {RT_WRAP_REPEAT, RT_WRAP_CLAMP_TO_EDGE, RT_WRAP_REPEAT};
  EXPECT_EQ(FastLinearKind(FloatView(t, 4, 4, 4, 1, 2, mixed)), 0x24u);
  EXPECT_EQ(FastLinearKind(FloatView(t, 1, 4, 4, 4, 3, mixed)), 0x31u);
  EXPECT_EQ(FastLinearKind(FloatView(t, 2, 4, 4, 1, 2, mixed)), 0x22u);
  const auto changed = [&](auto change) {
    TesseraTextureView v = FloatView(t, 4, 4, 4, 1, 2, mixed);
    change(v);
    return FastLinearKind(v);
  };
  EXPECT_EQ(changed([](TesseraTextureView& v) { v.wrap[1] = RT_WRAP_MIRROR; }), 0u);
  EXPECT_EQ(changed([](TesseraTextureView& v) { v.wrap[0] = RT_WRAP_CLAMP_TO_BORDER; }), 0u);
  // The third axis of a 2D texture is never read.
  EXPECT_EQ(changed([](TesseraTextureView& v) { v.wrap[2] = RT_WRAP_MIRROR; }), 0x24u);
  EXPECT_EQ(changed([](TesseraTextureView& v) { v.mag_filter = RT_FILTER_NEAREST; }), 0u);
  EXPECT_EQ(changed([](TesseraTextureView& v) { v.min_filter = RT_FILTER_NEAREST; }), 0u);
  EXPECT_EQ(changed([](TesseraTextureView& v) { v.index_mode = RT_TEXTURE_INDEX_ARRAY_INDEX; }),
            0u);
  EXPECT_EQ(changed([](TesseraTextureView& v) {
              v.format = RT_FORMAT_FLOAT3;
              v.element_size = 12;
            }),
            0u);
  EXPECT_EQ(changed([](TesseraTextureView& v) {
              v.format = RT_FORMAT_HALF4;
              v.element_size = 8;
            }),
            0u);
  EXPECT_EQ(changed([](TesseraTextureView& v) { v.element_size = 8; }), 0u);
  EXPECT_EQ(changed([](TesseraTextureView& v) { v.layered = 1; }), 0u);
  EXPECT_EQ(changed([](TesseraTextureView& v) { v.cubemap = 1; }), 0u);
  EXPECT_EQ(changed([](TesseraTextureView& v) { v.dimensionality = 1; }), 0u);
  EXPECT_EQ(changed([](TesseraTextureView& v) {
              v.level_count = 2;
              v.mip_filter = RT_FILTER_LINEAR;
            }),
            0u);
  EXPECT_EQ(changed([](TesseraTextureView& v) { v.levels[0].data = nullptr; }), 0u);
  // Several levels read with mip filtering off sample level 0 alone: still the fast lookup.
  EXPECT_EQ(changed([](TesseraTextureView& v) { v.level_count = 2; }), 0x24u);
  // Float texels read the same in every read mode.
  EXPECT_EQ(changed([](TesseraTextureView& v) { v.read_mode = RT_TEXTURE_READ_ELEMENT_TYPE; }),
            0x24u);
}

// Texel values: mostly ordinary, some special (a zero weight must keep them out).
std::vector<float> Texels(size_t count, std::mt19937& rng) {
  const float kSpecials[] = {kInf,  -kInf, std::numeric_limits<float>::quiet_NaN(), -0.f, 1e-42f,
                             3e38f, -3e38f};
  std::uniform_real_distribution<float> value(-4.f, 4.f);
  std::vector<float> t(count);
  for (float& f : t) f = rng() % 16 == 0 ? kSpecials[rng() % 7] : value(rng);
  return t;
}

float Coordinate(int k, int axis, unsigned n, std::mt19937& rng) {
  static const float kSpecials[] = {
      0.f,         -0.f,    1.f,   -1.f,  0.5f,
      1e-30f,      1e9f,    -1e9f, 3e38f, 8388607.5f,
      0.99999994f, 2.5e-8f, kInf,  -kInf, std::numeric_limits<float>::quiet_NaN()};
  constexpr int kCount = sizeof(kSpecials) / sizeof(kSpecials[0]);
  if (k < kCount * kCount) return kSpecials[axis == 0 ? k % kCount : (k / kCount + axis) % kCount];
  if (k % 3 == 0) {  // quarter-texel steps: centres, edges and midpoints
    return static_cast<float>(rng() % (8 * n)) / static_cast<float>(4 * n) - 0.5f;
  }
  return std::uniform_real_distribution<float>(-3.f, 3.f)(rng);
}

bool SameBits(const float4& a, const float4& b) { return std::memcmp(&a, &b, sizeof a) == 0; }

TEST(TextureFastLinearPath, GivesTheGeneralPathsBits) {
  std::mt19937 rng(2911);
  const RTwrapmode kWraps[][3] = {
      {RT_WRAP_CLAMP_TO_EDGE, RT_WRAP_CLAMP_TO_EDGE, RT_WRAP_CLAMP_TO_EDGE},
      {RT_WRAP_REPEAT, RT_WRAP_REPEAT, RT_WRAP_REPEAT},
      {RT_WRAP_REPEAT, RT_WRAP_CLAMP_TO_EDGE, RT_WRAP_REPEAT},
      {RT_WRAP_CLAMP_TO_EDGE, RT_WRAP_REPEAT, RT_WRAP_CLAMP_TO_EDGE}};
  const unsigned kSizes[][3] = {{1, 1, 1}, {2, 3, 2}, {7, 5, 3}, {64, 33, 9}, {1000, 2, 1}};
  for (unsigned dims : {2u, 3u}) {
    for (unsigned channels : {1u, 2u, 4u}) {
      for (const auto& size : kSizes) {
        const unsigned depth = dims == 3 ? size[2] : 1;
        const std::vector<float> texels = Texels(size_t{size[0]} * size[1] * depth * channels, rng);
        for (const auto& wrap : kWraps) {
          const TesseraTextureView general =
              FloatView(texels, channels, size[0], size[1], depth, dims, wrap);
          TesseraTextureView fast = general;
          MarkFastLookups(fast);
          ASSERT_EQ(fast.fast_linear, (dims << 4) | channels);
          ASSERT_EQ(general.fast_linear, 0u);
          int wrong = 0;
          for (int k = 0; k < 6000; ++k) {
            const float x = Coordinate(k, 0, size[0], rng), y = Coordinate(k, 1, size[1], rng),
                        z = Coordinate(k, 2, depth, rng);
            float4 want, got, got_lod{};
            if (dims == 2) {
              want = Sample2D<float4>(general, x, y);
              got = Sample2D<float4>(fast, x, y);
              got_lod = Sample2DLod<float4>(fast, x, y, 3.5f);  // one level: the same
            } else {
              want = Sample3D<float4>(general, x, y, z);
              got = got_lod = Sample3D<float4>(fast, x, y, z);
            }
            // A one-channel program's result is the first channel of the same lookup.
            const float one =
                dims == 2 ? Sample2D<float>(fast, x, y) : Sample3D<float>(fast, x, y, z);
            if (!SameBits(want, got) || !SameBits(want, got_lod) ||
                std::memcmp(&one, &want.x, sizeof one) != 0) {
              if (++wrong <= 3) {
                ADD_FAILURE() << dims << "D " << channels << " channels " << size[0] << "x"
                              << size[1] << "x" << depth << " wraps " << wrap[0] << wrap[1]
                              << wrap[2] << " at (" << x << ", " << y << ", " << z << "): general "
                              << want.x << " " << want.y << " " << want.z << " " << want.w
                              << ", fast " << got.x << " " << got.y << " " << got.z << " " << got.w;
              }
            }
          }
          EXPECT_EQ(wrong, 0) << dims << "D " << channels << " channels " << size[0] << "x"
                              << size[1] << "x" << depth;
        }
      }
    }
  }
}

}  // namespace

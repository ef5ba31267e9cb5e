// The texture sampling functions of tessera/detail/texture_sampling.h against the arithmetic of the
// CUDA Programming Guide's "Texture Fetching" appendix, on views built by hand over small arrays.
#include "tessera/detail/texture_sampling.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "tessera/rt.h"

namespace {

using tessera::texture::Fetch1D;
using tessera::texture::Fetch2D;
using tessera::texture::Fetch3D;
using tessera::texture::Gather2D;
using tessera::texture::Sample1D;
using tessera::texture::Sample1DGrad;
using tessera::texture::Sample1DLayered;
using tessera::texture::Sample1DLod;
using tessera::texture::Sample2D;
using tessera::texture::Sample2DGrad;
using tessera::texture::Sample2DLayered;
using tessera::texture::Sample2DLod;
using tessera::texture::Sample3D;
using tessera::texture::Sample3DLod;
using tessera::texture::SampleCubemap;
using tessera::texture::SampleCubemapLayered;

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

// One level, array-index coordinates, clamp, nearest, element type, no mipmaps: each test
// changes what it is about.
TesseraTextureView View(RTformat format, unsigned element_size, const void* data, unsigned width,
                        unsigned height = 1, unsigned depth = 1) {
  TesseraTextureView v{};
  v.levels[0] = {data, width, height, depth, 0};
  v.level_count = 1;
  v.dimensionality = depth > 1 ? 3 : (height > 1 ? 2 : 1);
  v.format = format;
  v.element_size = element_size;
  for (unsigned& w : v.wrap) w = RT_WRAP_CLAMP_TO_EDGE;
  v.min_filter = v.mag_filter = RT_FILTER_NEAREST;
  v.mip_filter = RT_FILTER_NONE;
  v.read_mode = RT_TEXTURE_READ_ELEMENT_TYPE;
  v.index_mode = RT_TEXTURE_INDEX_ARRAY_INDEX;
  v.max_anisotropy = 1.f;
  v.mip_level_clamp[0] = 0.f;
  v.mip_level_clamp[1] = 1000.f;
  return v;
}

TesseraTextureView FloatView(const std::vector<float>& texels, unsigned width, unsigned height = 1,
                             unsigned depth = 1) {
  return View(RT_FORMAT_FLOAT, sizeof(float), texels.data(), width, height, depth);
}

void SetFilter(TesseraTextureView* v, RTfiltermode filter) {
  v->min_filter = v->mag_filter = filter;
}
void SetWrap(TesseraTextureView* v, RTwrapmode wrap) {
  for (unsigned& w : v->wrap) w = wrap;
}

// ---- Wrap modes with nearest filtering -------------------------------------------------------

TEST(TextureWrap, NearestNormalizedAtAndBeyondEdges) {
  const std::vector<float> t = {10, 20, 30, 40};
  TesseraTextureView v = FloatView(t, 4);
  v.index_mode = RT_TEXTURE_INDEX_NORMALIZED_COORDINATES;

  SetWrap(&v, RT_WRAP_CLAMP_TO_EDGE);
  EXPECT_EQ(Sample1D<float>(v, -0.5f), 10.f);
  EXPECT_EQ(Sample1D<float>(v, 0.f), 10.f);
  EXPECT_EQ(Sample1D<float>(v, 0.2499f), 10.f);
  EXPECT_EQ(Sample1D<float>(v, 0.25f), 20.f);
  EXPECT_EQ(Sample1D<float>(v, 0.999f), 40.f);
  EXPECT_EQ(Sample1D<float>(v, 1.f), 40.f);
  EXPECT_EQ(Sample1D<float>(v, 7.f), 40.f);

  SetWrap(&v, RT_WRAP_CLAMP_TO_BORDER);
  EXPECT_EQ(Sample1D<float>(v, -0.01f), 0.f);
  EXPECT_EQ(Sample1D<float>(v, 0.f), 10.f);
  EXPECT_EQ(Sample1D<float>(v, 0.99f), 40.f);
  EXPECT_EQ(Sample1D<float>(v, 1.f), 0.f);
  EXPECT_EQ(Sample1D<float>(v, 3.f), 0.f);

  // Repeat: x is replaced by frac(x).
  SetWrap(&v, RT_WRAP_REPEAT);
  EXPECT_EQ(Sample1D<float>(v, 1.1f), 10.f);
  EXPECT_EQ(Sample1D<float>(v, -0.1f), 40.f);  // frac = 0.9
  EXPECT_EQ(Sample1D<float>(v, 2.6f), 30.f);   // frac = 0.6
  EXPECT_EQ(Sample1D<float>(v, 1.f), 10.f);
  EXPECT_EQ(Sample1D<float>(v, -1e-9f), 10.f);  // frac rounds to 1.0: texel 4 wraps to 0

  // Mirror: frac(x) where floor(x) is even, 1 - frac(x) where it is odd.
  SetWrap(&v, RT_WRAP_MIRROR);
  EXPECT_EQ(Sample1D<float>(v, 1.1f), 40.f);   // 0.9
  EXPECT_EQ(Sample1D<float>(v, -0.1f), 10.f);  // floor -1: 1 - 0.9
  EXPECT_EQ(Sample1D<float>(v, 2.3f), 20.f);   // 0.3
  EXPECT_EQ(Sample1D<float>(v, 1.f), 40.f);    // 1 - 0 = 1: the last texel
}

TEST(TextureWrap, MirrorOfNegativeCoordinates) {
  const std::vector<float> t = {10, 20, 30, 40};
  TesseraTextureView v = FloatView(t, 4);
  v.index_mode = RT_TEXTURE_INDEX_NORMALIZED_COORDINATES;
  SetWrap(&v, RT_WRAP_MIRROR);
  // -0.8: floor -1 (odd), frac 0.2, mirrored 0.8 -> texel 3.
  EXPECT_EQ(Sample1D<float>(v, -0.8f), 40.f);
  // -1.3: floor -2 (even), frac 0.7 -> texel 2.
  EXPECT_EQ(Sample1D<float>(v, -1.3f), 30.f);
}

TEST(TextureWrap, ArrayIndexTurnsRepeatAndMirrorIntoClamp) {
  const std::vector<float> t = {10, 20, 30, 40};
  for (RTwrapmode wrap : {RT_WRAP_REPEAT, RT_WRAP_MIRROR, RT_WRAP_CLAMP_TO_EDGE}) {
    TesseraTextureView v = FloatView(t, 4);
    SetWrap(&v, wrap);
    EXPECT_EQ(Sample1D<float>(v, 5.f), 40.f) << wrap;
    EXPECT_EQ(Sample1D<float>(v, -1.f), 10.f) << wrap;
    EXPECT_EQ(Sample1D<float>(v, 2.5f), 30.f) << wrap;
  }
  TesseraTextureView v = FloatView(t, 4);
  SetWrap(&v, RT_WRAP_CLAMP_TO_BORDER);
  EXPECT_EQ(Sample1D<float>(v, 4.f), 0.f);
  EXPECT_EQ(Sample1D<float>(v, -0.5f), 0.f);
  EXPECT_EQ(Sample1D<float>(v, 3.99f), 40.f);
}

TEST(TextureWrap, PerDimension) {
  // 2x2: a different wrap mode on each axis.
  const std::vector<float> t = {1, 2, 3, 4};
  TesseraTextureView v = FloatView(t, 2, 2);
  v.index_mode = RT_TEXTURE_INDEX_NORMALIZED_COORDINATES;
  v.wrap[0] = RT_WRAP_REPEAT;
  v.wrap[1] = RT_WRAP_CLAMP_TO_BORDER;
  EXPECT_EQ(Sample2D<float>(v, 1.25f, 0.75f), 3.f);  // x repeats to 0.25, y inside
  EXPECT_EQ(Sample2D<float>(v, 1.25f, 1.25f), 0.f);  // y in the border
}

// ---- Wrap modes with linear filtering --------------------------------------------------------

TEST(TextureWrap, LinearAtAndBeyondEdges) {
  const std::vector<float> t = {10, 20, 30, 40};
  TesseraTextureView v = FloatView(t, 4);
  SetFilter(&v, RT_FILTER_LINEAR);

  SetWrap(&v, RT_WRAP_CLAMP_TO_EDGE);
  EXPECT_EQ(Sample1D<float>(v, 0.25f), 10.f);  // xB = -0.25: T[-1] and T[0] are both T[0]
  EXPECT_EQ(Sample1D<float>(v, 4.f), 40.f);
  EXPECT_EQ(Sample1D<float>(v, 3.75f), 40.f);
  EXPECT_EQ(Sample1D<float>(v, 1.f), 15.f);  // halfway between texels 0 and 1
  EXPECT_EQ(Sample1D<float>(v, -100.f), 10.f);

  SetWrap(&v, RT_WRAP_CLAMP_TO_BORDER);
  EXPECT_EQ(Sample1D<float>(v, 0.25f), 7.5f);  // 0.25 * 0 + 0.75 * 10
  EXPECT_EQ(Sample1D<float>(v, 4.f), 20.f);    // 0.5 * 40 + 0.5 * 0
  EXPECT_EQ(Sample1D<float>(v, -5.f), 0.f);
  EXPECT_EQ(Sample1D<float>(v, 9.f), 0.f);

  v.index_mode = RT_TEXTURE_INDEX_NORMALIZED_COORDINATES;
  SetWrap(&v, RT_WRAP_REPEAT);
  EXPECT_EQ(Sample1D<float>(v, 0.f), 25.f);  // texels 3 and 0
  EXPECT_EQ(Sample1D<float>(v, 1.f), 25.f);
  EXPECT_EQ(Sample1D<float>(v, 0.125f), 10.f);
  SetWrap(&v, RT_WRAP_MIRROR);
  EXPECT_EQ(Sample1D<float>(v, 0.f), 10.f);  // texel -1 mirrors to 0
  EXPECT_EQ(Sample1D<float>(v, 1.f), 40.f);  // texel 4 mirrors to 3
  EXPECT_EQ(Sample1D<float>(v, 1.125f), 40.f);
}

// ---- Linear filtering arithmetic -------------------------------------------------------------

TEST(TextureLinear, WeightHasEightFractionalBits) {
  const std::vector<float> t = {0, 256};
  TesseraTextureView v = FloatView(t, 2);
  SetFilter(&v, RT_FILTER_LINEAR);
  EXPECT_EQ(Sample1D<float>(v, 0.8f), 77.f);             // alpha 0.3 -> 77/256, not 76.8
  EXPECT_EQ(Sample1D<float>(v, 0.6f), 26.f);             // 0.1 -> 25.6 -> 26
  EXPECT_EQ(Sample1D<float>(v, 1.499f), 256.f);          // 0.999 -> 255.7 -> 256: all of T[1]
  EXPECT_EQ(Sample1D<float>(v, 0.5f + 1.f / 512), 1.f);  // exactly half a step rounds up
  EXPECT_EQ(Sample1D<float>(v, 0.5f + 1.f / 1024), 0.f);
}

TEST(TextureLinear, BilinearWithQuantizedWeights) {
  const std::vector<float> t = {3, 100, -7, 1000};
  TesseraTextureView v = FloatView(t, 2, 2);
  SetFilter(&v, RT_FILTER_LINEAR);
  const double a = 77, b = 26;  // x 0.8 -> alpha 0.3, y 0.6 -> beta 0.1
  const double expected =
      ((256 - a) * (256 - b) * 3 + a * (256 - b) * 100 + (256 - a) * b * -7 + a * b * 1000) /
      65536.0;
  EXPECT_EQ(Sample2D<float>(v, 0.8f, 0.6f), static_cast<float>(expected));
  EXPECT_EQ(Sample2D<float>(v, 1.f, 1.f), (3.f + 100.f - 7.f + 1000.f) / 4.f);
}

TEST(TextureLinear, TrilinearWithQuantizedWeights) {
  std::vector<float> t(8);
  for (int i = 0; i < 8; ++i) t[i] = static_cast<float>(i * i + 1);
  TesseraTextureView v = FloatView(t, 2, 2, 2);
  SetFilter(&v, RT_FILTER_LINEAR);
  const int w[3][2] = {{179, 77}, {230, 26}, {51, 205}};  // alphas 0.3, 0.1, 0.8
  double expected = 0;
  for (int z = 0; z < 2; ++z)
    for (int y = 0; y < 2; ++y)
      for (int x = 0; x < 2; ++x)
        expected += double(w[0][x]) * w[1][y] * w[2][z] * t[z * 4 + y * 2 + x];
  EXPECT_EQ(Sample3D<float>(v, 0.8f, 0.6f, 1.3f), static_cast<float>(expected / (1 << 24)));
}

// The bilinear formula with quantized weights, written out directly for clamp and repeat, against
// the sampler over many coordinates: RGBA8 (with and without its shortcut), 16-bit, signed and
// float texels.
struct ReferenceAxis {
  int i0, i1, q;  // q: the weight of i1 in 1/256
};

ReferenceAxis ReferenceLinear(float x, int n, bool repeat) {
  float t;
  if (repeat) {
    const float f = x - std::floor(x);
    t = f * static_cast<float>(n) - 0.5f;
  } else {
    t = x * static_cast<float>(n) - 0.5f;
  }
  const float fl = std::floor(t);
  const int i = static_cast<int>(fl);
  const int q = static_cast<int>(std::floor((t - fl) * 256.f + 0.5f));
  if (repeat) return {(i % n + n) % n, ((i + 1) % n + n) % n, q};
  return {std::clamp(i, 0, n - 1), std::clamp(i + 1, 0, n - 1), q};
}

TEST(TextureLinear, MatchesTheFormulaAtRandomCoordinates) {
  constexpr int kW = 5, kH = 3;
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> byte(0, 255), word(0, 65535), sbyte(-128, 127);
  std::vector<unsigned char> u8(kW * kH * 4);
  std::vector<unsigned short> u16(kW * kH * 2);
  std::vector<signed char> s8(kW * kH * 4);
  std::vector<float> f32(kW * kH * 4);
  for (auto& c : u8) c = static_cast<unsigned char>(byte(rng));
  for (auto& c : u16) c = static_cast<unsigned short>(word(rng));
  for (auto& c : s8) c = static_cast<signed char>(sbyte(rng));
  for (auto& c : f32) c = std::ldexp(static_cast<float>(word(rng)) - 30000.f, -7);
  const std::vector<unsigned char> half_size(4, 0);

  std::uniform_real_distribution<float> coordinate(-1.5f, 2.5f);
  for (const bool repeat : {false, true}) {
    auto view = [&](RTformat format, unsigned size, const void* data) {
      TesseraTextureView v = View(format, size, data, kW, kH);
      v.index_mode = RT_TEXTURE_INDEX_NORMALIZED_COORDINATES;
      v.read_mode = RT_TEXTURE_READ_NORMALIZED_FLOAT;
      SetFilter(&v, RT_FILTER_LINEAR);
      SetWrap(&v, repeat ? RT_WRAP_REPEAT : RT_WRAP_CLAMP_TO_EDGE);
      return v;
    };
    const TesseraTextureView rgba8 = view(RT_FORMAT_UNSIGNED_BYTE4, 4, u8.data());
    TesseraTextureView rgba8_mip = rgba8;  // not the shortcut: two levels, nearest mip filter
    rgba8_mip.levels[1] = {half_size.data(), 1, 1, 1, 0};
    rgba8_mip.level_count = 2;
    rgba8_mip.mip_filter = RT_FILTER_NEAREST;
    const TesseraTextureView rg16 = view(RT_FORMAT_UNSIGNED_SHORT2, 4, u16.data());
    const TesseraTextureView snorm8 = view(RT_FORMAT_BYTE4, 4, s8.data());
    const TesseraTextureView float4v = view(RT_FORMAT_FLOAT4, 16, f32.data());
    for (int k = 0; k < 2000; ++k) {
      const float x = coordinate(rng), y = coordinate(rng);
      const ReferenceAxis ax = ReferenceLinear(x, kW, repeat), ay = ReferenceLinear(y, kH, repeat);
      const int xi[2] = {ax.i0, ax.i1}, yi[2] = {ay.i0, ay.i1};
      const int wx[2] = {256 - ax.q, ax.q}, wy[2] = {256 - ay.q, ay.q};
      auto sum = [&](auto texel, int channels, int c) {
        double s = 0;
        for (int j = 0; j < 2; ++j)
          for (int i = 0; i < 2; ++i)
            s += double(wx[i] * wy[j]) * texel((yi[j] * kW + xi[i]) * channels + c);
        return s;
      };
      SCOPED_TRACE(testing::Message() << "repeat " << repeat << " at " << x << ", " << y);
      const float4 a = Sample2D<float4>(rgba8, x, y), b = Sample2D<float4>(rgba8_mip, x, y);
      const float4 n = Sample2D<float4>(snorm8, x, y), f = Sample2D<float4>(float4v, x, y);
      const float2 w = Sample2D<float2>(rg16, x, y);
      const float got_a[4] = {a.x, a.y, a.z, a.w}, got_b[4] = {b.x, b.y, b.z, b.w};
      const float got_n[4] = {n.x, n.y, n.z, n.w}, got_f[4] = {f.x, f.y, f.z, f.w};
      const float got_w[2] = {w.x, w.y};
      for (int c = 0; c < 4; ++c) {
        const float expected_u8 =
            static_cast<float>(sum([&](int t) { return double(u8[t]); }, 4, c)) / (65536.f * 255);
        ASSERT_EQ(got_a[c], expected_u8) << c;
        ASSERT_EQ(got_b[c], expected_u8) << c;
        const double s8_sum = sum([&](int t) { return double(std::max<int>(s8[t], -127)); }, 4, c);
        ASSERT_EQ(got_n[c], static_cast<float>(s8_sum) / (65536.f * 127)) << c;
        ASSERT_EQ(got_f[c],
                  static_cast<float>(sum([&](int t) { return double(f32[t]); }, 4, c) / 65536.0))
            << c;
      }
      for (int c = 0; c < 2; ++c) {
        ASSERT_EQ(got_w[c], static_cast<float>(sum([&](int t) { return double(u16[t]); }, 2, c) /
                                               (65536.0 * 65535)))
            << c;
      }
    }
  }
}

TEST(TextureLinear, NormalizedCoordinatesScaleBySize) {
  const std::vector<float> t = {0, 256, 512, 768};
  TesseraTextureView v = FloatView(t, 4);
  v.index_mode = RT_TEXTURE_INDEX_NORMALIZED_COORDINATES;
  SetFilter(&v, RT_FILTER_LINEAR);
  EXPECT_EQ(Sample1D<float>(v, 0.2f), 77.f);  // 0.8 texels
  EXPECT_EQ(Sample1D<float>(v, 0.375f), 256.f);
}

TEST(TextureLinear, ZeroWeightIgnoresNonFiniteNeighbor) {
  const std::vector<float> t = {5, kInf};
  TesseraTextureView v = FloatView(t, 2);
  SetFilter(&v, RT_FILTER_LINEAR);
  EXPECT_EQ(Sample1D<float>(v, 0.5f), 5.f);
  EXPECT_EQ(Sample1D<float>(v, 1.f), kInf);
}

TEST(TextureLinear, IntegerElementReadsFallBackToNearest) {
  const std::vector<int> t = {10, 20};
  TesseraTextureView v = View(RT_FORMAT_INT, sizeof(int), t.data(), 2);
  SetFilter(&v, RT_FILTER_LINEAR);
  EXPECT_EQ(Sample1D<int>(v, 0.9f), 10);
  EXPECT_EQ(Sample1D<int>(v, 1.1f), 20);
  EXPECT_EQ(Sample1D<float>(v, 1.1f), 20.f);  // returned by value
}

// ---- Read modes and texel formats ------------------------------------------------------------

TEST(TextureReadMode, NormalizedUnsignedBytes) {
  const std::vector<unsigned char> t = {0, 128, 255, 77};
  TesseraTextureView v = View(RT_FORMAT_UNSIGNED_BYTE, 1, t.data(), 4);
  v.read_mode = RT_TEXTURE_READ_NORMALIZED_FLOAT;
  EXPECT_EQ(Sample1D<float>(v, 0.5f), 0.f);
  EXPECT_EQ(Sample1D<float>(v, 1.5f), 128.f / 255.f);
  EXPECT_EQ(Sample1D<float>(v, 2.5f), 1.f);
  SetFilter(&v, RT_FILTER_LINEAR);
  // alpha 77/256 between 0 and 255: exactly 77/256.
  const std::vector<unsigned char> ramp = {0, 255};
  v = View(RT_FORMAT_UNSIGNED_BYTE, 1, ramp.data(), 2);
  v.read_mode = RT_TEXTURE_READ_NORMALIZED_FLOAT;
  SetFilter(&v, RT_FILTER_LINEAR);
  EXPECT_EQ(Sample1D<float>(v, 0.8f), 77.f / 256.f);
  // Element type: the stored integers.
  v.read_mode = RT_TEXTURE_READ_ELEMENT_TYPE;
  EXPECT_EQ(Sample1D<unsigned char>(v, 1.5f), 255);
}

TEST(TextureReadMode, NormalizedSignedBytesAndShorts) {
  const std::vector<signed char> b = {-128, -127, 127, 64, -1};
  TesseraTextureView v = View(RT_FORMAT_BYTE, 1, b.data(), 5);
  v.read_mode = RT_TEXTURE_READ_NORMALIZED_FLOAT;
  EXPECT_EQ(Sample1D<float>(v, 0.5f), -1.f);  // max(-128/127, -1)
  EXPECT_EQ(Sample1D<float>(v, 1.5f), -1.f);
  EXPECT_EQ(Sample1D<float>(v, 2.5f), 1.f);
  EXPECT_EQ(Sample1D<float>(v, 3.5f), 64.f / 127.f);
  EXPECT_EQ(Sample1D<float>(v, 4.5f), -1.f / 127.f);
  // Linear between -128 (read as -1) and 127: 0.5 * -1 + 0.5 * 1.
  SetFilter(&v, RT_FILTER_LINEAR);
  EXPECT_EQ(Sample1D<float>(v, 1.f), -1.f);
  EXPECT_EQ(Sample1D<float>(v, 2.f), 0.f);

  const std::vector<short> s = {-32768, 32767, -100};
  v = View(RT_FORMAT_SHORT, 2, s.data(), 3);
  v.read_mode = RT_TEXTURE_READ_NORMALIZED_FLOAT;
  EXPECT_EQ(Sample1D<float>(v, 0.5f), -1.f);
  EXPECT_EQ(Sample1D<float>(v, 1.5f), 1.f);
  EXPECT_EQ(Sample1D<float>(v, 2.5f), -100.f / 32767.f);

  const std::vector<unsigned short> u = {65535, 1000};
  v = View(RT_FORMAT_UNSIGNED_SHORT, 2, u.data(), 2);
  v.read_mode = RT_TEXTURE_READ_NORMALIZED_FLOAT;
  EXPECT_EQ(Sample1D<float>(v, 0.5f), 1.f);
  EXPECT_EQ(Sample1D<float>(v, 1.5f), 1000.f / 65535.f);
  SetFilter(&v, RT_FILTER_LINEAR);
  EXPECT_EQ(Sample1D<float>(v, 1.f),
            static_cast<float>((128.0 * 65535 + 128.0 * 1000) / (256.0 * 65535)));
}

TEST(TextureReadMode, ThirtyTwoBitIntegersAreReturnedByValue) {
  const std::vector<unsigned> t = {7, 4000000000u};
  TesseraTextureView v = View(RT_FORMAT_UNSIGNED_INT, 4, t.data(), 2);
  v.read_mode = RT_TEXTURE_READ_NORMALIZED_FLOAT;
  EXPECT_EQ(Sample1D<float>(v, 0.5f), 7.f);
  EXPECT_EQ(Sample1D<unsigned>(v, 1.5f), 4000000000u);
}

TEST(TextureReadMode, Rgba8ElementAndNormalized) {
  const std::vector<unsigned char> t = {10, 20, 30, 40, 250, 240, 230, 220};
  TesseraTextureView v = View(RT_FORMAT_UNSIGNED_BYTE4, 4, t.data(), 2);
  const uchar4 e = Sample1D<uchar4>(v, 1.5f);
  EXPECT_EQ(e.x, 250);
  EXPECT_EQ(e.y, 240);
  EXPECT_EQ(e.z, 230);
  EXPECT_EQ(e.w, 220);
  v.read_mode = RT_TEXTURE_READ_NORMALIZED_FLOAT;
  SetFilter(&v, RT_FILTER_LINEAR);
  const float4 f = Sample1D<float4>(v, 0.8f);  // 179/256 of texel 0, 77/256 of texel 1
  EXPECT_EQ(f.x, static_cast<float>((179.0 * 10 + 77.0 * 250) / (256.0 * 255)));
  EXPECT_EQ(f.y, static_cast<float>((179.0 * 20 + 77.0 * 240) / (256.0 * 255)));
  EXPECT_EQ(f.z, static_cast<float>((179.0 * 30 + 77.0 * 230) / (256.0 * 255)));
  EXPECT_EQ(f.w, static_cast<float>((179.0 * 40 + 77.0 * 220) / (256.0 * 255)));
}

TEST(TextureReadMode, MissingChannelsReadZeroZeroOne) {
  const std::vector<float> t = {5, 6};
  TesseraTextureView v = View(RT_FORMAT_FLOAT2, 8, t.data(), 1);
  const float4 f = Sample1D<float4>(v, 0.5f);
  EXPECT_EQ(f.x, 5.f);
  EXPECT_EQ(f.y, 6.f);
  EXPECT_EQ(f.z, 0.f);
  EXPECT_EQ(f.w, 1.f);
  EXPECT_EQ(Sample1D<float>(v, 0.5f), 5.f);  // fewer components than the texel: the first
}

TEST(TextureReadMode, PackedThreeComponentTexels) {
  const std::vector<float> t = {1, 2, 3, 5, 6, 7};
  TesseraTextureView v = View(RT_FORMAT_FLOAT3, 12, t.data(), 2);
  SetFilter(&v, RT_FILTER_LINEAR);
  const float4 f = Sample1D<float4>(v, 1.f);
  EXPECT_EQ(f.x, 3.f);
  EXPECT_EQ(f.y, 4.f);
  EXPECT_EQ(f.z, 5.f);
  EXPECT_EQ(f.w, 1.f);
  const std::vector<short> s = {1, -2, 3, 4, 5, -6};
  v = View(RT_FORMAT_SHORT3, 6, s.data(), 2);
  const short3 e = Sample1D<short3>(v, 1.5f);
  EXPECT_EQ(e.x, 4);
  EXPECT_EQ(e.y, 5);
  EXPECT_EQ(e.z, -6);
}

TEST(TextureReadMode, FloatResultInIntegerTypeSaturates) {
  const std::vector<float> t = {1e20f, -3.7f, kNaN};
  TesseraTextureView v = FloatView(t, 3);
  EXPECT_EQ(Sample1D<int>(v, 0.5f), std::numeric_limits<int>::max());
  EXPECT_EQ(Sample1D<int>(v, 1.5f), -3);
  EXPECT_EQ(Sample1D<unsigned char>(v, 1.5f), 0);
  EXPECT_EQ(Sample1D<int>(v, 2.5f), 0);
}

// Every RTformat a texture can hold: its texels come back as stored (element type) and, for 8-
// and 16-bit integers, normalized.
template <typename S, int C>
void CheckFormat(RTformat format) {
  SCOPED_TRACE(testing::Message() << "format 0x" << std::hex << format);
  std::vector<S> t(2 * C);
  for (int i = 0; i < 2 * C; ++i) t[i] = static_cast<S>(i % 2 == 0 ? i + 1 : -(i + 1));
  TesseraTextureView v = View(format, sizeof(S) * C, t.data(), 2);
  const int4 e = Sample1D<int4>(v, 1.5f);
  const int got[4] = {e.x, e.y, e.z, e.w};
  for (int c = 0; c < 4; ++c) {
    EXPECT_EQ(got[c], c < C ? static_cast<int>(t[C + c]) : (c == 3 ? 1 : 0)) << c;
  }
  const float4 f = Fetch1D<float4>(v, 1);
  const float fetched[4] = {f.x, f.y, f.z, f.w};
  v.read_mode = RT_TEXTURE_READ_NORMALIZED_FLOAT;
  const float4 n = Sample1D<float4>(v, 1.5f);
  const float normalized[4] = {n.x, n.y, n.z, n.w};
  for (int c = 0; c < C; ++c) {
    EXPECT_EQ(fetched[c], static_cast<float>(t[C + c])) << c;
    float expected = static_cast<float>(t[C + c]);
    if (!std::is_same_v<S, float> && sizeof(S) <= 2) {
      expected = std::max(expected / static_cast<float>(std::numeric_limits<S>::max()), -1.f);
    }
    EXPECT_EQ(normalized[c], expected) << c;
  }
}

TEST(TextureFormat, EveryFormat) {
  CheckFormat<float, 1>(RT_FORMAT_FLOAT);
  CheckFormat<float, 2>(RT_FORMAT_FLOAT2);
  CheckFormat<float, 3>(RT_FORMAT_FLOAT3);
  CheckFormat<float, 4>(RT_FORMAT_FLOAT4);
  CheckFormat<signed char, 1>(RT_FORMAT_BYTE);
  CheckFormat<signed char, 2>(RT_FORMAT_BYTE2);
  CheckFormat<signed char, 3>(RT_FORMAT_BYTE3);
  CheckFormat<signed char, 4>(RT_FORMAT_BYTE4);
  CheckFormat<unsigned char, 1>(RT_FORMAT_UNSIGNED_BYTE);
  CheckFormat<unsigned char, 2>(RT_FORMAT_UNSIGNED_BYTE2);
  CheckFormat<unsigned char, 3>(RT_FORMAT_UNSIGNED_BYTE3);
  CheckFormat<unsigned char, 4>(RT_FORMAT_UNSIGNED_BYTE4);
  CheckFormat<short, 1>(RT_FORMAT_SHORT);
  CheckFormat<short, 2>(RT_FORMAT_SHORT2);
  CheckFormat<short, 3>(RT_FORMAT_SHORT3);
  CheckFormat<short, 4>(RT_FORMAT_SHORT4);
  CheckFormat<unsigned short, 1>(RT_FORMAT_UNSIGNED_SHORT);
  CheckFormat<unsigned short, 2>(RT_FORMAT_UNSIGNED_SHORT2);
  CheckFormat<unsigned short, 3>(RT_FORMAT_UNSIGNED_SHORT3);
  CheckFormat<unsigned short, 4>(RT_FORMAT_UNSIGNED_SHORT4);
  CheckFormat<int, 1>(RT_FORMAT_INT);
  CheckFormat<int, 2>(RT_FORMAT_INT2);
  CheckFormat<int, 3>(RT_FORMAT_INT3);
  CheckFormat<int, 4>(RT_FORMAT_INT4);
  CheckFormat<unsigned, 1>(RT_FORMAT_UNSIGNED_INT);
  CheckFormat<unsigned, 2>(RT_FORMAT_UNSIGNED_INT2);
  CheckFormat<unsigned, 3>(RT_FORMAT_UNSIGNED_INT3);
  CheckFormat<unsigned, 4>(RT_FORMAT_UNSIGNED_INT4);
}

TEST(TextureFormat, HalfFloats) {
  // 1, -2.5, 65504 (the largest half), 2^-24 (the smallest subnormal), -0, inf, NaN, 0.5.
  const std::vector<std::uint16_t> t = {0x3C00, 0xC100, 0x7BFF, 0x0001,
                                        0x8000, 0x7C00, 0x7E00, 0x3800};
  TesseraTextureView v = View(RT_FORMAT_HALF, 2, t.data(), 8);
  EXPECT_EQ(Fetch1D<float>(v, 0), 1.f);
  EXPECT_EQ(Fetch1D<float>(v, 1), -2.5f);
  EXPECT_EQ(Fetch1D<float>(v, 2), 65504.f);
  EXPECT_EQ(Fetch1D<float>(v, 3), std::ldexp(1.f, -24));
  EXPECT_TRUE(std::signbit(Fetch1D<float>(v, 4)));
  EXPECT_EQ(Fetch1D<float>(v, 5), kInf);
  EXPECT_TRUE(std::isnan(Fetch1D<float>(v, 6)));
  // Halves read as floats in both read modes, and filter.
  v.read_mode = RT_TEXTURE_READ_NORMALIZED_FLOAT;
  SetFilter(&v, RT_FILTER_LINEAR);
  EXPECT_EQ(Sample1D<float>(v, 0.8f), (179.f * 1.f + 77.f * -2.5f) / 256.f);
  EXPECT_EQ(Sample1D<float>(v, 7.5f), 0.5f);

  const std::vector<std::uint16_t> rgba = {0x3C00, 0x4000, 0x4200, 0x4400};  // 1, 2, 3, 4
  v = View(RT_FORMAT_HALF4, 8, rgba.data(), 1);
  const float4 f = Sample1D<float4>(v, 0.5f);
  EXPECT_EQ(f.x, 1.f);
  EXPECT_EQ(f.y, 2.f);
  EXPECT_EQ(f.z, 3.f);
  EXPECT_EQ(f.w, 4.f);
  v = View(RT_FORMAT_HALF3, 6, rgba.data(), 1);
  const float4 g = Sample1D<float4>(v, 0.5f);
  EXPECT_EQ(g.z, 3.f);
  EXPECT_EQ(g.w, 1.f);
  v = View(RT_FORMAT_HALF2, 4, rgba.data(), 2);
  EXPECT_EQ(Sample1D<float2>(v, 1.5f).y, 4.f);
}

TEST(TextureFormat, ViewsWithoutTexelsReadZero) {
  const std::vector<float> t = {5, 6};
  TesseraTextureView v = FloatView(t, 2);
  v.element_size = 8;  // disagrees with RT_FORMAT_FLOAT
  EXPECT_EQ(Sample1D<float>(v, 0.5f), 0.f);
  v = FloatView(t, 2);
  v.format = RT_FORMAT_USER;
  EXPECT_EQ(Sample1D<float>(v, 0.5f), 0.f);
  v = FloatView(t, 2);
  v.levels[0].data = nullptr;
  EXPECT_EQ(Sample1D<float>(v, 0.5f), 0.f);
  EXPECT_EQ(Fetch1D<float>(v, 0), 0.f);
  v = FloatView(t, 2);
  v.levels[0].width = 0;
  EXPECT_EQ(Sample1D<float>(v, 0.5f), 0.f);
  v = FloatView(t, 2);
  v.level_count = 0;  // read as one level
  EXPECT_EQ(Sample1D<float>(v, 0.5f), 5.f);
}

// ---- sRGB ------------------------------------------------------------------------------------

float SrgbToLinear(unsigned char c) {
  const double v = c / 255.0;
  return static_cast<float>(v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4));
}

TEST(TextureSrgb, DecodesColorNotAlphaBeforeFiltering) {
  const std::vector<unsigned char> t = {128, 10, 200, 128, 0, 0, 0, 255};
  TesseraTextureView v = View(RT_FORMAT_UNSIGNED_BYTE4, 4, t.data(), 2);
  v.read_mode = 3;  // RT_TEXTURE_READ_NORMALIZED_FLOAT_SRGB (OptiX 6)
  float4 f = Sample1D<float4>(v, 0.5f);
  EXPECT_EQ(f.x, SrgbToLinear(128));
  EXPECT_EQ(f.y, SrgbToLinear(10));
  EXPECT_EQ(f.z, SrgbToLinear(200));
  EXPECT_EQ(f.w, 128.f / 255.f);
  for (int c = 0; c < 256; ++c) {
    EXPECT_EQ(tessera::texture::detail::kSrgbToLinear[c],
              SrgbToLinear(static_cast<unsigned char>(c)))
        << c;
  }
  // Filtering happens on linear values: halfway is the mean of the decoded texels.
  SetFilter(&v, RT_FILTER_LINEAR);
  f = Sample1D<float4>(v, 1.f);
  EXPECT_EQ(f.x, static_cast<float>(0.5 * double(SrgbToLinear(128))));
  EXPECT_EQ(f.w, static_cast<float>((128.0 + 255.0) / (2 * 255.0)));
  // Plain normalized float: no decoding.
  v.read_mode = RT_TEXTURE_READ_NORMALIZED_FLOAT;
  SetFilter(&v, RT_FILTER_NEAREST);
  EXPECT_EQ(Sample1D<float4>(v, 0.5f).x, 128.f / 255.f);
  // Element type with sRGB returns the stored integers.
  v.read_mode = 2;  // RT_TEXTURE_READ_ELEMENT_TYPE_SRGB
  EXPECT_EQ(Sample1D<uchar4>(v, 0.5f).x, 128);
}

TEST(TextureSrgb, OneAndTwoChannelBytesDecodeEveryChannel) {
  const std::vector<unsigned char> t = {100, 150};
  TesseraTextureView v = View(RT_FORMAT_UNSIGNED_BYTE2, 2, t.data(), 1);
  v.read_mode = 3;
  const float2 f = Sample1D<float2>(v, 0.5f);
  EXPECT_EQ(f.x, SrgbToLinear(100));
  EXPECT_EQ(f.y, SrgbToLinear(150));
  // Signed bytes are not sRGB data: normalized only.
  const std::vector<signed char> s = {100};
  v = View(RT_FORMAT_BYTE, 1, s.data(), 1);
  v.read_mode = 3;
  EXPECT_EQ(Sample1D<float>(v, 0.5f), 100.f / 127.f);
}

// ---- Mipmaps ---------------------------------------------------------------------------------

struct MipTexture {
  // 4x4 of 1, 2x2 of 2, 1x1 of 4.
  std::vector<float> l0 = std::vector<float>(16, 1.f), l1 = std::vector<float>(4, 2.f),
                     l2 = std::vector<float>(1, 4.f);
  TesseraTextureView View(RTfiltermode mip_filter) const {
    TesseraTextureView v = FloatView(l0, 4, 4);
    v.levels[1] = {l1.data(), 2, 2, 1, 0};
    v.levels[2] = {l2.data(), 1, 1, 1, 0};
    v.level_count = 3;
    v.mip_filter = mip_filter;
    v.index_mode = RT_TEXTURE_INDEX_NORMALIZED_COORDINATES;
    return v;
  }
};

TEST(TextureMip, LevelSelection) {
  const MipTexture m;
  TesseraTextureView v = m.View(RT_FILTER_NONE);
  EXPECT_EQ(Sample2DLod<float>(v, 0.5f, 0.5f, 1.7f), 1.f);

  v = m.View(RT_FILTER_NEAREST);
  EXPECT_EQ(Sample2DLod<float>(v, 0.5f, 0.5f, 0.4f), 1.f);
  EXPECT_EQ(Sample2DLod<float>(v, 0.5f, 0.5f, 0.6f), 2.f);
  EXPECT_EQ(Sample2DLod<float>(v, 0.5f, 0.5f, 1.5f), 4.f);  // rounds half up
  EXPECT_EQ(Sample2DLod<float>(v, 0.5f, 0.5f, 9.f), 4.f);   // past the last level
  EXPECT_EQ(Sample2DLod<float>(v, 0.5f, 0.5f, -3.f), 1.f);
  EXPECT_EQ(Sample2D<float>(v, 0.5f, 0.5f), 1.f);  // plain lookups read level 0

  v = m.View(RT_FILTER_LINEAR);
  EXPECT_EQ(Sample2DLod<float>(v, 0.5f, 0.5f, 0.3f), (179.f * 1 + 77.f * 2) / 256.f);
  EXPECT_EQ(Sample2DLod<float>(v, 0.5f, 0.5f, 1.5f), 3.f);
  EXPECT_EQ(Sample2DLod<float>(v, 0.5f, 0.5f, 2.f), 4.f);
  EXPECT_EQ(Sample2DLod<float>(v, 0.5f, 0.5f, 1.999f), 4.f);  // weight 255.7/256 rounds to 1
}

TEST(TextureMip, BiasAndClamp) {
  const MipTexture m;
  TesseraTextureView v = m.View(RT_FILTER_NEAREST);
  v.mip_level_bias = 1.f;
  EXPECT_EQ(Sample2D<float>(v, 0.5f, 0.5f), 2.f);
  EXPECT_EQ(Sample2DLod<float>(v, 0.5f, 0.5f, 0.6f), 4.f);
  v.mip_level_bias = 0.f;
  v.mip_level_clamp[0] = 0.f;
  v.mip_level_clamp[1] = 0.5f;
  EXPECT_EQ(Sample2DLod<float>(v, 0.5f, 0.5f, 3.f), 2.f);  // clamped to 0.5, rounds to 1
  v.mip_level_clamp[0] = 1.f;
  v.mip_level_clamp[1] = 2.f;
  EXPECT_EQ(Sample2D<float>(v, 0.5f, 0.5f), 2.f);
}

TEST(TextureMip, MagnificationAndMinificationFilters) {
  const std::vector<float> t = {0, 256};
  TesseraTextureView v = FloatView(t, 2);
  v.mag_filter = RT_FILTER_NEAREST;
  v.min_filter = RT_FILTER_LINEAR;
  EXPECT_EQ(Sample1DLod<float>(v, 0.8f, 0.f), 0.f);   // lod <= 0: magnified, nearest
  EXPECT_EQ(Sample1DLod<float>(v, 0.8f, 1.f), 77.f);  // minified, linear (still level 0)
  v.mag_filter = RT_FILTER_LINEAR;
  v.min_filter = RT_FILTER_NEAREST;
  EXPECT_EQ(Sample1DLod<float>(v, 0.8f, -1.f), 77.f);
  EXPECT_EQ(Sample1DLod<float>(v, 0.8f, 0.5f), 0.f);
}

TEST(TextureMip, LevelFromGradients) {
  const MipTexture m;
  TesseraTextureView v = m.View(RT_FILTER_NEAREST);
  // Normalized derivatives scale by level 0's 4 texels: 0.25 -> 1 texel (lod 0), 0.5 -> 2
  // (lod 1), 1 -> 4 (lod 2). The longer of the two decides.
  EXPECT_EQ(Sample2DGrad<float>(v, 0.5f, 0.5f, make_float2(0.25f, 0), make_float2(0, 0.25f)), 1.f);
  EXPECT_EQ(Sample2DGrad<float>(v, 0.5f, 0.5f, make_float2(0.5f, 0), make_float2(0, 0.1f)), 2.f);
  EXPECT_EQ(Sample2DGrad<float>(v, 0.5f, 0.5f, make_float2(0, 0.1f), make_float2(0.6f, 0.8f)), 4.f);
  EXPECT_EQ(Sample2DGrad<float>(v, 0.5f, 0.5f, make_float2(0, 0), make_float2(0, 0)), 1.f);
  v = m.View(RT_FILTER_LINEAR);
  // 2^1.3 texels: lod 1.3, weight 77/256 toward level 2.
  const float d = std::exp2(1.3f) / 4.f;
  EXPECT_EQ(Sample2DGrad<float>(v, 0.5f, 0.5f, make_float2(d, 0), make_float2(0, d)),
            (179.f * 2 + 77.f * 4) / 256.f);
  const std::vector<float> t1 = {1, 1, 1, 1}, t2 = {2, 2};
  TesseraTextureView v1 = FloatView(t1, 4);
  v1.levels[1] = {t2.data(), 2, 1, 1, 0};
  v1.level_count = 2;
  v1.mip_filter = RT_FILTER_NEAREST;
  v1.index_mode = RT_TEXTURE_INDEX_NORMALIZED_COORDINATES;
  EXPECT_EQ(Sample1DGrad<float>(v1, 0.5f, 0.5f, 0.f), 2.f);
  EXPECT_EQ(Sample1DGrad<float>(v1, 0.5f, 0.f, 0.2f), 1.f);
}

TEST(TextureMip, AnisotropyProbesAlongTheLongerAxis) {
  // Level 0 columns 0, 10, 20, 30; level 2 is 100: isotropic filtering of a footprint 4 texels
  // wide reads level 2, anisotropic 4 probes across level 0.
  std::vector<float> l0(16);
  for (int i = 0; i < 16; ++i) l0[i] = 10.f * (i % 4);
  const std::vector<float> l1(4, 50.f), l2(1, 100.f);
  TesseraTextureView v = FloatView(l0, 4, 4);
  v.levels[1] = {l1.data(), 2, 2, 1, 0};
  v.levels[2] = {l2.data(), 1, 1, 1, 0};
  v.level_count = 3;
  v.mip_filter = RT_FILTER_NEAREST;
  v.index_mode = RT_TEXTURE_INDEX_NORMALIZED_COORDINATES;
  const float2 dx = make_float2(1.f, 0.f), dy = make_float2(0.f, 0.25f);
  EXPECT_EQ(Sample2DGrad<float>(v, 0.5f, 0.5f, dx, dy), 100.f);
  v.max_anisotropy = 4.f;
  EXPECT_EQ(Sample2DGrad<float>(v, 0.5f, 0.5f, dx, dy), 15.f);
  // Capped at 2 probes: level log2(4 / 2) = 1.
  v.max_anisotropy = 2.f;
  EXPECT_EQ(Sample2DGrad<float>(v, 0.5f, 0.5f, dx, dy), 50.f);
}

TEST(TextureMip, ThreeDimensionalLevels) {
  const std::vector<float> l0(8, 1.f), l1(1, 3.f);
  TesseraTextureView v = FloatView(l0, 2, 2, 2);
  v.levels[1] = {l1.data(), 1, 1, 1, 0};
  v.level_count = 2;
  v.mip_filter = RT_FILTER_LINEAR;
  v.index_mode = RT_TEXTURE_INDEX_NORMALIZED_COORDINATES;
  EXPECT_EQ(Sample3DLod<float>(v, 0.5f, 0.5f, 0.5f, 0.5f), 2.f);
}

TEST(TextureMip, IntegerElementReadsUseTheNearestLevel) {
  const std::vector<int> l0 = {1, 1}, l1 = {2};
  TesseraTextureView v = View(RT_FORMAT_INT, 4, l0.data(), 2);
  v.levels[1] = {l1.data(), 1, 1, 1, 0};
  v.level_count = 2;
  v.mip_filter = RT_FILTER_LINEAR;
  EXPECT_EQ(Sample1DLod<int>(v, 0.5f, 0.4f), 1);
  EXPECT_EQ(Sample1DLod<int>(v, 0.5f, 0.6f), 2);
}

// ---- Cubemaps and layers ---------------------------------------------------------------------

TEST(TextureCubemap, FaceSelection) {
  // Six 1x1 faces, each holding its index + 1.
  const std::vector<float> faces = {1, 2, 3, 4, 5, 6};
  TesseraTextureView v = FloatView(faces, 1, 1, 6);
  v.cubemap = 1;
  EXPECT_EQ(SampleCubemap<float>(v, 1, 0.2f, -0.3f), 1.f);
  EXPECT_EQ(SampleCubemap<float>(v, -1, 0.2f, -0.3f), 2.f);
  EXPECT_EQ(SampleCubemap<float>(v, 0.2f, 1, -0.3f), 3.f);
  EXPECT_EQ(SampleCubemap<float>(v, 0.2f, -1, -0.3f), 4.f);
  EXPECT_EQ(SampleCubemap<float>(v, 0.2f, -0.3f, 1), 5.f);
  EXPECT_EQ(SampleCubemap<float>(v, 0.2f, -0.3f, -1), 6.f);
  EXPECT_EQ(SampleCubemap<float>(v, 5, 5, 5), 1.f);   // ties: x first
  EXPECT_EQ(SampleCubemap<float>(v, 1, -2, 2), 4.f);  // then y
}

TEST(TextureCubemap, FaceCoordinates) {
  // Six 2x2 faces: texel (i, j) of face f holds 10 f + 2 j + i.
  std::vector<float> t(24);
  for (int f = 0; f < 6; ++f)
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 2; ++i) t[f * 4 + j * 2 + i] = 10.f * f + 2 * j + i;
  TesseraTextureView v = FloatView(t, 2, 2, 6);
  v.cubemap = 1;
  v.index_mode = RT_TEXTURE_INDEX_ARRAY_INDEX;  // faces always use normalized (s, t)
  // Directions with sc = -0.5, tc = 0.5 on each face: (s, t) = (0.25, 0.75), texel (0, 1).
  const float dirs[6][3] = {{1, -0.5f, 0.5f},   {-1, -0.5f, -0.5f}, {-0.5f, 1, 0.5f},
                            {-0.5f, -1, -0.5f}, {-0.5f, -0.5f, 1},  {0.5f, -0.5f, -1}};
  for (int f = 0; f < 6; ++f) {
    const float* d = dirs[f];
    EXPECT_EQ(SampleCubemap<float>(v, d[0], d[1], d[2]), 10.f * f + 2) << f;
    // The minor components negated: sc = 0.5, tc = -0.5, texel (1, 0).
    const float n[3] = {f / 2 == 0 ? d[0] : -d[0], f / 2 == 1 ? d[1] : -d[1],
                        f / 2 == 2 ? d[2] : -d[2]};
    EXPECT_EQ(SampleCubemap<float>(v, n[0], n[1], n[2]), 10.f * f + 1) << f;
  }
  // Linear filtering stays on the face: at the face's corner every tap is texel (0, 0).
  SetFilter(&v, RT_FILTER_LINEAR);
  EXPECT_EQ(SampleCubemap<float>(v, 1, 1, 1), 0.f);
}

TEST(TextureCubemap, Layered) {
  std::vector<float> t(12);
  for (int i = 0; i < 12; ++i) t[i] = static_cast<float>((i / 6) * 100 + i % 6);
  TesseraTextureView v = FloatView(t, 1, 1, 12);
  v.cubemap = 1;
  v.layered = 1;
  EXPECT_EQ(SampleCubemapLayered<float>(v, 0, 0, -1, 0), 5.f);
  EXPECT_EQ(SampleCubemapLayered<float>(v, 0, 0, -1, 1), 105.f);
  EXPECT_EQ(SampleCubemapLayered<float>(v, 0, 1, 0, 1), 102.f);
  EXPECT_EQ(SampleCubemapLayered<float>(v, 0, 1, 0, 7), 102.f);  // past the last layer
}

TEST(TextureLayered, TwoDimensionalLayersAreNotFilteredAcross) {
  // 2x1 texels, 3 layers: layer l holds (10 l, 10 l + 2).
  const std::vector<float> t = {0, 2, 10, 12, 20, 22};
  TesseraTextureView v = FloatView(t, 2, 1, 3);
  v.layered = 1;
  SetFilter(&v, RT_FILTER_LINEAR);
  EXPECT_EQ(Sample2DLayered<float>(v, 1.f, 0.5f, 0), 1.f);
  EXPECT_EQ(Sample2DLayered<float>(v, 1.f, 0.5f, 1), 11.f);
  EXPECT_EQ(Sample2DLayered<float>(v, 1.f, 0.5f, 2), 21.f);
  EXPECT_EQ(Sample2DLayered<float>(v, 1.f, 0.5f, 3), 21.f);  // clamped to the last layer
  EXPECT_EQ(Sample2DLayered<float>(v, 1.f, 0.5f, -4), 1.f);  // and the first
}

TEST(TextureLayered, OneDimensionalLayers) {
  const std::vector<float> t = {0, 2, 10, 12};
  TesseraTextureView v = FloatView(t, 2, 1, 2);
  v.layered = 1;
  SetFilter(&v, RT_FILTER_LINEAR);
  EXPECT_EQ(Sample1DLayered<float>(v, 1.f, 1), 11.f);
  EXPECT_EQ(Sample1DLayered<float>(v, 0.f, 1), 10.f);
}

// ---- Gather and fetch ------------------------------------------------------------------------

TEST(TextureGather, FourTexelsInPtxOrder) {
  // 2x2 uchar4; texel (i, j) has y = 10 (2 j + i) + 1.
  std::vector<unsigned char> t(16);
  for (int k = 0; k < 4; ++k) {
    t[k * 4 + 0] = 0;
    t[k * 4 + 1] = static_cast<unsigned char>(10 * k + 1);
    t[k * 4 + 2] = 0;
    t[k * 4 + 3] = 0;
  }
  TesseraTextureView v = View(RT_FORMAT_UNSIGNED_BYTE4, 4, t.data(), 2, 2);
  const uchar4 g = Gather2D<uchar4>(v, 1.f, 1.f, 1);
  EXPECT_EQ(g.x, 21);  // (i, j+1)
  EXPECT_EQ(g.y, 31);  // (i+1, j+1)
  EXPECT_EQ(g.z, 11);  // (i+1, j)
  EXPECT_EQ(g.w, 1);   // (i, j)
  v.read_mode = RT_TEXTURE_READ_NORMALIZED_FLOAT;
  SetWrap(&v, RT_WRAP_CLAMP_TO_BORDER);
  const float4 f = Gather2D<float4>(v, 0.25f, 0.25f, 1);  // i = j = -1: three border texels
  EXPECT_EQ(f.x, 0.f);
  EXPECT_EQ(f.y, 1.f / 255.f);
  EXPECT_EQ(f.z, 0.f);
  EXPECT_EQ(f.w, 0.f);
}

TEST(TextureFetch, IntegerCoordinatesWithoutWrapping) {
  const std::vector<unsigned char> t = {0, 51, 102, 153, 204, 255, 7, 8};
  TesseraTextureView v = View(RT_FORMAT_UNSIGNED_BYTE, 1, t.data(), 2, 2, 2);
  v.read_mode = RT_TEXTURE_READ_NORMALIZED_FLOAT;
  SetWrap(&v, RT_WRAP_REPEAT);
  EXPECT_EQ(Fetch1D<float>(v, 1), 0.2f);
  EXPECT_EQ(Fetch2D<float>(v, 1, 1), 0.6f);
  EXPECT_EQ(Fetch3D<float>(v, 1, 0, 1), 1.f);
  EXPECT_EQ(Fetch1D<float>(v, 2), 0.f);
  EXPECT_EQ(Fetch1D<float>(v, -1), 0.f);
  EXPECT_EQ(Fetch3D<float>(v, 0, 0, 2), 0.f);
  v.read_mode = RT_TEXTURE_READ_ELEMENT_TYPE;
  EXPECT_EQ(Fetch3D<unsigned char>(v, 1, 1, 1), 8);
}

// ---- Coordinates that are not numbers --------------------------------------------------------

TEST(TextureCoordinates, NanAndInfinityStayInside) {
  const std::vector<float> t = {10, 20, 30, 40};
  const float xs[] = {kNaN, kInf, -kInf, 1e30f, -1e30f, 3e9f, -3e9f, 8388609.f};
  for (RTtextureindexmode index :
       {RT_TEXTURE_INDEX_NORMALIZED_COORDINATES, RT_TEXTURE_INDEX_ARRAY_INDEX}) {
    for (RTwrapmode wrap :
         {RT_WRAP_REPEAT, RT_WRAP_CLAMP_TO_EDGE, RT_WRAP_MIRROR, RT_WRAP_CLAMP_TO_BORDER}) {
      for (RTfiltermode filter : {RT_FILTER_NEAREST, RT_FILTER_LINEAR}) {
        TesseraTextureView v = FloatView(t, 2, 2);
        v.index_mode = index;
        SetWrap(&v, wrap);
        SetFilter(&v, filter);
        for (float x : xs) {
          for (float y : xs) {
            const float r = Sample2D<float>(v, x, y);
            EXPECT_TRUE(r >= 0.f && r <= 40.f) << x << " " << y << " -> " << r;
          }
        }
        // NaN reads as coordinate 0.
        EXPECT_EQ(Sample2D<float>(v, kNaN, kNaN), Sample2D<float>(v, 0.f, 0.f));
      }
    }
  }
}

TEST(TextureCoordinates, NanLevelsDerivativesAndDirections) {
  const MipTexture m;
  TesseraTextureView v = m.View(RT_FILTER_LINEAR);
  EXPECT_EQ(Sample2DLod<float>(v, 0.5f, 0.5f, kNaN), 1.f);
  const float2 nan2 = make_float2(kNaN, kNaN), inf2 = make_float2(kInf, 0);
  const float g = Sample2DGrad<float>(v, 0.5f, 0.5f, nan2, nan2);
  EXPECT_TRUE(g >= 1.f && g <= 4.f) << g;
  v.max_anisotropy = 16.f;
  const float h = Sample2DGrad<float>(v, 0.5f, 0.5f, inf2, make_float2(0, 0.1f));
  EXPECT_TRUE(h >= 1.f && h <= 4.f) << h;
  const float i = Sample2DGrad<float>(v, kNaN, 0.5f, make_float2(1, 0), make_float2(0, 0));
  EXPECT_TRUE(i >= 1.f && i <= 4.f) << i;

  const std::vector<float> faces = {1, 2, 3, 4, 5, 6};
  TesseraTextureView c = FloatView(faces, 1, 1, 6);
  c.cubemap = 1;
  for (float a : {kNaN, kInf, 0.f}) {
    const float r = SampleCubemap<float>(c, a, a, a);
    EXPECT_TRUE(r >= 1.f && r <= 6.f) << a << " -> " << r;
  }
}

// Pitched rows (TesseraTextureLevel::pitch, CUDA's cudaResourceTypePitch2D): the padding between
// rows is never read, and every lookup, the fast RGBA8 one included, gives the packed view's bits.
TEST(TexturePitch, PitchedRowsSampleAsPackedOnes) {
  constexpr unsigned kW = 5, kH = 4, kPitch = 8;
  std::vector<unsigned char> packed(kW * kH * 4), pitched(kPitch * kH * 4, 0xff);
  for (size_t i = 0; i < packed.size(); ++i) packed[i] = static_cast<unsigned char>(i * 37 + 11);
  for (unsigned y = 0; y < kH; ++y) {
    std::memcpy(&pitched[y * kPitch * 4], &packed[y * kW * 4], kW * 4);
  }
  for (RTwrapmode wrap : {RT_WRAP_REPEAT, RT_WRAP_CLAMP_TO_EDGE, RT_WRAP_MIRROR}) {
    TesseraTextureView a = View(RT_FORMAT_UNSIGNED_BYTE4, 4, packed.data(), kW, kH);
    SetFilter(&a, RT_FILTER_LINEAR);
    SetWrap(&a, wrap);
    a.read_mode = RT_TEXTURE_READ_NORMALIZED_FLOAT;
    a.index_mode = RT_TEXTURE_INDEX_NORMALIZED_COORDINATES;
    TesseraTextureView b = a;
    b.levels[0].data = pitched.data();
    b.levels[0].pitch = kPitch;
    a.fast = tessera::texture::FastKind(a);
    b.fast = tessera::texture::FastKind(b);
    for (int i = -20; i <= 40; ++i) {
      const float x = i * 0.0625f, y = 1.f - i * 0.046875f;
      const float4 p = Sample2D<float4>(a, x, y), q = Sample2D<float4>(b, x, y);
      EXPECT_EQ(std::memcmp(&p, &q, sizeof p), 0) << x << ", " << y << " wrap " << wrap;
      const float4 g = Gather2D<float4>(a, x, y, 1), h = Gather2D<float4>(b, x, y, 1);
      EXPECT_EQ(std::memcmp(&g, &h, sizeof g), 0) << x << ", " << y;
    }
    for (int y = 0; y < int(kH); ++y) {
      for (int x = 0; x < int(kW); ++x) {
        const uint4 p = Fetch2D<uint4>(a, x, y), q = Fetch2D<uint4>(b, x, y);
        EXPECT_EQ(std::memcmp(&p, &q, sizeof p), 0) << x << ", " << y;
      }
    }
  }
}

}  // namespace

// Texture samplers on devices: a program reads a 2D texture through a declared rtTextureSampler
// and through its bindless id, mip levels reach the device, a change of the sampler's modes ships
// no texels, unknown ids raise RT_EXCEPTION_TEXTURE_ID_INVALID; on an in-process device and on 1
// and 3 worker processes, with bit-identical results.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "rt_fixture.h"
#include "tessera/detail/texture_sampling.h"

namespace tessera::testing {
namespace {

constexpr char kModule[] = "texture_programs";
constexpr unsigned kSide = 4;  // texture and launch: kSide x kSide

// Texel (x, y) of level `level`: distinct in every component.
Float4 Texel(unsigned x, unsigned y, unsigned level = 0) {
  return {static_cast<float>(x), static_cast<float>(y), static_cast<float>(x + kSide * y),
          static_cast<float>(level + 1)};
}

class TextureTest : public OnDevicesFixture {
 protected:
  void SetUp() override {
    OnDevicesFixture::SetUp();
    declared_ = Float4Buffer("declared_out", RT_BUFFER_OUTPUT, kSide, kSide);
    bindless_ = Float4Buffer("bindless_out", RT_BUFFER_OUTPUT, kSide, kSide);
    texels_ = TextureBuffer(kSide, 1);
    sampler_ = Sampler(texels_);
    Ok(rtVariableSetObject(ContextVar("tex"), sampler_));
    Ok(rtVariableSet1i(ContextVar("tex_id"), Id(sampler_)));
    Ok(rtVariableSet1f(ContextVar("lod"), 0.f));
    Ok(rtVariableSet2f(ContextVar("offset"), 0.f, 0.f));
    RayGen("sample_both");
  }

  void RayGen(const char* function) {
    Ok(rtContextSetRayGenerationProgram(ctx_, 0, Program(kModule, function)));
  }

  // A float4 texture of side x side texels and `levels` mip levels, each texel Texel(x, y, l).
  RTbuffer TextureBuffer(unsigned side, unsigned levels) {
    RTbuffer b = nullptr;
    EXPECT_EQ(rtBufferCreate(ctx_, RT_BUFFER_INPUT, &b), RT_SUCCESS);
    EXPECT_EQ(rtBufferSetFormat(b, RT_FORMAT_FLOAT4), RT_SUCCESS);
    EXPECT_EQ(rtBufferSetSize2D(b, side, side), RT_SUCCESS);
    EXPECT_EQ(rtBufferSetMipLevelCount(b, levels), RT_SUCCESS);
    for (unsigned l = 0; l < levels; ++l) {
      void* p = nullptr;
      EXPECT_EQ(rtBufferMapEx(b, RT_BUFFER_MAP_WRITE_DISCARD, l, nullptr, &p), RT_SUCCESS);
      const unsigned n = side >> l;
      for (unsigned y = 0; y < n; ++y) {
        for (unsigned x = 0; x < n; ++x) static_cast<Float4*>(p)[y * n + x] = Texel(x, y, l);
      }
      EXPECT_EQ(rtBufferUnmapEx(b, l), RT_SUCCESS);
    }
    return b;
  }

  // Nearest filtering at texel centres gives texels exactly, whatever the filter arithmetic.
  RTtexturesampler Sampler(RTbuffer b) {
    RTtexturesampler s = nullptr;
    EXPECT_EQ(rtTextureSamplerCreate(ctx_, &s), RT_SUCCESS);
    EXPECT_EQ(rtTextureSamplerSetBuffer(s, 0, 0, b), RT_SUCCESS);
    EXPECT_EQ(rtTextureSamplerSetFilteringModes(s, RT_FILTER_NEAREST, RT_FILTER_NEAREST,
                                                RT_FILTER_NEAREST),
              RT_SUCCESS);
    EXPECT_EQ(rtTextureSamplerSetReadMode(s, RT_TEXTURE_READ_ELEMENT_TYPE), RT_SUCCESS);
    for (unsigned d = 0; d < 3; ++d) {
      EXPECT_EQ(rtTextureSamplerSetWrapMode(s, d, RT_WRAP_CLAMP_TO_EDGE), RT_SUCCESS);
    }
    return s;
  }

  int Id(RTtexturesampler s) {
    int id = 0;
    EXPECT_EQ(rtTextureSamplerGetId(s, &id), RT_SUCCESS);
    return id;
  }

  void Launch() {
    const RTresult r = rtContextLaunch2D(ctx_, 0, kSide, kSide);
    ASSERT_EQ(r, RT_SUCCESS) << Error(r);
  }

  unsigned long long Sent() {
    unsigned long long sent = 0, received = 0;
    EXPECT_EQ(tesseraContextGetTransferStats(ctx_, &sent, &received), RT_SUCCESS);
    return sent;
  }

  // Both outputs hold `expected(x, y)` at every launch index.
  template <typename F>
  void ExpectBoth(F&& expected, const char* what) {
    const std::vector<Float4> declared = Read(declared_), bindless = Read(bindless_);
    for (unsigned y = 0; y < kSide; ++y) {
      for (unsigned x = 0; x < kSide; ++x) {
        EXPECT_EQ(declared[y * kSide + x], expected(x, y))
            << what << " declared at " << x << "," << y;
        EXPECT_EQ(bindless[y * kSide + x], expected(x, y))
            << what << " bindless at " << x << "," << y;
      }
    }
  }

  // A view of w x h texels as the host's general sampling path reads them: linear filtering,
  // normalized coordinates, one level (the wrap modes are set per check).
  static TesseraTextureView LinearView(const void* texels, unsigned w, unsigned h, RTformat format,
                                       unsigned element_size, RTtexturereadmode read_mode) {
    TesseraTextureView v{};
    v.levels[0] = {texels, w, h, 1, 0};
    v.level_count = 1;
    v.dimensionality = 2;
    v.format = format;
    v.element_size = element_size;
    v.min_filter = v.mag_filter = RT_FILTER_LINEAR;
    v.mip_filter = RT_FILTER_NONE;
    v.read_mode = read_mode;
    v.index_mode = RT_TEXTURE_INDEX_NORMALIZED_COORDINATES;
    v.mip_level_clamp[1] = 1000.f;
    return v;
  }

  // For each pair of wrap modes, sampler `s` set so and launched: both outputs hold what the
  // general path computes from `v` at the ray generation program's coordinates (offset -1.3,
  // 0.45 texels).
  template <size_t N>
  void ExpectTheGeneralPath(RTtexturesampler s, TesseraTextureView v,
                            const RTwrapmode (&modes)[N][2], const char* what) {
    for (const auto& m : modes) {
      Ok(rtTextureSamplerSetWrapMode(s, 0, m[0]));
      Ok(rtTextureSamplerSetWrapMode(s, 1, m[1]));
      v.wrap[0] = m[0];
      v.wrap[1] = m[1];
      Launch();
      ExpectBoth(
          [&](unsigned x, unsigned y) {
            const float4 f = tessera::texture::Sample2D<float4>(v, (x + 0.5f - 1.3f) / kSide,
                                                                (y + 0.5f + 0.45f) / kSide);
            return Float4{f.x, f.y, f.z, f.w};
          },
          what);
    }
  }

  RTbuffer declared_ = nullptr, bindless_ = nullptr, texels_ = nullptr;
  RTtexturesampler sampler_ = nullptr;
};

TEST_P(TextureTest, DeclaredAndBindlessReadTheTexels) {
  Launch();
  ExpectBoth([](unsigned x, unsigned y) { return Texel(x, y); }, "texel centres");
  RayGen("sample_plain");  // tex2D and the rtTex2D(T*, ...) form
  Launch();
  ExpectBoth([](unsigned x, unsigned y) { return Texel(x, y); }, "tex2D");
}

TEST_P(TextureTest, ChangingModesShipsNoTexels) {
  Ok(rtVariableSet2f(ContextVar("offset"), 2.f, 0.f));
  Launch();
  ExpectBoth([](unsigned x, unsigned y) { return Texel(std::min(x + 2, kSide - 1), y); }, "clamp");
  const unsigned long long before = Sent();
  EXPECT_GT(before, 0u);  // the texels went once
  Ok(rtTextureSamplerSetWrapMode(sampler_, 0, RT_WRAP_REPEAT));
  Launch();
  ExpectBoth([](unsigned x, unsigned y) { return Texel((x + 2) % kSide, y); }, "repeat");
  EXPECT_EQ(Sent(), before) << "a wrap mode change shipped buffer bytes";
  // New texels do travel.
  void* p = nullptr;
  Ok(rtBufferMap(texels_, &p));
  static_cast<Float4*>(p)[0] = {9.f, 9.f, 9.f, 9.f};
  Ok(rtBufferUnmap(texels_));
  Ok(rtVariableSet2f(ContextVar("offset"), 0.f, 0.f));
  Launch();
  EXPECT_GT(Sent(), before);
  EXPECT_EQ(Read(declared_)[0], (Float4{9.f, 9.f, 9.f, 9.f}));
  EXPECT_EQ(Read(bindless_)[0], (Float4{9.f, 9.f, 9.f, 9.f}));
}

TEST_P(TextureTest, MipLevelsReachTheDevice) {
  RTbuffer mipmapped = TextureBuffer(kSide, 3);
  RTtexturesampler s = Sampler(mipmapped);
  Ok(rtTextureSamplerSetMipLevelClamp(s, 0.f, 2.f));
  Ok(rtVariableSetObject(ContextVar("tex"), s));
  Ok(rtVariableSet1i(ContextVar("tex_id"), Id(s)));
  for (unsigned level = 0; level < 3; ++level) {
    Ok(rtVariableSet1f(ContextVar("lod"), static_cast<float>(level)));
    Launch();
    // Level l has kSide >> l texels a side: launch index (x, y) falls in texel (x, y) >> l.
    ExpectBoth([&](unsigned x, unsigned y) { return Texel(x >> level, y >> level, level); },
               "level");
  }
}

TEST_P(TextureTest, UnboundSamplersReadZerosAndSizesAreLevelZeros) {
  RayGen("sample_unbound");
  Launch();
  const std::vector<Float4> declared = Read(declared_), bindless = Read(bindless_);
  for (size_t i = 0; i < declared.size(); ++i) {
    EXPECT_EQ(declared[i], (Float4{0.f, 0.f, 0.f, 0.f})) << i;
    EXPECT_EQ(bindless[i], (Float4{kSide, kSide, 1.f, 0.f})) << i;  // rtTexSize
  }
}

TEST_P(TextureTest, NormalizedFloatReadsOfBytes) {
  RTbuffer b = nullptr;
  Ok(rtBufferCreate(ctx_, RT_BUFFER_INPUT, &b));
  Ok(rtBufferSetFormat(b, RT_FORMAT_UNSIGNED_BYTE4));
  Ok(rtBufferSetSize2D(b, kSide, kSide));
  void* p = nullptr;
  Ok(rtBufferMap(b, &p));
  for (unsigned i = 0; i < kSide * kSide; ++i) {
    const unsigned char texel[4] = {0, 255, 51, static_cast<unsigned char>(i)};
    std::memcpy(static_cast<unsigned char*>(p) + 4 * i, texel, 4);
  }
  Ok(rtBufferUnmap(b));
  RTtexturesampler s = Sampler(b);
  Ok(rtTextureSamplerSetReadMode(s, RT_TEXTURE_READ_NORMALIZED_FLOAT));
  Ok(rtVariableSetObject(ContextVar("bytes_tex"), s));
  RayGen("sample_bytes");
  Launch();
  const std::vector<Float4> out = Read(declared_);
  for (unsigned i = 0; i < kSide * kSide; ++i) {
    EXPECT_EQ(out[i][0], 0.f);
    EXPECT_EQ(out[i][1], 1.f);
    EXPECT_FLOAT_EQ(out[i][2], 0.2f);
    EXPECT_FLOAT_EQ(out[i][3], i / 255.f);
  }
}

// An RGBA8 image read bilinearly as floats, the commonest texture, takes the engine's fast path
// (tessera/detail/texture_fast.h) for clamp and repeat; mirror and mixed modes take the general
// one. Every mode gives what the general sampling functions give on the host, texel for texel, at
// coordinates between texels and past the edges, declared and by id, also when the id is too
// sparse for the engine's table.
TEST_P(TextureTest, BilinearBytesMatchTheGeneralPathInEveryWrapMode) {
  constexpr unsigned kW = 5, kH = 3;
  std::vector<unsigned char> bytes(kW * kH * 4);
  for (size_t i = 0; i < bytes.size(); ++i) bytes[i] = static_cast<unsigned char>(i * 97 + 13);
  for (int sparse = 0; sparse < 2; ++sparse) {
    if (sparse == 1) {  // the next sampler's id lies past the engine's array
      for (int i = 0; i < 9000; ++i) {
        RTmaterial m = nullptr;
        Ok(rtMaterialCreate(ctx_, &m));
      }
    }
    RTbuffer b = nullptr;
    Ok(rtBufferCreate(ctx_, RT_BUFFER_INPUT, &b));
    Ok(rtBufferSetFormat(b, RT_FORMAT_UNSIGNED_BYTE4));
    Ok(rtBufferSetSize2D(b, kW, kH));
    void* p = nullptr;
    Ok(rtBufferMap(b, &p));
    std::memcpy(p, bytes.data(), bytes.size());
    Ok(rtBufferUnmap(b));
    RTtexturesampler s = Sampler(b);
    Ok(rtTextureSamplerSetReadMode(s, RT_TEXTURE_READ_NORMALIZED_FLOAT));
    Ok(rtTextureSamplerSetFilteringModes(s, RT_FILTER_LINEAR, RT_FILTER_LINEAR, RT_FILTER_NONE));
    Ok(rtVariableSetObject(ContextVar("bytes_tex"), s));
    Ok(rtVariableSet1i(ContextVar("bytes_id"), Id(s)));
    if (sparse == 1) {
      ASSERT_GT(Id(s), 9000);
    }
    Ok(rtVariableSet2f(ContextVar("offset"), -1.3f, 0.45f));
    RayGen("sample_bytes_both");
    const RTwrapmode modes[][2] = {{RT_WRAP_CLAMP_TO_EDGE, RT_WRAP_CLAMP_TO_EDGE},
                                   {RT_WRAP_REPEAT, RT_WRAP_REPEAT},
                                   {RT_WRAP_MIRROR, RT_WRAP_MIRROR},
                                   {RT_WRAP_REPEAT, RT_WRAP_CLAMP_TO_BORDER}};
    ExpectTheGeneralPath(s,
                         LinearView(bytes.data(), kW, kH, RT_FORMAT_UNSIGNED_BYTE4, 4,
                                    RT_TEXTURE_READ_NORMALIZED_FLOAT),
                         modes, sparse == 1 ? "sparse id" : "dense id");
  }
}

// A float4 texture filtered linearly, as an HDR environment map is read: devices take the fast
// linear lookup (texture_fast_float.h) where the wrap modes allow and must give the general
// path's bits in every mode, declared and by id.
TEST_P(TextureTest, BilinearFloatsMatchTheGeneralPathInEveryWrapMode) {
  std::vector<Float4> texels;
  for (unsigned y = 0; y < kSide; ++y) {
    for (unsigned x = 0; x < kSide; ++x) texels.push_back(Texel(x, y));
  }
  Ok(rtTextureSamplerSetFilteringModes(sampler_, RT_FILTER_LINEAR, RT_FILTER_LINEAR,
                                       RT_FILTER_NONE));
  Ok(rtVariableSet2f(ContextVar("offset"), -1.3f, 0.45f));
  RayGen("sample_plain");
  const RTwrapmode modes[][2] = {{RT_WRAP_CLAMP_TO_EDGE, RT_WRAP_CLAMP_TO_EDGE},
                                 {RT_WRAP_REPEAT, RT_WRAP_CLAMP_TO_EDGE},
                                 {RT_WRAP_REPEAT, RT_WRAP_REPEAT},
                                 {RT_WRAP_MIRROR, RT_WRAP_MIRROR}};
  ExpectTheGeneralPath(
      sampler_,
      LinearView(texels.data(), kSide, kSide, RT_FORMAT_FLOAT4, 16, RT_TEXTURE_READ_ELEMENT_TYPE),
      modes, "float4");
}

// Cube maps and layered textures reach the device with their faces and layers in order.
TEST_P(TextureTest, CubeMapFacesAndLayers) {
  // 2x2 texels a face or layer, each texel of face f (layer l) holding f (10 + l).
  auto filled = [&](unsigned desc, unsigned depth, float base) {
    RTbuffer b = nullptr;
    EXPECT_EQ(rtBufferCreate(ctx_, RT_BUFFER_INPUT | desc, &b), RT_SUCCESS);
    EXPECT_EQ(rtBufferSetFormat(b, RT_FORMAT_FLOAT4), RT_SUCCESS);
    EXPECT_EQ(rtBufferSetSize3D(b, 2, 2, depth), RT_SUCCESS);
    void* p = nullptr;
    EXPECT_EQ(rtBufferMap(b, &p), RT_SUCCESS);
    for (unsigned i = 0; i < 4 * depth; ++i) {
      static_cast<Float4*>(p)[i] = {base + i / 4, 0.f, 0.f, 1.f};
    }
    EXPECT_EQ(rtBufferUnmap(b), RT_SUCCESS);
    return b;
  };
  Ok(rtVariableSetObject(ContextVar("cube_tex"), Sampler(filled(RT_BUFFER_CUBEMAP, 6, 0.f))));
  Ok(rtVariableSetObject(ContextVar("layers_tex"), Sampler(filled(RT_BUFFER_LAYERED, 3, 10.f))));
  RayGen("sample_cube_and_layers");
  Launch();
  const std::vector<Float4> faces = Read(declared_), layers = Read(bindless_);
  for (unsigned i = 0; i < kSide * kSide; ++i) {
    EXPECT_EQ(faces[i], (Float4{static_cast<float>(i % 6), 0.f, 0.f, 1.f})) << "face of " << i;
    EXPECT_EQ(layers[i], (Float4{10.f + i % 3, 0.f, 0.f, 1.f})) << "layer of " << i;
  }
}

TEST_P(TextureTest, UnknownIdsRaiseTextureIdInvalid) {
  Ok(rtVariableSet1i(ContextVar("tex_id"), 99999));
  // Disabled (the default): the read gives zeros.
  Launch();
  for (const Float4& v : Read(bindless_)) EXPECT_EQ(v, (Float4{0.f, 0.f, 0.f, 0.f}));
  Ok(rtContextSetExceptionEnabled(ctx_, RT_EXCEPTION_TEXTURE_ID_INVALID, 1));
  Ok(rtContextSetExceptionProgram(ctx_, 0, Program(kModule, "record_exception")));
  Launch();
  for (const Float4& v : Read(declared_)) {
    EXPECT_EQ(v[0], static_cast<float>(RT_EXCEPTION_TEXTURE_ID_INVALID));
  }
}

TEST_P(TextureTest, ASamplerBoundToTheWrongShapeFailsTheLaunchNamingIt) {
  RTbuffer flat = nullptr;
  Ok(rtBufferCreate(ctx_, RT_BUFFER_INPUT, &flat));
  Ok(rtBufferSetFormat(flat, RT_FORMAT_FLOAT4));
  Ok(rtBufferSetSize1D(flat, 8));
  Ok(rtVariableSetObject(ContextVar("tex"), Sampler(flat)));
  const RTresult r = rtContextLaunch2D(ctx_, 0, kSide, kSide);
  EXPECT_NE(r, RT_SUCCESS);
  const std::string message = Error(r);
  EXPECT_NE(message.find("rtTextureSampler 'tex'"), std::string::npos) << message;
  EXPECT_NE(message.find("needs a 2D buffer"), std::string::npos) << message;
}

INSTANTIATE_TEST_SUITE_P(Devices, TextureTest, ::testing::Values("inproc", "local:1", "local:3"),
                         DeviceName);

// Linear filtering between texels, wrapped and mipmapped, gives the same bits on every device set.
TEST(TextureDeterminismTest, BitIdenticalOnEveryDeviceSet) {
  std::vector<std::vector<Float4>> results;
  for (const char* spec : {"inproc", "local:1", "local:3"}) {
    RTcontext ctx = nullptr;
    ASSERT_EQ(rtContextCreate(&ctx), RT_SUCCESS);
    ASSERT_EQ(tesseraContextSetDeviceSpec(ctx, spec), RT_SUCCESS);
    ASSERT_EQ(rtContextSetEntryPointCount(ctx, 1), RT_SUCCESS);
    ASSERT_EQ(rtContextSetRayTypeCount(ctx, 1), RT_SUCCESS);
    auto var = [&](const char* name) {
      RTvariable v = nullptr;
      EXPECT_EQ(rtContextDeclareVariable(ctx, name, &v), RT_SUCCESS);
      return v;
    };
    constexpr unsigned kTex = 16, kW = 37, kH = 23;
    RTbuffer texels = nullptr;
    ASSERT_EQ(rtBufferCreate(ctx, RT_BUFFER_INPUT, &texels), RT_SUCCESS);
    ASSERT_EQ(rtBufferSetFormat(texels, RT_FORMAT_FLOAT4), RT_SUCCESS);
    ASSERT_EQ(rtBufferSetSize2D(texels, kTex, kTex), RT_SUCCESS);
    ASSERT_EQ(rtBufferSetMipLevelCount(texels, 2), RT_SUCCESS);
    for (unsigned l = 0; l < 2; ++l) {
      void* p = nullptr;
      ASSERT_EQ(rtBufferMapEx(texels, RT_BUFFER_MAP_WRITE_DISCARD, l, nullptr, &p), RT_SUCCESS);
      const unsigned n = (kTex >> l) * (kTex >> l);
      for (unsigned i = 0; i < n; ++i) {
        static_cast<Float4*>(p)[i] = {std::sin(i * 0.37f), std::cos(i * 1.3f), i * 0.01f,
                                      static_cast<float>(l)};
      }
      ASSERT_EQ(rtBufferUnmapEx(texels, l), RT_SUCCESS);
    }
    RTtexturesampler s = nullptr;
    ASSERT_EQ(rtTextureSamplerCreate(ctx, &s), RT_SUCCESS);
    ASSERT_EQ(rtTextureSamplerSetBuffer(s, 0, 0, texels), RT_SUCCESS);
    ASSERT_EQ(
        rtTextureSamplerSetFilteringModes(s, RT_FILTER_LINEAR, RT_FILTER_LINEAR, RT_FILTER_LINEAR),
        RT_SUCCESS);
    ASSERT_EQ(rtTextureSamplerSetWrapMode(s, 0, RT_WRAP_MIRROR), RT_SUCCESS);
    ASSERT_EQ(rtTextureSamplerSetMipLevelClamp(s, 0.f, 1.f), RT_SUCCESS);
    ASSERT_EQ(rtVariableSetObject(var("tex"), s), RT_SUCCESS);
    int id = 0;
    ASSERT_EQ(rtTextureSamplerGetId(s, &id), RT_SUCCESS);
    ASSERT_EQ(rtVariableSet1i(var("tex_id"), id), RT_SUCCESS);
    ASSERT_EQ(rtVariableSet1f(var("lod"), 0.4f), RT_SUCCESS);
    ASSERT_EQ(rtVariableSet2f(var("offset"), 11.3f, -3.7f), RT_SUCCESS);
    RTbuffer outs[2];
    const char* names[2] = {"declared_out", "bindless_out"};
    for (int k = 0; k < 2; ++k) {
      ASSERT_EQ(rtBufferCreate(ctx, RT_BUFFER_OUTPUT, &outs[k]), RT_SUCCESS);
      ASSERT_EQ(rtBufferSetFormat(outs[k], RT_FORMAT_FLOAT4), RT_SUCCESS);
      ASSERT_EQ(rtBufferSetSize2D(outs[k], kW, kH), RT_SUCCESS);
      ASSERT_EQ(rtVariableSetObject(var(names[k]), outs[k]), RT_SUCCESS);
    }
    RTprogram rg = nullptr;
    const std::string path = std::string(TESSERA_TEST_MODULE_DIR) + "/" + kModule + ".so";
    ASSERT_EQ(rtProgramCreateFromPTXFile(ctx, path.c_str(), "sample_both", &rg), RT_SUCCESS);
    ASSERT_EQ(rtContextSetRayGenerationProgram(ctx, 0, rg), RT_SUCCESS);
    ASSERT_EQ(rtContextLaunch2D(ctx, 0, kW, kH), RT_SUCCESS) << spec;
    std::vector<Float4> both(2 * kW * kH);
    for (int k = 0; k < 2; ++k) {
      void* p = nullptr;
      ASSERT_EQ(rtBufferMap(outs[k], &p), RT_SUCCESS);
      std::memcpy(both.data() + k * kW * kH, p, kW * kH * sizeof(Float4));
      ASSERT_EQ(rtBufferUnmap(outs[k]), RT_SUCCESS);
    }
    // The declared sampler and the bindless id read the same texture the same way.
    EXPECT_EQ(std::memcmp(both.data(), both.data() + kW * kH, kW * kH * sizeof(Float4)), 0) << spec;
    results.push_back(std::move(both));
    ASSERT_EQ(rtContextDestroy(ctx), RT_SUCCESS);
  }
  // Filtering really happened: some output lies strictly between texels.
  bool blended = false;
  for (const Float4& v : results[0]) blended |= v[3] > 0.f && v[3] < 1.f;
  EXPECT_TRUE(blended);
  for (size_t k = 1; k < results.size(); ++k) {
    EXPECT_EQ(std::memcmp(results[0].data(), results[k].data(), results[0].size() * sizeof(Float4)),
              0)
        << "device set " << k << " differs from inproc";
  }
}

}  // namespace
}  // namespace tessera::testing

// Texture samplers and buffer mip levels through the C API: every property's default and round
// trip, bad enum values, deprecated arguments, validation of what a sampler reads, ids, variables.
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "api_test_util.h"
#include "gtest/gtest.h"
#include "tessera/rt.h"

namespace tessera::test {
namespace {

class HostTextureTest : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_EQ(rtContextCreate(&ctx), RT_SUCCESS);
    ASSERT_EQ(rtTextureSamplerCreate(ctx, &sampler), RT_SUCCESS);
  }
  void TearDown() override { EXPECT_EQ(rtContextDestroy(ctx), RT_SUCCESS); }

  RTbuffer Buffer(unsigned desc, RTformat format, std::vector<RTsize> dims) {
    RTbuffer b = nullptr;
    EXPECT_EQ(rtBufferCreate(ctx, desc, &b), RT_SUCCESS);
    EXPECT_EQ(rtBufferSetFormat(b, format), RT_SUCCESS);
    EXPECT_EQ(rtBufferSetSizev(b, static_cast<unsigned>(dims.size()), dims.data()), RT_SUCCESS);
    return b;
  }

  // `code`, and a message from `fn` that says `words`.
  void ExpectError(RTresult got, RTresult code, const char* fn, const char* words) {
    EXPECT_EQ(got, code) << fn;
    const std::string message = ErrorString(ctx, code);
    EXPECT_EQ(message.rfind(fn, 0), 0u) << message;
    EXPECT_NE(message.find(words), std::string::npos) << message;
  }

  RTcontext ctx = nullptr;
  RTtexturesampler sampler = nullptr;
};

TEST_F(HostTextureTest, DefaultsAreOptixs) {
  RTwrapmode wrap[3];
  for (unsigned d = 0; d < 3; ++d) {
    ASSERT_EQ(rtTextureSamplerGetWrapMode(sampler, d, &wrap[d]), RT_SUCCESS);
    EXPECT_EQ(wrap[d], RT_WRAP_REPEAT);
  }
  RTfiltermode mn, mg, mp;
  ASSERT_EQ(rtTextureSamplerGetFilteringModes(sampler, &mn, &mg, &mp), RT_SUCCESS);
  EXPECT_EQ(mn, RT_FILTER_LINEAR);
  EXPECT_EQ(mg, RT_FILTER_LINEAR);
  EXPECT_EQ(mp, RT_FILTER_NONE);
  float f = 0.f, g = 0.f;
  ASSERT_EQ(rtTextureSamplerGetMaxAnisotropy(sampler, &f), RT_SUCCESS);
  EXPECT_EQ(f, 1.f);
  ASSERT_EQ(rtTextureSamplerGetMipLevelClamp(sampler, &f, &g), RT_SUCCESS);
  EXPECT_EQ(f, 0.f);
  EXPECT_EQ(g, 0.f);
  ASSERT_EQ(rtTextureSamplerGetMipLevelBias(sampler, &f), RT_SUCCESS);
  EXPECT_EQ(f, 0.f);
  RTtexturereadmode read;
  ASSERT_EQ(rtTextureSamplerGetReadMode(sampler, &read), RT_SUCCESS);
  EXPECT_EQ(read, RT_TEXTURE_READ_NORMALIZED_FLOAT);
  RTtextureindexmode index;
  ASSERT_EQ(rtTextureSamplerGetIndexingMode(sampler, &index), RT_SUCCESS);
  EXPECT_EQ(index, RT_TEXTURE_INDEX_NORMALIZED_COORDINATES);
  unsigned n = 0;
  ASSERT_EQ(rtTextureSamplerGetMipLevelCount(sampler, &n), RT_SUCCESS);
  EXPECT_EQ(n, 1u);
  ASSERT_EQ(rtTextureSamplerGetArraySize(sampler, &n), RT_SUCCESS);
  EXPECT_EQ(n, 1u);
  RTbuffer b = reinterpret_cast<RTbuffer>(&n);
  ASSERT_EQ(rtTextureSamplerGetBuffer(sampler, 0, 0, &b), RT_SUCCESS);
  EXPECT_EQ(b, nullptr);
  RTcontext c = nullptr;
  ASSERT_EQ(rtTextureSamplerGetContext(sampler, &c), RT_SUCCESS);
  EXPECT_EQ(c, ctx);
}

TEST_F(HostTextureTest, EveryPropertyRoundTrips) {
  const RTwrapmode modes[3] = {RT_WRAP_CLAMP_TO_EDGE, RT_WRAP_MIRROR, RT_WRAP_CLAMP_TO_BORDER};
  for (unsigned d = 0; d < 3; ++d) {
    ASSERT_EQ(rtTextureSamplerSetWrapMode(sampler, d, modes[d]), RT_SUCCESS);
  }
  for (unsigned d = 0; d < 3; ++d) {
    RTwrapmode got;
    ASSERT_EQ(rtTextureSamplerGetWrapMode(sampler, d, &got), RT_SUCCESS);
    EXPECT_EQ(got, modes[d]);
  }
  ASSERT_EQ(rtTextureSamplerSetFilteringModes(sampler, RT_FILTER_NEAREST, RT_FILTER_LINEAR,
                                              RT_FILTER_NEAREST),
            RT_SUCCESS);
  RTfiltermode mn, mg, mp;
  ASSERT_EQ(rtTextureSamplerGetFilteringModes(sampler, &mn, &mg, &mp), RT_SUCCESS);
  EXPECT_EQ(mn, RT_FILTER_NEAREST);
  EXPECT_EQ(mg, RT_FILTER_LINEAR);
  EXPECT_EQ(mp, RT_FILTER_NEAREST);

  float f = 0.f, g = 0.f;
  ASSERT_EQ(rtTextureSamplerSetMaxAnisotropy(sampler, 8.f), RT_SUCCESS);
  ASSERT_EQ(rtTextureSamplerGetMaxAnisotropy(sampler, &f), RT_SUCCESS);
  EXPECT_EQ(f, 8.f);
  // Clamped to [1, 16] as in OptiX.
  ASSERT_EQ(rtTextureSamplerSetMaxAnisotropy(sampler, 100.f), RT_SUCCESS);
  ASSERT_EQ(rtTextureSamplerGetMaxAnisotropy(sampler, &f), RT_SUCCESS);
  EXPECT_EQ(f, 16.f);
  ASSERT_EQ(rtTextureSamplerSetMaxAnisotropy(sampler, 0.f), RT_SUCCESS);
  ASSERT_EQ(rtTextureSamplerGetMaxAnisotropy(sampler, &f), RT_SUCCESS);
  EXPECT_EQ(f, 1.f);

  ASSERT_EQ(rtTextureSamplerSetMipLevelClamp(sampler, 1.f, 4.5f), RT_SUCCESS);
  ASSERT_EQ(rtTextureSamplerGetMipLevelClamp(sampler, &f, &g), RT_SUCCESS);
  EXPECT_EQ(f, 1.f);
  EXPECT_EQ(g, 4.5f);
  ASSERT_EQ(rtTextureSamplerSetMipLevelBias(sampler, -0.25f), RT_SUCCESS);
  ASSERT_EQ(rtTextureSamplerGetMipLevelBias(sampler, &f), RT_SUCCESS);
  EXPECT_EQ(f, -0.25f);

  for (RTtexturereadmode mode :
       {RT_TEXTURE_READ_ELEMENT_TYPE, RT_TEXTURE_READ_NORMALIZED_FLOAT,
        RT_TEXTURE_READ_ELEMENT_TYPE_SRGB, RT_TEXTURE_READ_NORMALIZED_FLOAT_SRGB}) {
    RTtexturereadmode got;
    ASSERT_EQ(rtTextureSamplerSetReadMode(sampler, mode), RT_SUCCESS);
    ASSERT_EQ(rtTextureSamplerGetReadMode(sampler, &got), RT_SUCCESS);
    EXPECT_EQ(got, mode);
  }
  RTtextureindexmode index;
  ASSERT_EQ(rtTextureSamplerSetIndexingMode(sampler, RT_TEXTURE_INDEX_ARRAY_INDEX), RT_SUCCESS);
  ASSERT_EQ(rtTextureSamplerGetIndexingMode(sampler, &index), RT_SUCCESS);
  EXPECT_EQ(index, RT_TEXTURE_INDEX_ARRAY_INDEX);

  RTbuffer b = Buffer(RT_BUFFER_INPUT, RT_FORMAT_FLOAT4, {4, 4});
  ASSERT_EQ(rtTextureSamplerSetBuffer(sampler, 0, 0, b), RT_SUCCESS);
  RTbuffer got = nullptr;
  ASSERT_EQ(rtTextureSamplerGetBuffer(sampler, 0, 0, &got), RT_SUCCESS);
  EXPECT_EQ(got, b);
  EXPECT_EQ(rtTextureSamplerValidate(sampler), RT_SUCCESS);
}

TEST_F(HostTextureTest, BadValuesAreRefusedNamingTheSampler) {
  ExpectError(rtTextureSamplerSetWrapMode(sampler, 3, RT_WRAP_REPEAT), RT_ERROR_INVALID_VALUE,
              "rtTextureSamplerSetWrapMode(texture sampler #", "dimension 3");
  ExpectError(rtTextureSamplerSetWrapMode(sampler, 0, static_cast<RTwrapmode>(9)),
              RT_ERROR_INVALID_VALUE, "rtTextureSamplerSetWrapMode", "wrap mode 9");
  RTwrapmode wrap;
  ExpectError(rtTextureSamplerGetWrapMode(sampler, 5, &wrap), RT_ERROR_INVALID_VALUE,
              "rtTextureSamplerGetWrapMode", "dimension 5");
  ExpectError(
      rtTextureSamplerSetFilteringModes(sampler, RT_FILTER_NONE, RT_FILTER_LINEAR, RT_FILTER_NONE),
      RT_ERROR_INVALID_VALUE, "rtTextureSamplerSetFilteringModes", "minification");
  ExpectError(rtTextureSamplerSetFilteringModes(sampler, RT_FILTER_LINEAR, RT_FILTER_LINEAR,
                                                static_cast<RTfiltermode>(7)),
              RT_ERROR_INVALID_VALUE, "rtTextureSamplerSetFilteringModes", "mipmapping filter 7");
  ExpectError(rtTextureSamplerSetReadMode(sampler, static_cast<RTtexturereadmode>(4)),
              RT_ERROR_INVALID_VALUE, "rtTextureSamplerSetReadMode", "read mode 4");
  ExpectError(rtTextureSamplerSetIndexingMode(sampler, static_cast<RTtextureindexmode>(-1)),
              RT_ERROR_INVALID_VALUE, "rtTextureSamplerSetIndexingMode", "indexing mode -1");
  ExpectError(rtTextureSamplerSetMipLevelClamp(sampler, 3.f, 1.f), RT_ERROR_INVALID_VALUE,
              "rtTextureSamplerSetMipLevelClamp", "0 <= min <= max");
  ExpectError(rtTextureSamplerSetMipLevelBias(sampler, std::numeric_limits<float>::infinity()),
              RT_ERROR_INVALID_VALUE, "rtTextureSamplerSetMipLevelBias", "not finite");
  // Deprecated in OptiX 3.9: texture arrays and per-sampler mip levels.
  ExpectError(rtTextureSamplerSetMipLevelCount(sampler, 3), RT_ERROR_INVALID_VALUE,
              "rtTextureSamplerSetMipLevelCount", "rtBufferSetMipLevelCount");
  ExpectError(rtTextureSamplerSetArraySize(sampler, 2), RT_ERROR_INVALID_VALUE,
              "rtTextureSamplerSetArraySize", "RT_BUFFER_LAYERED");
  RTbuffer b = Buffer(RT_BUFFER_INPUT, RT_FORMAT_FLOAT, {4});
  ExpectError(rtTextureSamplerSetBuffer(sampler, 1, 0, b), RT_ERROR_INVALID_VALUE,
              "rtTextureSamplerSetBuffer", "texture array index 1");
  ExpectError(rtTextureSamplerSetBuffer(sampler, 0, 2, b), RT_ERROR_INVALID_VALUE,
              "rtTextureSamplerSetBuffer", "mip level 2");
  // Nothing above changed the sampler.
  RTbuffer got = b;
  ASSERT_EQ(rtTextureSamplerGetBuffer(sampler, 0, 0, &got), RT_SUCCESS);
  EXPECT_EQ(got, nullptr);
  RTtexturereadmode read;
  ASSERT_EQ(rtTextureSamplerGetReadMode(sampler, &read), RT_SUCCESS);
  EXPECT_EQ(read, RT_TEXTURE_READ_NORMALIZED_FLOAT);
}

TEST_F(HostTextureTest, AnOutputBufferIsRefused) {
  RTbuffer out = Buffer(RT_BUFFER_OUTPUT, RT_FORMAT_FLOAT4, {4, 4});
  ExpectError(rtTextureSamplerSetBuffer(sampler, 0, 0, out), RT_ERROR_INVALID_VALUE,
              "rtTextureSamplerSetBuffer(texture sampler #", "RT_BUFFER_OUTPUT");
  RTbuffer io = Buffer(RT_BUFFER_INPUT_OUTPUT, RT_FORMAT_FLOAT4, {4, 4});
  EXPECT_EQ(rtTextureSamplerSetBuffer(sampler, 0, 0, io), RT_SUCCESS);
}

TEST_F(HostTextureTest, ValidationSaysWhatTheSamplerCannotRead) {
  ExpectError(rtTextureSamplerValidate(sampler), RT_ERROR_INVALID_VALUE,
              "rtTextureSamplerValidate(texture sampler #", "buffer is not set");
  struct Case {
    unsigned desc;
    RTformat format;
    std::vector<RTsize> dims;
    const char* says;
  };
  const Case cases[] = {
      {RT_BUFFER_INPUT, RT_FORMAT_USER, {4}, "RT_FORMAT_USER"},
      {RT_BUFFER_INPUT, RT_FORMAT_BUFFER_ID, {4}, "RT_FORMAT_BUFFER_ID"},
      {RT_BUFFER_INPUT | RT_BUFFER_CUBEMAP, RT_FORMAT_FLOAT4, {8, 4, 6}, "faces must be square"},
      {RT_BUFFER_INPUT | RT_BUFFER_CUBEMAP, RT_FORMAT_FLOAT4, {8, 8, 5}, "the depth 6"},
      {RT_BUFFER_INPUT | RT_BUFFER_CUBEMAP | RT_BUFFER_LAYERED,
       RT_FORMAT_FLOAT4,
       {8, 8, 9},
       "a multiple of 6"},
      {RT_BUFFER_INPUT | RT_BUFFER_LAYERED, RT_FORMAT_FLOAT4, {8, 8}, "must be 3D"},
  };
  for (const Case& c : cases) {
    RTbuffer b = nullptr;
    ASSERT_EQ(rtBufferCreate(ctx, c.desc, &b), RT_SUCCESS);
    ASSERT_EQ(rtBufferSetFormat(b, c.format), RT_SUCCESS);
    if (c.format == RT_FORMAT_USER) {
      ASSERT_EQ(rtBufferSetElementSize(b, 8), RT_SUCCESS);
    }
    ASSERT_EQ(rtBufferSetSizev(b, static_cast<unsigned>(c.dims.size()), c.dims.data()), RT_SUCCESS);
    ASSERT_EQ(rtTextureSamplerSetBuffer(sampler, 0, 0, b), RT_SUCCESS);
    ExpectError(rtTextureSamplerValidate(sampler), RT_ERROR_INVALID_VALUE,
                "rtTextureSamplerValidate(texture sampler #", c.says);
  }
  // Good shapes: a cube map, 2 layers of cube map, a layered 2D texture.
  for (const Case& c :
       {Case{RT_BUFFER_INPUT | RT_BUFFER_CUBEMAP, RT_FORMAT_HALF4, {8, 8, 6}, ""},
        Case{RT_BUFFER_INPUT | RT_BUFFER_CUBEMAP | RT_BUFFER_LAYERED,
             RT_FORMAT_UNSIGNED_BYTE4,
             {8, 8, 12},
             ""},
        Case{RT_BUFFER_INPUT | RT_BUFFER_LAYERED, RT_FORMAT_SHORT2, {8, 4, 3}, ""}}) {
    ASSERT_EQ(rtTextureSamplerSetBuffer(sampler, 0, 0, Buffer(c.desc, c.format, c.dims)),
              RT_SUCCESS);
    EXPECT_EQ(rtTextureSamplerValidate(sampler), RT_SUCCESS) << ErrorString(ctx, RT_ERROR_UNKNOWN);
  }
}

TEST_F(HostTextureTest, EveryNumericFormatIsReadable) {
  for (int f = RT_FORMAT_FLOAT; f <= RT_FORMAT_UNSIGNED_INT4; ++f) {
    ASSERT_EQ(rtTextureSamplerSetBuffer(sampler, 0, 0,
                                        Buffer(RT_BUFFER_INPUT, static_cast<RTformat>(f), {2, 2})),
              RT_SUCCESS);
    EXPECT_EQ(rtTextureSamplerValidate(sampler), RT_SUCCESS) << "format 0x" << std::hex << f;
  }
  const std::pair<RTformat, RTsize> halves[] = {
      {RT_FORMAT_HALF, 2}, {RT_FORMAT_HALF2, 4}, {RT_FORMAT_HALF3, 6}, {RT_FORMAT_HALF4, 8}};
  for (const auto& [format, size] : halves) {
    RTbuffer b = Buffer(RT_BUFFER_INPUT, format, {2, 2});
    RTsize element = 0;
    ASSERT_EQ(rtBufferGetElementSize(b, &element), RT_SUCCESS);
    EXPECT_EQ(element, size);
    ASSERT_EQ(rtTextureSamplerSetBuffer(sampler, 0, 0, b), RT_SUCCESS);
    EXPECT_EQ(rtTextureSamplerValidate(sampler), RT_SUCCESS);
  }
}

TEST_F(HostTextureTest, ALaunchValidatesSamplersItReaches) {
  RTvariable v = nullptr;
  ASSERT_EQ(rtContextDeclareVariable(ctx, "tex", &v), RT_SUCCESS);
  ASSERT_EQ(rtVariableSetObject(v, sampler), RT_SUCCESS);
  ExpectError(rtContextValidate(ctx), RT_ERROR_INVALID_CONTEXT, "rtContextValidate",
              "texture sampler #");
  // A sampler no variable names is checked once programs can reach it by id.
  RTtexturesampler loose = nullptr;
  ASSERT_EQ(rtTextureSamplerCreate(ctx, &loose), RT_SUCCESS);
  ASSERT_EQ(rtTextureSamplerSetBuffer(sampler, 0, 0, Buffer(RT_BUFFER_INPUT, RT_FORMAT_FLOAT, {4})),
            RT_SUCCESS);
  EXPECT_EQ(rtContextValidate(ctx), RT_SUCCESS) << ErrorString(ctx, RT_ERROR_INVALID_CONTEXT);
  int id = 0;
  ASSERT_EQ(rtTextureSamplerGetId(loose, &id), RT_SUCCESS);
  ExpectError(rtContextValidate(ctx), RT_ERROR_INVALID_CONTEXT, "rtContextValidate",
              "buffer is not set");
}

TEST_F(HostTextureTest, IdsRoundTrip) {
  int id = 0;
  ASSERT_EQ(rtTextureSamplerGetId(sampler, &id), RT_SUCCESS);
  EXPECT_NE(id, 0);  // RT_TEXTURE_ID_NULL
  RTtexturesampler found = nullptr;
  ASSERT_EQ(rtContextGetTextureSamplerFromId(ctx, id, &found), RT_SUCCESS);
  EXPECT_EQ(found, sampler);
  // A buffer's id names no sampler, nor do 0 and ids never given.
  RTbuffer b = Buffer(RT_BUFFER_INPUT, RT_FORMAT_FLOAT, {4});
  int buffer_id = 0;
  ASSERT_EQ(rtBufferGetId(b, &buffer_id), RT_SUCCESS);
  for (int bad : {buffer_id, 0, -3, 1 << 30}) {
    ExpectError(rtContextGetTextureSamplerFromId(ctx, bad, &found), RT_ERROR_INVALID_VALUE,
                "rtContextGetTextureSamplerFromId", "no live texture sampler has id");
  }
  ASSERT_EQ(rtTextureSamplerDestroy(sampler), RT_SUCCESS);
  EXPECT_EQ(rtContextGetTextureSamplerFromId(ctx, id, &found), RT_ERROR_INVALID_VALUE);
}

TEST_F(HostTextureTest, VariablesHoldSamplers) {
  RTvariable v = nullptr;
  ASSERT_EQ(rtContextDeclareVariable(ctx, "tex", &v), RT_SUCCESS);
  ASSERT_EQ(rtVariableSetObject(v, sampler), RT_SUCCESS);
  RTobjecttype type;
  ASSERT_EQ(rtVariableGetType(v, &type), RT_SUCCESS);
  EXPECT_EQ(type, RT_OBJECTTYPE_TEXTURE_SAMPLER);
  RTobject o = nullptr;
  ASSERT_EQ(rtVariableGetObject(v, &o), RT_SUCCESS);
  EXPECT_EQ(o, sampler);
  // Another sampler may replace it; a buffer may not (the first set fixes the kind).
  RTtexturesampler other = nullptr;
  ASSERT_EQ(rtTextureSamplerCreate(ctx, &other), RT_SUCCESS);
  EXPECT_EQ(rtVariableSetObject(v, other), RT_SUCCESS);
  EXPECT_EQ(rtVariableSetObject(v, Buffer(RT_BUFFER_INPUT, RT_FORMAT_FLOAT, {1})),
            RT_ERROR_TYPE_MISMATCH);
  float f = 0.f;
  EXPECT_EQ(rtVariableGet1f(v, &f), RT_ERROR_TYPE_MISMATCH);
}

// ---- Buffer mip levels ------------------------------------------------------------------------

TEST_F(HostTextureTest, MipLevelSizesHalveToOne) {
  RTbuffer b = Buffer(RT_BUFFER_INPUT, RT_FORMAT_FLOAT, {8, 4});
  unsigned n = 0;
  ASSERT_EQ(rtBufferGetMipLevelCount(b, &n), RT_SUCCESS);
  EXPECT_EQ(n, 1u);
  ASSERT_EQ(rtBufferSetMipLevelCount(b, 4), RT_SUCCESS);
  ASSERT_EQ(rtBufferGetMipLevelCount(b, &n), RT_SUCCESS);
  EXPECT_EQ(n, 4u);
  const RTsize want[4][2] = {{8, 4}, {4, 2}, {2, 1}, {1, 1}};
  for (unsigned level = 0; level < 4; ++level) {
    RTsize w = 0, h = 0;
    ASSERT_EQ(rtBufferGetMipLevelSize2D(b, level, &w, &h), RT_SUCCESS);
    EXPECT_EQ(w, want[level][0]) << level;
    EXPECT_EQ(h, want[level][1]) << level;
  }
  RTsize w = 0, h = 0, d = 0;
  ExpectError(rtBufferGetMipLevelSize2D(b, 4, &w, &h), RT_ERROR_INVALID_VALUE,
              "rtBufferGetMipLevelSize2D(buffer #", "mip level 4");
  ExpectError(rtBufferGetMipLevelSize3D(b, 0, &w, &h, &d), RT_ERROR_INVALID_VALUE,
              "rtBufferGetMipLevelSize3D", "2D, not 3D");
  ExpectError(rtBufferSetMipLevelCount(b, 5), RT_ERROR_INVALID_VALUE, "rtBufferSetMipLevelCount",
              "at most 4 mip levels");
  ExpectError(rtBufferSetMipLevelCount(b, 0), RT_ERROR_INVALID_VALUE, "rtBufferSetMipLevelCount",
              "mip level count 0");
  // A resize that leaves too few texels for the levels is refused.
  ExpectError(rtBufferSetSize2D(b, 2, 2), RT_ERROR_INVALID_VALUE, "rtBufferSetSize2D",
              "at most 2 mip levels");
}

TEST_F(HostTextureTest, LayeredAndCubeMapDepthStays) {
  RTbuffer b = Buffer(RT_BUFFER_INPUT | RT_BUFFER_CUBEMAP, RT_FORMAT_UNSIGNED_BYTE4, {16, 16, 6});
  ASSERT_EQ(rtBufferSetMipLevelCount(b, 5), RT_SUCCESS);
  RTsize w = 0, h = 0, d = 0;
  ASSERT_EQ(rtBufferGetMipLevelSize3D(b, 4, &w, &h, &d), RT_SUCCESS);
  EXPECT_EQ(w, 1u);
  EXPECT_EQ(h, 1u);
  EXPECT_EQ(d, 6u);
  RTbuffer volume = Buffer(RT_BUFFER_INPUT, RT_FORMAT_FLOAT, {4, 4, 4});
  ASSERT_EQ(rtBufferSetMipLevelCount(volume, 3), RT_SUCCESS);
  ASSERT_EQ(rtBufferGetMipLevelSize3D(volume, 2, &w, &h, &d), RT_SUCCESS);
  EXPECT_EQ(d, 1u);
}

TEST_F(HostTextureTest, MapExMapsOneLevelAtItsPlace) {
  RTbuffer b = Buffer(RT_BUFFER_INPUT, RT_FORMAT_FLOAT, {4, 4});
  ASSERT_EQ(rtBufferSetMipLevelCount(b, 3), RT_SUCCESS);
  void* levels[3] = {};
  for (unsigned l = 0; l < 3; ++l) {
    ASSERT_EQ(rtBufferMapEx(b, RT_BUFFER_MAP_WRITE_DISCARD, l, nullptr, &levels[l]), RT_SUCCESS);
  }
  // Level 0 (16 floats), then level 1 (4), then level 2 (1).
  EXPECT_EQ(static_cast<float*>(levels[1]) - static_cast<float*>(levels[0]), 16);
  EXPECT_EQ(static_cast<float*>(levels[2]) - static_cast<float*>(levels[1]), 4);
  static_cast<float*>(levels[2])[0] = 42.f;
  void* again = nullptr;
  ExpectError(rtBufferMapEx(b, RT_BUFFER_MAP_READ, 2, nullptr, &again), RT_ERROR_ALREADY_MAPPED,
              "rtBufferMapEx", "mip level 2 is already mapped");
  for (unsigned l = 0; l < 3; ++l) ASSERT_EQ(rtBufferUnmapEx(b, l), RT_SUCCESS);
  ExpectError(rtBufferUnmapEx(b, 1), RT_ERROR_INVALID_VALUE, "rtBufferUnmapEx", "not mapped");
  ExpectError(rtBufferMapEx(b, 3, 0, nullptr, &again), RT_ERROR_INVALID_VALUE, "rtBufferMapEx",
              "RT_BUFFER_MAP_");
  float mine[16];
  ExpectError(rtBufferMapEx(b, RT_BUFFER_MAP_READ, 0, mine, &again), RT_ERROR_INVALID_VALUE,
              "rtBufferMapEx", "user_owned");
  ExpectError(rtBufferMapEx(b, RT_BUFFER_MAP_READ, 3, nullptr, &again), RT_ERROR_INVALID_VALUE,
              "rtBufferMapEx", "mip level 3");
  ASSERT_EQ(rtBufferMapEx(b, RT_BUFFER_MAP_READ, 2, nullptr, &again), RT_SUCCESS);
  EXPECT_EQ(static_cast<float*>(again)[0], 42.f);
  ASSERT_EQ(rtBufferUnmapEx(b, 2), RT_SUCCESS);
}

}  // namespace
}  // namespace tessera::test

// Buffers on the device: every RTformat through an INPUT → program → OUTPUT round trip,
// INPUT_OUTPUT across launches, 2D/3D indexing, size(), and atomics on shared elements.
#include <cstdint>
#include <numeric>
#include <string>

#include "rt_fixture.h"

namespace tessera::testing {
namespace {

constexpr char kModule[] = "buffer_programs";

struct FormatCase {
  const char* name;  // program suffix
  RTformat format;
  size_t element_size;
};

const FormatCase kFormats[] = {
    {"float1", RT_FORMAT_FLOAT, 4},
    {"float2", RT_FORMAT_FLOAT2, 8},
    {"float3", RT_FORMAT_FLOAT3, 12},
    {"float4", RT_FORMAT_FLOAT4, 16},
    {"byte1", RT_FORMAT_BYTE, 1},
    {"byte4", RT_FORMAT_BYTE4, 4},
    {"ubyte1", RT_FORMAT_UNSIGNED_BYTE, 1},
    {"ubyte3", RT_FORMAT_UNSIGNED_BYTE3, 3},
    {"ubyte4", RT_FORMAT_UNSIGNED_BYTE4, 4},
    {"short1", RT_FORMAT_SHORT, 2},
    {"short2", RT_FORMAT_SHORT2, 4},
    {"ushort1", RT_FORMAT_UNSIGNED_SHORT, 2},
    {"ushort4", RT_FORMAT_UNSIGNED_SHORT4, 8},
    {"int1", RT_FORMAT_INT, 4},
    {"int3", RT_FORMAT_INT3, 12},
    {"uint1", RT_FORMAT_UNSIGNED_INT, 4},
    {"uint2", RT_FORMAT_UNSIGNED_INT2, 8},
    {"uint4", RT_FORMAT_UNSIGNED_INT4, 16},
    {"user", RT_FORMAT_USER, 20},
};

class BufferFormatTest : public RtFixture, public ::testing::WithParamInterface<FormatCase> {};

TEST_P(BufferFormatTest, InputReachesTheProgramAndOutputComesBack) {
  const FormatCase& f = GetParam();
  constexpr size_t kCount = 37;
  Ok(rtContextSetEntryPointCount(ctx_, 1));
  RTprogram copy = Program(kModule, std::string("copy_") + f.name);
  Ok(rtContextSetRayGenerationProgram(ctx_, 0, copy));
  RTbuffer in = nullptr, out = nullptr;
  Ok(rtBufferCreate(ctx_, RT_BUFFER_INPUT, &in));
  Ok(rtBufferCreate(ctx_, RT_BUFFER_OUTPUT, &out));
  for (RTbuffer b : {in, out}) {
    Ok(rtBufferSetFormat(b, f.format));
    if (f.format == RT_FORMAT_USER) Ok(rtBufferSetElementSize(b, f.element_size));
    Ok(rtBufferSetSize1D(b, kCount));
  }
  std::vector<unsigned char> bytes(kCount * f.element_size);
  for (size_t i = 0; i < bytes.size(); ++i) bytes[i] = static_cast<unsigned char>(i * 7 + 3);
  void* p = nullptr;
  Ok(rtBufferMap(in, &p));
  std::memcpy(p, bytes.data(), bytes.size());
  Ok(rtBufferUnmap(in));
  RTvariable vin = nullptr, vout = nullptr;
  Ok(rtProgramDeclareVariable(copy, (std::string("in_") + f.name).c_str(), &vin));
  Ok(rtProgramDeclareVariable(copy, (std::string("out_") + f.name).c_str(), &vout));
  Ok(rtVariableSetObject(vin, in));
  Ok(rtVariableSetObject(vout, out));
  Ok(rtContextLaunch1D(ctx_, 0, kCount));
  Ok(rtBufferMap(out, &p));
  EXPECT_EQ(std::memcmp(p, bytes.data(), bytes.size()), 0);
  Ok(rtBufferUnmap(out));
}

INSTANTIATE_TEST_SUITE_P(AllFormats, BufferFormatTest, ::testing::ValuesIn(kFormats),
                         [](const auto& info) { return std::string(info.param.name); });

class BufferTest : public RtFixture {
 protected:
  void SetUp() override {
    RtFixture::SetUp();
    Ok(rtContextSetEntryPointCount(ctx_, 1));
  }
  RTbuffer Make(unsigned type, RTformat format, std::vector<RTsize> dims, const char* name) {
    RTbuffer b = nullptr;
    EXPECT_EQ(rtBufferCreate(ctx_, type, &b), RT_SUCCESS);
    EXPECT_EQ(rtBufferSetFormat(b, format), RT_SUCCESS);
    EXPECT_EQ(rtBufferSetSizev(b, static_cast<unsigned>(dims.size()), dims.data()), RT_SUCCESS);
    EXPECT_EQ(rtVariableSetObject(ContextVar(name), b), RT_SUCCESS);
    return b;
  }
  template <typename T>
  std::vector<T> Contents(RTbuffer b, size_t count) {
    void* p = nullptr;
    std::vector<T> v(count);
    EXPECT_EQ(rtBufferMap(b, &p), RT_SUCCESS);
    std::memcpy(v.data(), p, count * sizeof(T));
    EXPECT_EQ(rtBufferUnmap(b), RT_SUCCESS);
    return v;
  }
};

TEST_F(BufferTest, InputOutputKeepsDeviceWritesAcrossLaunchesAndSeesHostWrites) {
  RTbuffer counter = Make(RT_BUFFER_INPUT_OUTPUT, RT_FORMAT_INT, {5}, "counter");
  Ok(rtContextSetRayGenerationProgram(ctx_, 0, Program(kModule, "increment")));
  for (int i = 0; i < 3; ++i) Ok(rtContextLaunch1D(ctx_, 0, 5));
  EXPECT_EQ(Contents<int>(counter, 5), std::vector<int>(5, 3));
  void* p = nullptr;
  Ok(rtBufferMap(counter, &p));
  static_cast<int*>(p)[2] = 100;
  Ok(rtBufferUnmap(counter));
  Ok(rtContextLaunch1D(ctx_, 0, 5));
  EXPECT_EQ(Contents<int>(counter, 5), (std::vector<int>{4, 4, 101, 4, 4}));
}

TEST_F(BufferTest, TwoAndThreeDimensionalIndexing) {
  RTbuffer g2 = Make(RT_BUFFER_OUTPUT, RT_FORMAT_UNSIGNED_INT2, {5, 3}, "grid2");
  Ok(rtContextSetRayGenerationProgram(ctx_, 0, Program(kModule, "write_index2")));
  Ok(rtContextLaunch2D(ctx_, 0, 5, 3));
  std::vector<std::array<unsigned, 2>> v2 = Contents<std::array<unsigned, 2>>(g2, 15);
  for (unsigned y = 0; y < 3; ++y)
    for (unsigned x = 0; x < 5; ++x) EXPECT_EQ(v2[y * 5 + x], (std::array<unsigned, 2>{x, y}));

  RTbuffer g3 = Make(RT_BUFFER_OUTPUT, RT_FORMAT_UNSIGNED_INT4, {4, 3, 2}, "grid3");
  Ok(rtContextSetRayGenerationProgram(ctx_, 0, Program(kModule, "write_index3")));
  Ok(rtContextLaunch3D(ctx_, 0, 4, 3, 2));
  auto v3 = Contents<std::array<unsigned, 4>>(g3, 24);
  for (unsigned z = 0; z < 2; ++z)
    for (unsigned y = 0; y < 3; ++y)
      for (unsigned x = 0; x < 4; ++x)
        EXPECT_EQ(v3[(z * 3 + y) * 4 + x], (std::array<unsigned, 4>{x, y, z, 7u}));
}

TEST_F(BufferTest, AtomicScatterIntoSharedElements) {
  RTbuffer h = Make(RT_BUFFER_OUTPUT, RT_FORMAT_UNSIGNED_INT, {4}, "histogram");
  Ok(rtContextSetRayGenerationProgram(ctx_, 0, Program(kModule, "scatter")));
  Ok(rtContextLaunch1D(ctx_, 0, 10000));
  EXPECT_EQ(Contents<unsigned>(h, 4), std::vector<unsigned>(4, 2500));
}

TEST_F(BufferTest, ElementSizeMismatchFailsTheLaunchNamingTheBuffer) {
  RTprogram copy = Program(kModule, "copy_float4");
  Ok(rtContextSetRayGenerationProgram(ctx_, 0, copy));
  Make(RT_BUFFER_INPUT, RT_FORMAT_FLOAT3, {4}, "in_float4");  // 12-byte elements
  Make(RT_BUFFER_OUTPUT, RT_FORMAT_FLOAT4, {4}, "out_float4");
  RTresult r = rtContextLaunch1D(ctx_, 0, 4);
  EXPECT_NE(r, RT_SUCCESS);
  EXPECT_NE(Error(r).find("in_float4"), std::string::npos) << Error(r);
}

}  // namespace
}  // namespace tessera::testing

// Buffers through the C API: every format, 1/2/3D and Sizev, map/unmap round trips, ids, rules.
#include <cstring>
#include <vector>

#include "api_test_util.h"
#include "gtest/gtest.h"
#include "tessera/rt.h"

namespace tessera::test {
namespace {

class HostBufferTest : public ::testing::Test {
 protected:
  void SetUp() override { ASSERT_EQ(rtContextCreate(&ctx), RT_SUCCESS); }
  void TearDown() override { EXPECT_EQ(rtContextDestroy(ctx), RT_SUCCESS); }

  RTbuffer Make(unsigned desc = RT_BUFFER_INPUT) {
    RTbuffer b = nullptr;
    EXPECT_EQ(rtBufferCreate(ctx, desc, &b), RT_SUCCESS);
    return b;
  }

  RTcontext ctx = nullptr;
};

struct FormatSize {
  RTformat format;
  RTsize size;
};

constexpr FormatSize kFormats[] = {
    {RT_FORMAT_FLOAT, 4},
    {RT_FORMAT_FLOAT2, 8},
    {RT_FORMAT_FLOAT3, 12},
    {RT_FORMAT_FLOAT4, 16},
    {RT_FORMAT_BYTE, 1},
    {RT_FORMAT_BYTE2, 2},
    {RT_FORMAT_BYTE3, 3},
    {RT_FORMAT_BYTE4, 4},
    {RT_FORMAT_UNSIGNED_BYTE, 1},
    {RT_FORMAT_UNSIGNED_BYTE2, 2},
    {RT_FORMAT_UNSIGNED_BYTE3, 3},
    {RT_FORMAT_UNSIGNED_BYTE4, 4},
    {RT_FORMAT_SHORT, 2},
    {RT_FORMAT_SHORT2, 4},
    {RT_FORMAT_SHORT3, 6},
    {RT_FORMAT_SHORT4, 8},
    {RT_FORMAT_UNSIGNED_SHORT, 2},
    {RT_FORMAT_UNSIGNED_SHORT2, 4},
    {RT_FORMAT_UNSIGNED_SHORT3, 6},
    {RT_FORMAT_UNSIGNED_SHORT4, 8},
    {RT_FORMAT_INT, 4},
    {RT_FORMAT_INT2, 8},
    {RT_FORMAT_INT3, 12},
    {RT_FORMAT_INT4, 16},
    {RT_FORMAT_UNSIGNED_INT, 4},
    {RT_FORMAT_UNSIGNED_INT2, 8},
    {RT_FORMAT_UNSIGNED_INT3, 12},
    {RT_FORMAT_UNSIGNED_INT4, 16},
    {RT_FORMAT_BUFFER_ID, 4},
};

TEST_F(HostBufferTest, EveryFormatAndDimensionalityRoundTrips) {
  for (const FormatSize& f : kFormats) {
    for (unsigned dims = 1; dims <= 3; ++dims) {
      RTbuffer b = Make(RT_BUFFER_INPUT_OUTPUT);
      ASSERT_EQ(rtBufferSetFormat(b, f.format), RT_SUCCESS);
      RTformat format;
      ASSERT_EQ(rtBufferGetFormat(b, &format), RT_SUCCESS);
      EXPECT_EQ(format, f.format);
      RTsize element = 0;
      ASSERT_EQ(rtBufferGetElementSize(b, &element), RT_SUCCESS);
      EXPECT_EQ(element, f.size) << f.format;
      const RTsize size[3] = {5, 3, 2};
      RTsize count = 1;
      RTresult sized = dims == 1   ? rtBufferSetSize1D(b, size[0])
                       : dims == 2 ? rtBufferSetSize2D(b, size[0], size[1])
                                   : rtBufferSetSize3D(b, size[0], size[1], size[2]);
      ASSERT_EQ(sized, RT_SUCCESS);
      for (unsigned d = 0; d < dims; ++d) count *= size[d];
      unsigned got_dims = 0;
      ASSERT_EQ(rtBufferGetDimensionality(b, &got_dims), RT_SUCCESS);
      EXPECT_EQ(got_dims, dims);
      RTsize w = 0, h = 0, d = 0;
      ASSERT_EQ(rtBufferGetSize3D(b, &w, &h, &d), RT_SUCCESS);
      EXPECT_EQ(w, size[0]);
      EXPECT_EQ(h, dims >= 2 ? size[1] : 1);
      EXPECT_EQ(d, dims >= 3 ? size[2] : 1);

      // Contents start zeroed and survive a map/unmap round trip.
      void* p = nullptr;
      ASSERT_EQ(rtBufferMap(b, &p), RT_SUCCESS);
      std::vector<unsigned char> zeros(count * f.size, 0);
      EXPECT_EQ(std::memcmp(p, zeros.data(), zeros.size()), 0);
      for (size_t i = 0; i < zeros.size(); ++i) static_cast<unsigned char*>(p)[i] = i * 7 + 1;
      ASSERT_EQ(rtBufferUnmap(b), RT_SUCCESS);
      ASSERT_EQ(rtBufferMap(b, &p), RT_SUCCESS);
      for (size_t i = 0; i < zeros.size(); ++i) {
        ASSERT_EQ(static_cast<unsigned char*>(p)[i], static_cast<unsigned char>(i * 7 + 1));
      }
      ASSERT_EQ(rtBufferUnmap(b), RT_SUCCESS);
      EXPECT_EQ(rtBufferValidate(b), RT_SUCCESS);
      ASSERT_EQ(rtBufferDestroy(b), RT_SUCCESS);
    }
  }
}

TEST_F(HostBufferTest, UserFormatNeedsAnElementSize) {
  RTbuffer b = Make();
  ASSERT_EQ(rtBufferSetFormat(b, RT_FORMAT_USER), RT_SUCCESS);
  ASSERT_EQ(rtBufferSetSize1D(b, 4), RT_SUCCESS);
  void* p;
  EXPECT_EQ(rtBufferMap(b, &p), RT_ERROR_INVALID_VALUE);
  EXPECT_EQ(rtBufferValidate(b), RT_ERROR_INVALID_VALUE);
  EXPECT_NE(ErrorString(ctx, RT_ERROR_INVALID_VALUE).find("element size"), std::string::npos);
  EXPECT_EQ(rtBufferSetElementSize(b, 0), RT_ERROR_INVALID_VALUE);
  // More than devices accept is refused here, also while the buffer holds no elements.
  RTbuffer empty = Make();
  ASSERT_EQ(rtBufferSetFormat(empty, RT_FORMAT_USER), RT_SUCCESS);
  ASSERT_EQ(rtBufferSetSize2D(empty, 0, 0), RT_SUCCESS);
  EXPECT_EQ(rtBufferSetElementSize(empty, ~RTsize{0}), RT_ERROR_INVALID_VALUE);
  EXPECT_NE(ErrorString(ctx, RT_ERROR_INVALID_VALUE).find("the largest element devices accept"),
            std::string::npos);
  EXPECT_EQ(rtBufferSetElementSize(empty, RTsize{1} << 20), RT_SUCCESS);
  ASSERT_EQ(rtBufferSetElementSize(b, 20), RT_SUCCESS);
  RTsize element = 0;
  ASSERT_EQ(rtBufferGetElementSize(b, &element), RT_SUCCESS);
  EXPECT_EQ(element, 20u);
  ASSERT_EQ(rtBufferMap(b, &p), RT_SUCCESS);
  std::memset(p, 0xAB, 80);  // the whole 4 x 20 bytes are ours
  ASSERT_EQ(rtBufferUnmap(b), RT_SUCCESS);
  EXPECT_EQ(rtBufferValidate(b), RT_SUCCESS);

  RTbuffer f = Make();
  ASSERT_EQ(rtBufferSetFormat(f, RT_FORMAT_FLOAT), RT_SUCCESS);
  EXPECT_EQ(rtBufferSetElementSize(f, 4), RT_ERROR_INVALID_VALUE);  // only for USER
}

TEST_F(HostBufferTest, SizevMatchesFixedDimensionForms) {
  RTbuffer b = Make();
  ASSERT_EQ(rtBufferSetFormat(b, RT_FORMAT_INT), RT_SUCCESS);
  const RTsize dims[3] = {4, 6, 2};
  for (unsigned n = 1; n <= 3; ++n) {
    ASSERT_EQ(rtBufferSetSizev(b, n, dims), RT_SUCCESS);
    RTsize got[3] = {0, 0, 0};
    ASSERT_EQ(rtBufferGetSizev(b, n, got), RT_SUCCESS);
    for (unsigned i = 0; i < n; ++i) EXPECT_EQ(got[i], dims[i]);
    unsigned dimensionality = 0;
    ASSERT_EQ(rtBufferGetDimensionality(b, &dimensionality), RT_SUCCESS);
    EXPECT_EQ(dimensionality, n);
  }
  RTsize w = 0, h = 0;
  ASSERT_EQ(rtBufferGetSize2D(b, &w, &h), RT_SUCCESS);
  EXPECT_EQ(w, 4u);
  EXPECT_EQ(h, 6u);
  ASSERT_EQ(rtBufferGetSize1D(b, &w), RT_SUCCESS);
  EXPECT_EQ(w, 4u);
}

TEST_F(HostBufferTest, MapRules) {
  RTbuffer b = Make();
  void* p;
  EXPECT_EQ(rtBufferMap(b, &p), RT_ERROR_INVALID_VALUE);  // no format yet
  ASSERT_EQ(rtBufferSetFormat(b, RT_FORMAT_FLOAT4), RT_SUCCESS);
  ASSERT_EQ(rtBufferSetSize2D(b, 2, 2), RT_SUCCESS);
  EXPECT_EQ(rtBufferUnmap(b), RT_ERROR_INVALID_VALUE);
  EXPECT_NE(ErrorString(ctx, RT_ERROR_INVALID_VALUE).find("not mapped"), std::string::npos);
  ASSERT_EQ(rtBufferMap(b, &p), RT_SUCCESS);
  void* again;
  EXPECT_EQ(rtBufferMap(b, &again), RT_ERROR_ALREADY_MAPPED);
  EXPECT_EQ(rtBufferSetSize2D(b, 4, 4), RT_ERROR_ALREADY_MAPPED);
  std::string message = ErrorString(ctx, RT_ERROR_ALREADY_MAPPED);
  EXPECT_NE(message.find("rtBufferSetSize2D(buffer #"), std::string::npos) << message;
  EXPECT_NE(message.find("buffer is mapped"), std::string::npos) << message;
  EXPECT_EQ(rtBufferSetFormat(b, RT_FORMAT_INT), RT_ERROR_ALREADY_MAPPED);
  EXPECT_EQ(rtBufferValidate(b), RT_ERROR_ALREADY_MAPPED);
  ASSERT_EQ(rtBufferUnmap(b), RT_SUCCESS);
  EXPECT_EQ(rtBufferSetSize2D(b, 4, 4), RT_SUCCESS);
  // Zero-sized buffers still map to a usable pointer.
  ASSERT_EQ(rtBufferSetSize1D(b, 0), RT_SUCCESS);
  ASSERT_EQ(rtBufferMap(b, &p), RT_SUCCESS);
  EXPECT_NE(p, nullptr);
  ASSERT_EQ(rtBufferUnmap(b), RT_SUCCESS);
}

TEST_F(HostBufferTest, ResizeZeroesContents) {
  RTbuffer b = Make();
  ASSERT_EQ(rtBufferSetFormat(b, RT_FORMAT_UNSIGNED_INT), RT_SUCCESS);
  ASSERT_EQ(rtBufferSetSize1D(b, 8), RT_SUCCESS);
  void* p;
  ASSERT_EQ(rtBufferMap(b, &p), RT_SUCCESS);
  std::memset(p, 0xFF, 32);
  ASSERT_EQ(rtBufferUnmap(b), RT_SUCCESS);
  ASSERT_EQ(rtBufferSetSize1D(b, 16), RT_SUCCESS);
  ASSERT_EQ(rtBufferMap(b, &p), RT_SUCCESS);
  for (int i = 0; i < 16; ++i) EXPECT_EQ(static_cast<unsigned*>(p)[i], 0u);
  ASSERT_EQ(rtBufferUnmap(b), RT_SUCCESS);
}

// Sizes whose bytes would pass 2^46 (or wrap around 2^64) are refused by whichever call makes them
// so, and the buffer keeps its size, format and contents.
TEST_F(HostBufferTest, OversizedBuffersAreRefusedAndLeaveTheBufferAsItWas) {
  RTbuffer b = Make();
  ASSERT_EQ(rtBufferSetFormat(b, RT_FORMAT_USER), RT_SUCCESS);
  ASSERT_EQ(rtBufferSetElementSize(b, 4), RT_SUCCESS);
  ASSERT_EQ(rtBufferSetSize1D(b, 1000), RT_SUCCESS);
  void* p;
  ASSERT_EQ(rtBufferMap(b, &p), RT_SUCCESS);
  static_cast<unsigned*>(p)[999] = 42;
  ASSERT_EQ(rtBufferUnmap(b), RT_SUCCESS);

  auto unchanged = [&](const char* after) {
    SCOPED_TRACE(after);
    RTsize width = 0, element = 0;
    ASSERT_EQ(rtBufferGetSize1D(b, &width), RT_SUCCESS);
    ASSERT_EQ(rtBufferGetElementSize(b, &element), RT_SUCCESS);
    EXPECT_EQ(width, 1000u);
    EXPECT_EQ(element, 4u);
    ASSERT_EQ(rtBufferMap(b, &p), RT_SUCCESS);
    EXPECT_EQ(static_cast<unsigned*>(p)[999], 42u);
    ASSERT_EQ(rtBufferUnmap(b), RT_SUCCESS);
  };
  // 2^63 elements of 4 bytes wrap around 2^64.
  EXPECT_EQ(rtBufferSetSize1D(b, RTsize{1} << 63), RT_ERROR_INVALID_VALUE);
  EXPECT_NE(ErrorString(ctx, RT_ERROR_INVALID_VALUE).find("too large"), std::string::npos);
  unchanged("SetSize1D");
  EXPECT_EQ(rtBufferSetSize3D(b, RTsize{1} << 20, RTsize{1} << 20, RTsize{1} << 20),
            RT_ERROR_INVALID_VALUE);
  unchanged("SetSize3D");
  // 1000 elements of 2^60 bytes: refused for the element alone.
  EXPECT_EQ(rtBufferSetElementSize(b, RTsize{1} << 60), RT_ERROR_INVALID_VALUE);
  EXPECT_NE(ErrorString(ctx, RT_ERROR_INVALID_VALUE).find("exceeds 1048576 bytes"),
            std::string::npos)
      << ErrorString(ctx, RT_ERROR_INVALID_VALUE);
  unchanged("SetElementSize");
  // 2^40 elements of 1 MiB.
  ASSERT_EQ(rtBufferSetSize1D(b, 1), RT_SUCCESS);
  ASSERT_EQ(rtBufferSetElementSize(b, RTsize{1} << 20), RT_SUCCESS);
  EXPECT_EQ(rtBufferSetSize1D(b, RTsize{1} << 40), RT_ERROR_INVALID_VALUE);
  EXPECT_NE(ErrorString(ctx, RT_ERROR_INVALID_VALUE).find("too large"), std::string::npos)
      << ErrorString(ctx, RT_ERROR_INVALID_VALUE);
}

TEST_F(HostBufferTest, DescriptionRules) {
  RTbuffer b;
  EXPECT_EQ(rtBufferCreate(ctx, 0, &b), RT_ERROR_INVALID_VALUE);
  EXPECT_EQ(rtBufferCreate(ctx, RT_BUFFER_INPUT | RT_BUFFER_GPU_LOCAL, &b), RT_ERROR_INVALID_VALUE);
  EXPECT_NE(ErrorString(ctx, RT_ERROR_INVALID_VALUE).find("GPU_LOCAL"), std::string::npos);
  EXPECT_EQ(rtBufferCreate(ctx, RT_BUFFER_OUTPUT | RT_BUFFER_GPU_LOCAL, &b),
            RT_ERROR_INVALID_VALUE);
  EXPECT_EQ(rtBufferCreate(ctx, RT_BUFFER_INPUT | 0x100, &b), RT_ERROR_INVALID_VALUE);
  EXPECT_EQ(rtBufferCreate(ctx, RT_BUFFER_INPUT_OUTPUT | RT_BUFFER_GPU_LOCAL, &b), RT_SUCCESS);
  EXPECT_EQ(rtBufferCreate(ctx, RT_BUFFER_INPUT | RT_BUFFER_COPY_ON_DIRTY, &b), RT_SUCCESS);
  EXPECT_EQ(rtBufferMarkDirty(b), RT_SUCCESS);
  RTbuffer f = Make();
  EXPECT_EQ(rtBufferSetFormat(f, RT_FORMAT_UNKNOWN), RT_ERROR_INVALID_VALUE);
  EXPECT_EQ(rtBufferSetFormat(f, static_cast<RTformat>(0x999)), RT_ERROR_INVALID_VALUE);
  EXPECT_EQ(rtBufferSetSize3D(f, RTsize{1} << 40, RTsize{1} << 40, 2), RT_ERROR_INVALID_VALUE);
}

TEST_F(HostBufferTest, IdsAreUniqueAndResolve) {
  RTbuffer a = Make();
  RTbuffer b = Make();
  int ia = 0, ib = 0;
  ASSERT_EQ(rtBufferGetId(a, &ia), RT_SUCCESS);
  ASSERT_EQ(rtBufferGetId(b, &ib), RT_SUCCESS);
  EXPECT_GT(ia, 0);
  EXPECT_GT(ib, 0);
  EXPECT_NE(ia, ib);
  RTbuffer found = nullptr;
  ASSERT_EQ(rtContextGetBufferFromId(ctx, ib, &found), RT_SUCCESS);
  EXPECT_EQ(found, b);
  ASSERT_EQ(rtBufferDestroy(b), RT_SUCCESS);
  EXPECT_EQ(rtContextGetBufferFromId(ctx, ib, &found), RT_ERROR_INVALID_VALUE);
  EXPECT_EQ(rtContextGetBufferFromId(ctx, 0, &found), RT_ERROR_INVALID_VALUE);
  RTbuffer c = Make();
  int ic = 0;
  ASSERT_EQ(rtBufferGetId(c, &ic), RT_SUCCESS);
  EXPECT_GT(ic, ib);  // never reused
  RTcontext owner = nullptr;
  ASSERT_EQ(rtBufferGetContext(c, &owner), RT_SUCCESS);
  EXPECT_EQ(owner, ctx);
}

TEST_F(HostBufferTest, UsedHostMemoryCountsBufferBytes) {
  RTsize before = 0;
  ASSERT_EQ(
      rtContextGetAttribute(ctx, RT_CONTEXT_ATTRIBUTE_USED_HOST_MEMORY, sizeof(RTsize), &before),
      RT_SUCCESS);
  RTbuffer b = Make();
  ASSERT_EQ(rtBufferSetFormat(b, RT_FORMAT_FLOAT4), RT_SUCCESS);
  ASSERT_EQ(rtBufferSetSize2D(b, 10, 10), RT_SUCCESS);
  RTsize after = 0;
  ASSERT_EQ(
      rtContextGetAttribute(ctx, RT_CONTEXT_ATTRIBUTE_USED_HOST_MEMORY, sizeof(RTsize), &after),
      RT_SUCCESS);
  EXPECT_EQ(after - before, 1600u);
}

}  // namespace
}  // namespace tessera::test

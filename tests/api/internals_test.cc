// Small internal pieces: the Status↔RTresult table, content hashes, byte ranges, tiling,
// matrix inversion.
#include <cstring>

#include "byte_ranges.h"
#include "gtest/gtest.h"
#include "hash.h"
#include "matrix4.h"
#include "status.h"

namespace tessera::api {
namespace {

TEST(StatusTableTest, RoundTripsEveryResultCode) {
  const RTresult codes[] = {RT_TIMEOUT_CALLBACK,
                            RT_ERROR_INVALID_CONTEXT,
                            RT_ERROR_INVALID_VALUE,
                            RT_ERROR_MEMORY_ALLOCATION_FAILED,
                            RT_ERROR_TYPE_MISMATCH,
                            RT_ERROR_VARIABLE_NOT_FOUND,
                            RT_ERROR_VARIABLE_REDECLARED,
                            RT_ERROR_ILLEGAL_SYMBOL,
                            RT_ERROR_INVALID_SOURCE,
                            RT_ERROR_VERSION_MISMATCH,
                            RT_ERROR_OBJECT_CREATION_FAILED,
                            RT_ERROR_NO_DEVICE,
                            RT_ERROR_INVALID_DEVICE,
                            RT_ERROR_INVALID_IMAGE,
                            RT_ERROR_FILE_NOT_FOUND,
                            RT_ERROR_ALREADY_MAPPED,
                            RT_ERROR_LAUNCH_FAILED,
                            RT_ERROR_NOT_SUPPORTED,
                            RT_ERROR_CONNECTION_FAILED,
                            RT_ERROR_UNKNOWN};
  for (RTresult code : codes) {
    absl::Status s = RtError(code, "why");
    EXPECT_FALSE(s.ok());
    EXPECT_EQ(ToRtResult(s), code) << ResultText(code);
    EXPECT_EQ(s.message(), "why");
    EXPECT_NE(std::string(ResultText(code)).find("RT_"), std::string::npos);
  }
}

TEST(StatusTableTest, PlainStatusesMapByCode) {
  EXPECT_EQ(ToRtResult(absl::OkStatus()), RT_SUCCESS);
  EXPECT_EQ(ToRtResult(absl::InvalidArgumentError("x")), RT_ERROR_INVALID_VALUE);
  EXPECT_EQ(ToRtResult(absl::CancelledError("x")), RT_TIMEOUT_CALLBACK);
  EXPECT_EQ(ToRtResult(absl::InternalError("x")), RT_ERROR_LAUNCH_FAILED);
  EXPECT_EQ(ToRtResult(absl::UnavailableError("x")), RT_ERROR_CONNECTION_FAILED);
  EXPECT_EQ(ToRtResult(absl::UnimplementedError("x")), RT_ERROR_NOT_SUPPORTED);
  EXPECT_EQ(ToRtResult(absl::ResourceExhaustedError("x")), RT_ERROR_MEMORY_ALLOCATION_FAILED);
  EXPECT_EQ(ToRtResult(absl::FailedPreconditionError("x")), RT_ERROR_INVALID_CONTEXT);
  EXPECT_EQ(ToRtResult(absl::UnknownError("x")), RT_ERROR_UNKNOWN);
}

TEST(HashTest, MatchesXxh64ReferenceValues) {
  EXPECT_EQ(Hash64("", 0, 0), 0xEF46DB3751D8E999ULL);
  EXPECT_EQ(HashString("abc", 0), 0x44BC2CF5AD770999ULL);
  EXPECT_EQ(HexHash(0x1234), "0000000000001234");
}

TEST(HashTest, CoversEveryByteAndLength) {
  std::string a(1000, 'a');
  std::string b = a;
  b[999] = 'b';
  EXPECT_NE(HashString(a), HashString(b));
  EXPECT_NE(HashString(a.substr(0, 999)), HashString(a));
  for (size_t n : {1, 7, 8, 31, 32, 33, 63, 64, 65}) {
    EXPECT_NE(HashString(a.substr(0, n)), HashString(a.substr(0, n + 1))) << n;
  }
  EXPECT_NE(ChunkHash("", 0), 0u);
}

TEST(ByteRangesTest, MergesAndOverlaps) {
  ByteRanges r;
  EXPECT_TRUE(r.empty());
  r.Add(10, 20);
  r.Add(30, 40);
  r.Add(5, 5);  // empty
  EXPECT_EQ(r.ranges().size(), 2u);
  EXPECT_TRUE(r.Overlaps(15, 16));
  EXPECT_FALSE(r.Overlaps(20, 30));
  EXPECT_FALSE(r.Overlaps(0, 10));
  r.Add(20, 30);  // bridges both
  ASSERT_EQ(r.ranges().size(), 1u);
  EXPECT_EQ(r.ranges()[0], std::make_pair(uint64_t{10}, uint64_t{40}));
  r.Add(0, 100);
  ASSERT_EQ(r.ranges().size(), 1u);
  EXPECT_EQ(r.ranges()[0].second, 100u);
  r.Clear();
  EXPECT_TRUE(r.empty());
}

TEST(Matrix4Test, InvertsAndRejectsSingular) {
  Matrix4 m = {2, 0, 0, 1, 0, 4, 0, 2, 0, 0, 8, 3, 0, 0, 0, 1};
  Matrix4 inv;
  ASSERT_TRUE(Invert(m, &inv));
  EXPECT_FLOAT_EQ(inv[0], 0.5f);
  EXPECT_FLOAT_EQ(inv[3], -0.5f);
  EXPECT_FLOAT_EQ(inv[5], 0.25f);
  EXPECT_FLOAT_EQ(inv[11], -3.0f / 8.0f);
  Matrix4 singular = {1, 2, 3, 4, 2, 4, 6, 8, 0, 0, 1, 0, 0, 0, 0, 1};
  EXPECT_FALSE(Invert(singular, &inv));
  Matrix4 zero{};
  EXPECT_FALSE(Invert(zero, &inv));
  EXPECT_EQ(Transpose(m)[3 * 4 + 0], 1.0f);
}

// Singularity does not depend on units: a translation far from the origin or a tiny uniform
// scale has determinant far from 0 relative to its rows and columns, and an exact inverse.
TEST(Matrix4Test, InvertsLargeTranslationsAndTinyScales) {
  Matrix4 inv;
  const Matrix4 translate = {1, 0, 0, 2e12f, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  ASSERT_TRUE(Invert(translate, &inv));
  EXPECT_EQ(inv[3], -2e12f);
  EXPECT_EQ(inv[0], 1.0f);
  const Matrix4 stretch = {1e16f, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  ASSERT_TRUE(Invert(stretch, &inv));
  EXPECT_FLOAT_EQ(inv[0], 1e-16f);
  const Matrix4 tiny = {1e-20f, 0, 0, 0, 0, 1e-20f, 0, 0, 0, 0, 1e-20f, 0, 0, 0, 0, 1};
  ASSERT_TRUE(Invert(tiny, &inv));
  EXPECT_FLOAT_EQ(inv[5], 1e20f);
  const Matrix4 dependent = {1, 2, 3, 0, 4, 5, 6, 0, 7, 8, 9, 0, 0, 0, 0, 1};
  EXPECT_FALSE(Invert(dependent, &inv));
}

}  // namespace
}  // namespace tessera::api

// The acceleration data blob (api/src/acceleration_blob.h): what it keeps, and every way a blob
// that is not one this Tessera wrote is refused with a message saying why.
#include "acceleration_blob.h"

#include <cstring>
#include <string>

#include "gtest/gtest.h"
#include "hash.h"
#include "tessera/rt.h"

namespace tessera::api {
namespace {

AccelerationBlob Sample() {
  AccelerationBlob b;
  b.builder = "Lbvh";
  b.traverser = "BvhCompact";
  b.properties = {{"refine", "2"}, {"refit", "0"}};
  b.node_kind = RT_OBJECTTYPE_GEOMETRY_GROUP;
  b.inputs = {{kGeometryInput, 2, "'box' in module ab"}, {kTrianglesInput, 5, ""}};
  b.bounds = {{0, 1, 2, 3, 4, 5, -1, -2, -3, 1, 2, 3}, {}};
  return b;
}

// `bytes` with its checksum made right again after an edit.
std::string Resealed(std::string bytes) {
  const uint64_t sum = Hash64(bytes.data(), bytes.size() - 8);
  std::memcpy(&bytes[bytes.size() - 8], &sum, 8);
  return bytes;
}

std::string Refusal(const std::string& bytes) {
  absl::StatusOr<AccelerationBlob> b = DecodeAccelerationBlob(bytes.data(), bytes.size());
  EXPECT_FALSE(b.ok());
  return b.ok() ? "" : std::string(b.status().message());
}

TEST(AccelerationBlobTest, RoundTrips) {
  const std::string bytes = EncodeAccelerationBlob(Sample());
  absl::StatusOr<AccelerationBlob> b = DecodeAccelerationBlob(bytes.data(), bytes.size());
  ASSERT_TRUE(b.ok()) << b.status();
  EXPECT_EQ(b->builder, "Lbvh");
  EXPECT_EQ(b->traverser, "BvhCompact");
  EXPECT_EQ(b->properties, Sample().properties);
  EXPECT_EQ(b->node_kind, static_cast<uint32_t>(RT_OBJECTTYPE_GEOMETRY_GROUP));
  EXPECT_EQ(DescribeInputMismatch(b->inputs, Sample().inputs), "");
  EXPECT_EQ(b->bounds, Sample().bounds);
  EXPECT_EQ(EncodeAccelerationBlob(*b), bytes);  // deterministic
}

TEST(AccelerationBlobTest, RefusesWhatItDidNotWrite) {
  const std::string good = EncodeAccelerationBlob(Sample());
  EXPECT_NE(Refusal(good.substr(0, good.size() - 1)).find("truncated"), std::string::npos);
  EXPECT_NE(Refusal(good.substr(0, 12)).find("truncated"), std::string::npos);
  EXPECT_NE(Refusal(good + "x").find("trailing"), std::string::npos);
  EXPECT_NE(Refusal("").find("too short"), std::string::npos);
  std::string magic = good;
  magic[0] = 'X';
  EXPECT_NE(Refusal(magic).find("magic"), std::string::npos);
  std::string corrupt = good;
  corrupt[good.size() / 2] ^= 1;
  EXPECT_NE(Refusal(corrupt).find("checksum"), std::string::npos);
  std::string version = good;
  version[8] = 2;
  EXPECT_NE(Refusal(version).find("format version 2; this Tessera reads version 1"),
            std::string::npos);
  // Another machine kind, checksummed right.
  std::string platform = good;
  const size_t at = platform.find("little-endian");
  ASSERT_NE(at, std::string::npos);
  platform.replace(at, 6, "middle");
  EXPECT_NE(Refusal(Resealed(platform)).find("made on 'tessera-embree3"), std::string::npos);
  // Fields that lie about their lengths, checksummed right.
  std::string lying = good;
  const uint32_t huge = 0xFFFFFFF0u;
  const size_t builder_len = 24 + 4 + AccelerationDataPlatform().size();
  std::memcpy(&lying[builder_len], &huge, 4);
  EXPECT_NE(Refusal(Resealed(lying)).find("malformed"), std::string::npos);
}

TEST(AccelerationBlobTest, SaysWhichInputDiffers) {
  std::vector<BuildInput> now = Sample().inputs;
  now[1].primitive_count = 6;
  EXPECT_EQ(DescribeInputMismatch(Sample().inputs, now), "child 1 had 5 primitives, now 6");
  now.pop_back();
  EXPECT_EQ(DescribeInputMismatch(Sample().inputs, now),
            "it was built over 2 children, the node now has 1");
  now = Sample().inputs;
  now[0].bounds_program = "'other' in module ab";
  EXPECT_NE(DescribeInputMismatch(Sample().inputs, now).find("'other'"), std::string::npos);
}

}  // namespace
}  // namespace tessera::api

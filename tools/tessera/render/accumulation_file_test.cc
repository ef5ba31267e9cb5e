#include "tools/tessera/render/accumulation_file.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <cstring>
#include <fstream>

namespace tessera::render {
namespace {

std::string TempPath(const char* name) {
  return std::string(::testing::TempDir()) + "/" + name + "." + std::to_string(getpid());
}

TEST(AccumulationFileTest, KeepsEveryBit) {
  Accumulation a;
  a.width = 3;
  a.height = 2;
  a.samples = 17;
  a.key = "scene builtin:cornell; seed 4";
  for (int i = 0; i < 24; ++i) a.sums.push_back(i == 5 ? 1e-45f : 0.1f * static_cast<float>(i));
  const std::string path = TempPath("keeps.accum");
  ASSERT_TRUE(WriteAccumulation(path, a).ok());
  const absl::StatusOr<Accumulation> b = ReadAccumulation(path);
  ASSERT_TRUE(b.ok()) << b.status();
  EXPECT_EQ(b->width, 3);
  EXPECT_EQ(b->height, 2);
  EXPECT_EQ(b->samples, 17u);
  EXPECT_EQ(b->key, a.key);
  ASSERT_EQ(b->sums.size(), a.sums.size());
  EXPECT_EQ(std::memcmp(b->sums.data(), a.sums.data(), a.sums.size() * sizeof(float)), 0);
  std::remove(path.c_str());
}

TEST(AccumulationFileTest, RefusesWhatIsNotOneNamingTheFile) {
  EXPECT_TRUE(absl::IsNotFound(ReadAccumulation(TempPath("missing")).status()));
  const std::string path = TempPath("bad.accum");
  std::ofstream(path) << "P6\n";
  auto bad = ReadAccumulation(path);
  EXPECT_TRUE(absl::IsInvalidArgument(bad.status()));
  EXPECT_NE(bad.status().message().find(path), std::string::npos);

  Accumulation a;
  a.width = a.height = 4;
  a.sums.assign(64, 1.f);
  ASSERT_TRUE(WriteAccumulation(path, a).ok());
  ASSERT_EQ(truncate(path.c_str(), 100), 0);  // cut short
  bad = ReadAccumulation(path);
  EXPECT_TRUE(absl::IsInvalidArgument(bad.status()));
  EXPECT_NE(bad.status().message().find("cut short"), std::string::npos);
  std::remove(path.c_str());
}

}  // namespace
}  // namespace tessera::render

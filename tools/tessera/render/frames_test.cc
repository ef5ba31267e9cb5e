#include "tools/tessera/render/frames.h"

#include <gtest/gtest.h>

namespace tessera::render {
namespace {

TEST(FramesTest, ParsesRangesAndSteps) {
  EXPECT_EQ(*ParseFrames("7"), (std::vector<int>{7}));
  EXPECT_EQ(*ParseFrames("1-4"), (std::vector<int>{1, 2, 3, 4}));
  EXPECT_EQ(*ParseFrames("0-10:4"), (std::vector<int>{0, 4, 8}));
  EXPECT_EQ(*ParseFrames("3-3:2"), (std::vector<int>{3}));
}

TEST(FramesTest, RefusesMalformedRanges) {
  for (const char* bad : {"", "a", "1-", "-3", "4-2", "1-4:0", "1-4:", "1-4:x", "1.5", "1 - 2"}) {
    const auto frames = ParseFrames(bad);
    ASSERT_FALSE(frames.ok()) << bad;
    EXPECT_NE(frames.status().message().find(std::string("'") + bad + "'"), std::string::npos)
        << frames.status();
  }
}

TEST(FramesTest, ExpandsEachRunOfHashesInTheFileName) {
  EXPECT_TRUE(HasFramePattern("out.####.exr"));
  EXPECT_FALSE(HasFramePattern("shots#1/out.exr"));
  EXPECT_EQ(ExpandFramePattern("out.####.exr", 7), "out.0007.exr");
  EXPECT_EQ(ExpandFramePattern("dir#/f#_##.png", 12), "dir#/f12_12.png");
  EXPECT_EQ(ExpandFramePattern("f.##.png", 12345), "f.12345.png");
}

}  // namespace
}  // namespace tessera::render

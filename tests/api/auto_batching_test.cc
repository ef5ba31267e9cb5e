// AutoBatching (api/src/auto_batching.h): which entry points' launches trace their first rays as
// packets, from what earlier launches measured. An entry point starts on single rays, tries
// packets after a launch of few rays per launch index, keeps them while packets answer nearly
// every index, and once it falls short stays on single rays.
#include "auto_batching.h"

#include <gtest/gtest.h>

#include <string>

namespace tessera::api {
namespace {

using State = AutoBatching::State;

const int kProgram = 0, kOtherProgram = 0;
const void* const kRg = &kProgram;
const void* const kOtherRg = &kOtherProgram;

// Entry point 0 (program kRg) after a launch of one ray per index and a try that packets answered.
AutoBatching OnForEntryZero() {
  AutoBatching a;
  a.Choose(0, kRg);
  a.Record(0, 100, 100, 0);
  a.Choose(0, kRg);
  a.Record(0, 100, 100, 100);
  EXPECT_EQ(a.state(0), State::kOn);
  return a;
}

TEST(AutoBatchingTest, PrimaryRaysTryPacketsAndKeepThemWhilePacketsAnswer) {
  AutoBatching a;
  EXPECT_FALSE(a.Choose(0, kRg));  // nothing measured yet: single rays
  EXPECT_TRUE(a.Record(0, 1000, 1000, 0));
  EXPECT_EQ(a.state(0), State::kOn);
  EXPECT_TRUE(a.Choose(0, kRg));
  EXPECT_FALSE(a.Record(0, 1000, 1000, 1000));  // packets answered every index: kept
  EXPECT_EQ(a.state(0), State::kOn);
  EXPECT_TRUE(a.Choose(0, kRg));
  EXPECT_FALSE(a.Record(0, 1000, 1000, 950));  // 0.95 answered: still on
  EXPECT_TRUE(a.Choose(0, kRg));
}

TEST(AutoBatchingTest, ManyRaysPerIndexStayOnSingleRays) {
  AutoBatching a;
  for (int launch = 0; launch < 3; ++launch) {
    EXPECT_FALSE(a.Choose(0, kRg));
    EXPECT_FALSE(a.Record(0, 1000, 8000, 0));  // a path tracer: eight rays an index
    EXPECT_EQ(a.state(0), State::kWatching);
  }
  // The bound itself: 1.25 rays an index tries, a little more does not.
  EXPECT_FALSE(a.Record(0, 1000, 1251, 0));
  EXPECT_TRUE(a.Record(0, 1000, 1250, 0));
  EXPECT_EQ(a.state(0), State::kOn);
}

TEST(AutoBatchingTest, ATryThatPacketsDoNotAnswerTurnsThemOffForGood) {
  AutoBatching a;
  a.Choose(0, kRg);
  a.Record(0, 1000, 1000, 0);
  ASSERT_TRUE(a.Choose(0, kRg));
  EXPECT_TRUE(a.Record(0, 1000, 1000, 899));  // user geometry, a write before the trace ...
  EXPECT_EQ(a.state(0), State::kOff);
  for (int launch = 0; launch < 3; ++launch) {
    EXPECT_FALSE(a.Choose(0, kRg));
    EXPECT_FALSE(a.Record(0, 1000, 1000, 0));
  }
}

TEST(AutoBatchingTest, PacketsTurnOffWhenLaterLaunchesTraceMoreRays) {
  AutoBatching a = OnForEntryZero();
  EXPECT_TRUE(a.Record(0, 100, 300, 100));
  EXPECT_EQ(a.state(0), State::kOff);
  EXPECT_FALSE(a.Choose(0, kRg));
}

TEST(AutoBatchingTest, EntryPointsAndProgramsAreWatchedApart) {
  AutoBatching a = OnForEntryZero();
  EXPECT_FALSE(a.Choose(1, kRg));  // another entry point starts on single rays
  EXPECT_EQ(a.state(1), State::kWatching);
  // Another ray generation program on entry point 0 starts it afresh.
  EXPECT_FALSE(a.Choose(0, kOtherRg));
  EXPECT_EQ(a.state(0), State::kWatching);
}

TEST(AutoBatchingTest, AnEmptyLaunchChangesNothing) {
  AutoBatching a;
  a.Choose(0, kRg);
  EXPECT_FALSE(a.Record(0, 0, 0, 0));
  EXPECT_EQ(a.state(0), State::kWatching);
}

TEST(AutoBatchingTest, TheVariableSaysAlwaysAutoOrNever) {
  std::string warning;
  EXPECT_EQ(AutoBatching::Parse(nullptr, &warning), AutoBatching::Mode::kNever);
  EXPECT_EQ(AutoBatching::Parse("", &warning), AutoBatching::Mode::kNever);
  EXPECT_EQ(AutoBatching::Parse("0", &warning), AutoBatching::Mode::kNever);
  EXPECT_EQ(AutoBatching::Parse("auto", &warning), AutoBatching::Mode::kAuto);
  EXPECT_EQ(AutoBatching::Parse("1", &warning), AutoBatching::Mode::kAlways);
  EXPECT_TRUE(warning.empty());
  EXPECT_EQ(AutoBatching::Parse("yes", &warning), AutoBatching::Mode::kNever);
  EXPECT_NE(warning.find("TESSERA_BATCHING=yes"), std::string::npos) << warning;
}

}  // namespace
}  // namespace tessera::api

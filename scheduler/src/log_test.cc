#include "tessera/scheduler/log.h"

#include <gtest/gtest.h>
#include <regex.h>

#include <string>
#include <thread>
#include <utility>
#include <vector>

namespace tessera::log {
namespace {

struct Received {
  std::vector<std::pair<int, std::string>> lines;
};

void Collect(int level, const char* message, void* user) {
  static_cast<Received*>(user)->lines.emplace_back(level, message);
}

class LogTest : public ::testing::Test {
 protected:
  void SetUp() override { saved_ = CurrentLevel(); }
  void TearDown() override {
    SetCallback(nullptr, nullptr);
    SetLevel(saved_);
  }
  Level saved_ = Level::kInfo;
};

// POSIX extended regular expressions: std::regex trips GCC 12's -Wmaybe-uninitialized in the
// sanitizer build (tools/sanitize.sh), where warnings are errors too.
bool Matches(const std::string& text, const char* pattern) {
  regex_t re;
  if (regcomp(&re, pattern, REG_EXTENDED | REG_NOSUB) != 0) return false;
  const bool matched = regexec(&re, text.c_str(), 0, nullptr, 0) == 0;
  regfree(&re);
  return matched;
}

TEST_F(LogTest, ParsesEveryLevelNameAndRejectsOthersNamingThem) {
  EXPECT_EQ(*ParseLevel("trace"), Level::kTrace);
  EXPECT_EQ(*ParseLevel("DEBUG"), Level::kDebug);
  EXPECT_EQ(*ParseLevel(" info "), Level::kInfo);
  EXPECT_EQ(*ParseLevel("warn"), Level::kWarn);
  EXPECT_EQ(*ParseLevel("warning"), Level::kWarn);
  EXPECT_EQ(*ParseLevel("error"), Level::kError);
  EXPECT_EQ(*ParseLevel("off"), Level::kOff);
  absl::StatusOr<Level> bad = ParseLevel("loud");
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.status().message().find("'loud' is not a log level"), std::string::npos)
      << bad.status();
  EXPECT_NE(bad.status().message().find("trace, debug, info, warn, error or off"),
            std::string::npos);
}

TEST_F(LogTest, StderrLinesCarryTimeComponentAndLevel) {
  SetLevel(Level::kInfo);
  testing::internal::CaptureStderr();
  Info(Component::kWorker, "serving %d sessions", 3);
  Debug(Component::kWorker, "not shown at info");
  const std::string said = testing::internal::GetCapturedStderr();
  EXPECT_TRUE(Matches(said,
                      R"(^\[[0-9]{4}-[0-9]{2}-[0-9]{2} [0-9]{2}:[0-9]{2}:[0-9]{2}\.[0-9]{3}\] )"
                      "\\[worker\\] \\[info\\] serving 3 sessions\n$"))
      << said;
  Level level;
  absl::string_view message;
  ASSERT_TRUE(ParseLine(said.substr(0, said.size() - 1), &level, &message)) << said;
  EXPECT_EQ(level, Level::kInfo);
  EXPECT_EQ(message, "serving 3 sessions");
  EXPECT_FALSE(ParseLine("tessera-worker listening on unix:/x", &level, &message));
  EXPECT_FALSE(ParseLine("[not a time] [api] [info] x", &level, &message));
}

TEST_F(LogTest, TheLevelFiltersLines) {
  SetLevel(Level::kError);
  EXPECT_FALSE(Enabled(Level::kWarn));
  EXPECT_TRUE(Enabled(Level::kError));
  testing::internal::CaptureStderr();
  Warn(Component::kApi, "a warning");
  Error(Component::kApi, "an error");
  std::string said = testing::internal::GetCapturedStderr();
  EXPECT_EQ(said.find("a warning"), std::string::npos) << said;
  EXPECT_NE(said.find("[api] [error] an error"), std::string::npos) << said;
  SetLevel(Level::kOff);
  testing::internal::CaptureStderr();
  Error(Component::kApi, "nothing at all");
  said = testing::internal::GetCapturedStderr();
  EXPECT_EQ(said, "");
}

TEST_F(LogTest, ACallbackGetsEveryEnabledLineInsteadOfStderrUntilItIsRemoved) {
  SetLevel(Level::kDebug);
  Received received;
  SetCallback(&Collect, &received);
  testing::internal::CaptureStderr();
  Warn(Component::kScheduler, "device %s not answering\n", "unix:/w");
  Debug(Component::kApi, "detail");
  Trace(Component::kApi, "below the level");
  std::string said = testing::internal::GetCapturedStderr();
  EXPECT_EQ(said, "");
  ASSERT_EQ(received.lines.size(), 2u);
  EXPECT_EQ(received.lines[0].first, static_cast<int>(Level::kWarn));
  EXPECT_EQ(received.lines[0].second, "device unix:/w not answering");
  EXPECT_EQ(received.lines[1].first, static_cast<int>(Level::kDebug));

  SetCallback(nullptr, nullptr);
  testing::internal::CaptureStderr();
  Info(Component::kApi, "back on stderr");
  said = testing::internal::GetCapturedStderr();
  EXPECT_NE(said.find("[api] [info] back on stderr"), std::string::npos) << said;
  EXPECT_EQ(received.lines.size(), 2u);
}

// A callback that logs (or replaces itself) must not deadlock: its own lines go to stderr.
void Reentrant(int level, const char* message, void* user) {
  ++*static_cast<int*>(user);
  Warn(Component::kApi, "inside: %s", message);
  SetCallback(nullptr, nullptr);
}

TEST_F(LogTest, ACallbackThatLogsOrRemovesItselfDoesNotDeadlock) {
  SetLevel(Level::kInfo);
  int calls = 0;
  SetCallback(&Reentrant, &calls);
  testing::internal::CaptureStderr();
  Info(Component::kApi, "first");
  Info(Component::kApi, "second");
  const std::string said = testing::internal::GetCapturedStderr();
  EXPECT_EQ(calls, 1);
  EXPECT_NE(said.find("[api] [warn] inside: first"), std::string::npos) << said;
  EXPECT_NE(said.find("[api] [info] second"), std::string::npos) << said;
}

TEST_F(LogTest, LinesFromManyThreadsArriveWhole) {
  SetLevel(Level::kInfo);
  Received received;
  SetCallback(&Collect, &received);
  std::vector<std::thread> threads;
  for (int t = 0; t < 8; ++t) {
    threads.emplace_back([t] {
      for (int i = 0; i < 100; ++i) Info(Component::kWorker, "thread %d line %d", t, i);
    });
  }
  for (std::thread& t : threads) t.join();
  SetCallback(nullptr, nullptr);
  EXPECT_EQ(received.lines.size(), 800u);
}

}  // namespace
}  // namespace tessera::log

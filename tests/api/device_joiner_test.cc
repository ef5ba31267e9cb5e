// DeviceJoiner (api/src/device_joiner.h) with a create function of the test's own: tries until one
// succeeds, waits longer after each failure, tries at once when kicked, and never holds up the
// context that lets it go, even while a try hangs.
#include "device_joiner.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include "fake_device.h"

namespace tessera::api {
namespace {

using Clock = std::chrono::steady_clock;

// Fails the first `failures` tries (UNAVAILABLE), then makes a fake device; notes when each try
// began.
struct Attempts {
  explicit Attempts(int failures) : failures(failures) {}
  const int failures;
  std::mutex mu;
  std::vector<Clock::time_point> at;
  DeviceJoiner::Create Create() {
    return [this]() -> absl::StatusOr<std::unique_ptr<Device>> {
      int n;
      {
        std::lock_guard<std::mutex> lock(mu);
        at.push_back(Clock::now());
        n = static_cast<int>(at.size());
      }
      if (n <= failures) return absl::UnavailableError("not up yet");
      return std::unique_ptr<Device>(
          new test::FakeDevice(std::make_shared<test::FakeDevice::Record>()));
    };
  }
  size_t count() {
    std::lock_guard<std::mutex> lock(mu);
    return at.size();
  }
};

JoinBackoff Short() {
  JoinBackoff b;
  b.first = absl::Milliseconds(40);
  b.most = absl::Milliseconds(160);
  return b;
}

std::unique_ptr<Device> TakeWithin(DeviceJoiner& joiner, std::chrono::milliseconds limit) {
  const auto end = Clock::now() + limit;
  while (Clock::now() < end) {
    if (std::unique_ptr<Device> d = joiner.Take()) return d;
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  return nullptr;
}

TEST(DeviceJoinerTest, TriesUntilOneSucceedsWaitingLongerEachTimeUpToTheMost) {
  Attempts attempts(5);
  DeviceJoiner joiner("unix:/w", attempts.Create(), /*try_at_once=*/true, /*lost=*/false, Short());
  ASSERT_NE(TakeWithin(joiner, std::chrono::seconds(10)), nullptr);
  EXPECT_EQ(joiner.Take(), nullptr) << "taken once";
  ASSERT_EQ(attempts.count(), 6u);
  EXPECT_EQ(joiner.tries(), 6u);
  EXPECT_EQ(joiner.last_error().message(), "not up yet");
  // The gaps grow 40, 80, 160 ms and stay at 160 (each at least its wait; scheduling only adds).
  const std::chrono::milliseconds least[] = {
      std::chrono::milliseconds(40), std::chrono::milliseconds(80), std::chrono::milliseconds(160),
      std::chrono::milliseconds(160), std::chrono::milliseconds(160)};
  for (size_t i = 1; i < attempts.at.size(); ++i) {
    EXPECT_GE(attempts.at[i] - attempts.at[i - 1], least[i - 1]) << "gap " << i;
  }
}

TEST(DeviceJoinerTest, AKickTriesAtOnceAndWaitSaysWhenThatTryEnded) {
  Attempts attempts(1000);  // never up
  JoinBackoff slow;
  slow.first = absl::Seconds(30);
  slow.most = absl::Seconds(30);
  DeviceJoiner joiner("unix:/w", attempts.Create(), /*try_at_once=*/false, /*lost=*/false, slow);
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  EXPECT_EQ(attempts.count(), 0u) << "it was told the caller had just tried";
  const auto start = Clock::now();
  const uint64_t tries = joiner.Kick();
  EXPECT_FALSE(joiner.Wait(tries, absl::Now() + absl::Seconds(10)));  // it failed
  EXPECT_LT(Clock::now() - start, std::chrono::seconds(5));
  EXPECT_EQ(attempts.count(), 1u);
  EXPECT_GE(joiner.tries(), tries);
}

TEST(DeviceJoinerTest, LettingGoDoesNotWaitForATryUnderWay) {
  // Shared with the try, which outlives the test on the joiner's thread.
  auto release = std::make_shared<std::atomic<bool>>(false);
  auto started = std::make_shared<std::atomic<bool>>(false);
  auto hang = [release, started]() -> absl::StatusOr<std::unique_ptr<Device>> {
    *started = true;
    while (!*release) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    return absl::UnavailableError("gave up");
  };
  auto joiner = std::make_unique<DeviceJoiner>("10.0.0.5:7000", hang, true, false, Short());
  while (!*started) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  const auto start = Clock::now();
  joiner.reset();
  EXPECT_LT(Clock::now() - start, std::chrono::milliseconds(500));
  *release = true;  // the try ends on its own thread, which then stops
}

}  // namespace
}  // namespace tessera::api

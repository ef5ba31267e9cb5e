// Running workers listed in a device spec that are down when a context starts (docs/devices.md
// "Running workers as a service"): launches run on the devices that answer, a worker that comes
// up later joins with the whole state and takes tiles, one that never comes up costs nothing but
// one line, and with none answering the launch fails naming them. The lines reach an embedding
// application's log callback (tesseraSetLogCallback) with their levels.
#include <gtest/gtest.h>
#include <stdlib.h>

#include <chrono>
#include <filesystem>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "e2e_scene.h"
#include "http_get.h"
#include "tessera/log.h"
#include "tessera/rt_ext.h"
#include "transport/worker_process.h"

namespace tessera::e2e {
namespace {

using Clock = std::chrono::steady_clock;
constexpr unsigned kW = 64, kH = 64;

// What the log callback received.
struct LogLines {
  std::mutex mu;
  std::vector<std::pair<int, std::string>> lines;
  static void Receive(int level, const char* message, void* user) {
    auto* self = static_cast<LogLines*>(user);
    std::lock_guard<std::mutex> lock(self->mu);
    self->lines.emplace_back(level, message);
  }
  // Lines holding `text`, with the level of the first in `*level`.
  int Count(const std::string& text, int* level = nullptr) {
    std::lock_guard<std::mutex> lock(mu);
    int count = 0;
    for (const auto& [l, line] : lines) {
      if (line.find(text) == std::string::npos) continue;
      if (count++ == 0 && level != nullptr) *level = l;
    }
    return count;
  }
};

class LateWorkerTest : public ::testing::Test {
 protected:
  void SetUp() override {
    char pattern[] = "/tmp/tessera-late-test-XXXXXX";
    ASSERT_NE(mkdtemp(pattern), nullptr);
    dir_ = pattern;
    tesseraSetLogCallback(&LogLines::Receive, &log_);
    // The inproc reference.
    ASSERT_EQ(rtContextCreate(&reference_), RT_SUCCESS);
    ASSERT_EQ(tesseraContextSetDeviceSpec(reference_, "inproc"), RT_SUCCESS);
    std::string error;
    ASSERT_EQ(BuildScene(reference_, kW, kH, &reference_scene_, &error), RT_SUCCESS) << error;
    ASSERT_EQ(rtContextLaunch2D(reference_, 0, kW, kH), RT_SUCCESS);
    image_ = ReadBytes(reference_scene_.image);
  }
  void TearDown() override {
    if (ctx_ != nullptr) rtContextDestroy(ctx_);
    if (reference_ != nullptr) rtContextDestroy(reference_);
    tesseraSetLogCallback(nullptr, nullptr);
    std::error_code ec;
    std::filesystem::remove_all(dir_, ec);
  }
  void Create(const std::string& spec) {
    ASSERT_EQ(rtContextCreate(&ctx_), RT_SUCCESS);
    ASSERT_EQ(tesseraContextSetDeviceSpec(ctx_, spec.c_str()), RT_SUCCESS)
        << ErrorText(ctx_, RT_ERROR_INVALID_VALUE);
    std::string error;
    ASSERT_EQ(BuildScene(ctx_, kW, kH, &scene_, &error), RT_SUCCESS) << error;
  }
  // Launches and checks the image against the reference.
  void LaunchAndCompare() {
    const RTresult r = rtContextLaunch2D(ctx_, 0, kW, kH);
    ASSERT_EQ(r, RT_SUCCESS) << ErrorText(ctx_, r);
    ASSERT_EQ(ReadBytes(scene_.image), image_) << "not the image of one in-process device";
  }
  std::string Socket(const std::string& name) const { return "unix:" + dir_ + "/" + name; }

  std::string dir_;
  LogLines log_;
  RTcontext reference_ = nullptr;
  Scene reference_scene_;
  std::string image_;
  RTcontext ctx_ = nullptr;
  Scene scene_;
};

std::unique_ptr<transport::WorkerProcess> StartWorker(const std::string& listen) {
  transport::WorkerProcess::Options options;
  options.listen = listen;
  options.threads = 1;
  options.extra_args = {"--status-listen", "0"};
  auto worker = transport::WorkerProcess::Spawn(options);
  EXPECT_TRUE(worker.ok()) << worker.status();
  return worker.ok() ? *std::move(worker) : nullptr;
}

// The worker starts 1.5 s after the first launch: launches meanwhile run on the others, and once
// it answers it joins (said once), receives the whole state and takes tiles, and the images stay
// those of one in-process device.
TEST_F(LateWorkerTest, AWorkerThatComesUpLaterJoinsAndTakesTiles) {
  const std::string late = Socket("late.sock");
  ASSERT_NO_FATAL_FAILURE(Create("inproc," + late));
  const auto start = Clock::now();
  ASSERT_NO_FATAL_FAILURE(LaunchAndCompare());
  int level = -1;
  EXPECT_EQ(log_.Count("device " + late +
                           " not answering; continuing with 1 devices, retrying "
                           "in background",
                       &level),
            1);
  EXPECT_EQ(level, TESSERA_LOG_WARN);

  std::unique_ptr<transport::WorkerProcess> worker;
  double up_after = -1;  // when it listened
  std::thread starter([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(1500));
    worker = StartWorker(late);
    up_after = std::chrono::duration<double>(Clock::now() - start).count();
  });
  // Launches go on meanwhile, none of them waiting for the worker.
  int launches = 1;
  double joined_after = -1;
  int port = 0;
  while (Clock::now() - start < std::chrono::seconds(30)) {
    const auto before = Clock::now();
    ASSERT_NO_FATAL_FAILURE(LaunchAndCompare());
    EXPECT_LT(Clock::now() - before, std::chrono::seconds(5)) << "a launch waited";
    ++launches;
    if (joined_after < 0 && log_.Count("device " + late + " is up; joining", &level) == 1) {
      joined_after = std::chrono::duration<double>(Clock::now() - start).count();
      EXPECT_EQ(level, TESSERA_LOG_INFO);
    }
    if (joined_after >= 0 && port == 0) {
      starter.join();
      ASSERT_NE(worker, nullptr);
      port = StatusPort(worker->LogTail());
      ASSERT_NE(port, 0) << worker->LogTail();
    }
    if (port != 0 && JsonNumber(HttpGet(port, "/status").body, "tiles") > 0) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  if (starter.joinable()) starter.join();
  ASSERT_GE(joined_after, 1.5) << "joined before it was up";
  ASSERT_NE(port, 0) << "never joined";
  const std::string status = HttpGet(port, "/status").body;
  EXPECT_GT(JsonNumber(status, "tiles"), 0) << status;
  EXPECT_EQ(JsonNumber(status, "sessions"), 1) << status;
  std::printf(
      "a worker started 1.5 s after the first launch listened %.2f s after it and joined "
      "%.2f s after it (the backoff's tries: 0, 0.5, 1.5, 3.5, 7.5 s...), %d launches in "
      "all\n",
      up_after, joined_after, launches);
  EXPECT_EQ(log_.Count("not answering"), 1) << "said more than once";
  unsigned count = 0;
  ASSERT_EQ(rtContextGetDeviceCount(ctx_, &count), RT_SUCCESS);
  EXPECT_EQ(count, 2u) << "listed devices, whether they answer or not";
}

// A worker that never comes up: every launch runs on the others at once, and it is said once.
TEST_F(LateWorkerTest, AWorkerThatNeverComesUpCostsOneLine) {
  const std::string never = Socket("never.sock");
  ASSERT_NO_FATAL_FAILURE(Create("inproc," + never));
  unsigned count = 0;
  ASSERT_EQ(rtContextGetDeviceCount(ctx_, &count), RT_SUCCESS);
  EXPECT_EQ(count, 2u);
  for (int i = 0; i < 10; ++i) {
    const auto before = Clock::now();
    ASSERT_NO_FATAL_FAILURE(LaunchAndCompare());
    EXPECT_LT(Clock::now() - before, std::chrono::seconds(2)) << "launch " << i << " waited";
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  EXPECT_EQ(log_.Count(never + " not answering"), 1);
  EXPECT_EQ(log_.Count(never + " is up"), 0);
}

// No device answers: the launch fails with RT_ERROR_CONNECTION_FAILED naming every device and
// why, after one try each (a refused connection is at once) and the next launch likewise; once
// one comes up, launches succeed.
TEST_F(LateWorkerTest, NoDeviceAnsweringFailsNamingThem) {
  const std::string a = Socket("a.sock"), b = Socket("b.sock");
  ASSERT_NO_FATAL_FAILURE(Create(a + "," + b));
  for (int attempt = 0; attempt < 2; ++attempt) {
    const auto before = Clock::now();
    const RTresult r = rtContextLaunch2D(ctx_, 0, kW, kH);
    EXPECT_EQ(r, RT_ERROR_CONNECTION_FAILED) << ErrorText(ctx_, r);
    const std::string message = ErrorText(ctx_, r);
    for (const std::string& part : {std::string("no device could be started"), a, b,
                                    std::string("tried again in the background")}) {
      EXPECT_NE(message.find(part), std::string::npos) << part << ": " << message;
    }
    EXPECT_LT(Clock::now() - before, std::chrono::seconds(12)) << "attempt " << attempt;
  }
  std::unique_ptr<transport::WorkerProcess> worker = StartWorker(b);
  ASSERT_NE(worker, nullptr);
  ASSERT_NO_FATAL_FAILURE(LaunchAndCompare());
}

}  // namespace
}  // namespace tessera::e2e

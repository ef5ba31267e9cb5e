// Faults at the moments before tiles run (issue 23): a worker killed or stopped while it starts or
// while it takes the first state update is a lost device like one lost mid-launch. The launch
// runs on the others and succeeds, ends within the silence deadline (never a hang), and the next
// launch starts the worker again. Only "no device could be started" fails a launch.
#include <gtest/gtest.h>
#include <signal.h>
#include <stdlib.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "e2e_scene.h"
#include "process_util.h"
#include "tessera/rt_ext.h"
#include "transport/worker_process.h"

namespace tessera::e2e {
namespace {

using Clock = std::chrono::steady_clock;
constexpr char kWorker[] = "tessera-worker";
constexpr unsigned kW = 64, kH = 48;

// Restores an environment variable when the test ends, however it ends.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const std::string& value) : name_(name) {
    if (const char* old = std::getenv(name)) {
      had_ = true;
      old_ = old;
    }
    setenv(name, value.c_str(), 1);
  }
  ~ScopedEnv() {
    if (had_) {
      setenv(name_, old_.c_str(), 1);
    } else {
      unsetenv(name_);
    }
  }

 private:
  const char* name_;
  bool had_ = false;
  std::string old_;
};

class StartFaultTest : public ::testing::Test {
 protected:
  void SetUp() override {
    char dir[] = "/tmp/tessera-start-faults-XXXXXX";
    ASSERT_NE(mkdtemp(dir), nullptr);
    dir_ = dir;
  }
  void TearDown() override {
    if (ctx_ != nullptr) rtContextDestroy(ctx_);
    for (const char* f : {"/wrapper.sh", "/first-done"}) std::remove((dir_ + f).c_str());
    rmdir(dir_.c_str());
  }
  void Ok(RTresult code) { ASSERT_EQ(code, RT_SUCCESS) << ErrorText(ctx_, code); }
  void Create(const std::string& spec) {
    if (ctx_ != nullptr) rtContextDestroy(ctx_);
    ctx_ = nullptr;
    Ok(rtContextCreate(&ctx_));
    Ok(tesseraContextSetDeviceSpec(ctx_, spec.c_str()));
    std::string error;
    ASSERT_EQ(BuildScene(ctx_, kW, kH, &scene_, &error), RT_SUCCESS) << error;
  }
  std::string Reference() {
    Create("inproc");
    Ok(rtContextLaunch2D(ctx_, 0, kW, kH));
    return ReadBytes(scene_.image);
  }
  // A TESSERA_WORKER that runs `first` (shell commands) instead of starting worker 0 the first
  // time it is spawned, and starts the real worker otherwise.
  std::string Wrapper(const std::string& first) {
    absl::StatusOr<std::string> worker = transport::FindWorkerBinary();
    EXPECT_TRUE(worker.ok()) << worker.status();
    const std::string path = dir_ + "/wrapper.sh";
    std::ofstream out(path);
    out << "#!/bin/sh\n"
        << "case \"$*\" in *w0.sock*)\n"
        << "  if [ ! -e '" << dir_ << "/first-done' ]; then\n"
        << "    touch '" << dir_ << "/first-done'\n"
        << "    " << first << "\n"
        << "  fi;;\n"
        << "esac\n"
        << "exec '" << worker.value_or("tessera-worker") << "' \"$@\"\n";
    out.close();
    chmod(path.c_str(), 0755);
    return path;
  }
  RTresult TimedLaunch(double* seconds, std::string* said) {
    testing::internal::CaptureStderr();
    const auto start = Clock::now();
    RTresult r = rtContextLaunch2D(ctx_, 0, kW, kH);
    *seconds = std::chrono::duration<double>(Clock::now() - start).count();
    *said = testing::internal::GetCapturedStderr();
    return r;
  }

  std::string dir_;
  RTcontext ctx_ = nullptr;
  Scene scene_;
};

// A worker that dies while it starts: the first launch runs on the other and the next one on
// both.
TEST_F(StartFaultTest, AWorkerKilledWhileStartingIsALostDevice) {
  const std::string reference = Reference();
  ScopedEnv worker("TESSERA_WORKER", Wrapper("kill -9 $$"));
  Create("local:2");
  double seconds = 0;
  std::string said;
  RTresult r = TimedLaunch(&seconds, &said);
  ASSERT_EQ(r, RT_SUCCESS) << ErrorText(ctx_, r) << "\n" << said;
  EXPECT_TRUE(ReadBytes(scene_.image) == reference);
  EXPECT_NE(said.find("could not be started"), std::string::npos) << said;
  EXPECT_NE(said.find("local:2/0"), std::string::npos) << said;
  r = TimedLaunch(&seconds, &said);
  ASSERT_EQ(r, RT_SUCCESS) << ErrorText(ctx_, r);
  EXPECT_TRUE(ReadBytes(scene_.image) == reference);
  EXPECT_EQ(ChildrenNamed(getpid(), kWorker).size(), 2u);
  EXPECT_EQ(said.find("could not be started"), std::string::npos) << said;
}

// A worker stopped while it starts (it never says where it listens) is dropped after the silence
// deadline, not after a fixed start timeout, and the launch succeeds on the other.
TEST_F(StartFaultTest, AWorkerStoppedWhileStartingIsDroppedAfterTheDeadline) {
  const std::string reference = Reference();
  ScopedEnv timeout("TESSERA_WORKER_TIMEOUT", kDeadline);
  ScopedEnv worker("TESSERA_WORKER", Wrapper("kill -STOP $$"));
  Create("local:2");
  double seconds = 0;
  std::string said;
  RTresult r = TimedLaunch(&seconds, &said);
  ASSERT_EQ(r, RT_SUCCESS) << ErrorText(ctx_, r) << "\n" << said;
  EXPECT_TRUE(ReadBytes(scene_.image) == reference);
  EXPECT_NE(said.find("did not report listening within " + kDeadline + "s"), std::string::npos)
      << said;
  EXPECT_LT(seconds, 10.0);
  r = TimedLaunch(&seconds, &said);
  ASSERT_EQ(r, RT_SUCCESS) << ErrorText(ctx_, r);
  EXPECT_EQ(ChildrenNamed(getpid(), kWorker).size(), 2u);
}

// With no device at all, the launch fails with the device's own reason: a worker that cannot be
// started is a configuration error, said as such.
TEST_F(StartFaultTest, NoDeviceStartedFailsNamingWhy) {
  ScopedEnv worker("TESSERA_WORKER", "/nonexistent/tessera-worker");
  Create("local:2");
  testing::internal::CaptureStderr();
  RTresult r = rtContextLaunch2D(ctx_, 0, kW, kH);
  testing::internal::GetCapturedStderr();
  EXPECT_EQ(r, RT_ERROR_CONNECTION_FAILED);
  EXPECT_NE(ErrorText(ctx_, r).find("could not be started"), std::string::npos)
      << ErrorText(ctx_, r);
  EXPECT_NE(ErrorText(ctx_, r).find("/nonexistent/tessera-worker"), std::string::npos)
      << ErrorText(ctx_, r);
}

// The timeout callback runs on the launching thread while the first state update ships.
std::atomic<int> g_signal{0};
std::atomic<int> g_faults{0};
int SignalOneWorkerOnce() {
  if (g_faults.load() == 0) {
    std::vector<pid_t> workers = ChildrenNamed(getpid(), kWorker);
    if (!workers.empty() && kill(workers.front(), g_signal.load()) == 0) ++g_faults;
  }
  return 0;
}

// Adds an INPUT buffer of `bytes` to the scene: a first state update that takes a while to ship
// (the worker's socket fills, so the host's writes wait for it to read).
void AddBallast(RTcontext ctx, RTsize bytes) {
  RTbuffer ballast;
  ASSERT_EQ(rtBufferCreate(ctx, RT_BUFFER_INPUT, &ballast), RT_SUCCESS);
  ASSERT_EQ(rtBufferSetFormat(ballast, RT_FORMAT_UNSIGNED_BYTE), RT_SUCCESS);
  ASSERT_EQ(rtBufferSetSize1D(ballast, bytes), RT_SUCCESS);
  void* data = nullptr;
  ASSERT_EQ(rtBufferMap(ballast, &data), RT_SUCCESS);
  for (RTsize i = 0; i < bytes; i += 4096) static_cast<unsigned char*>(data)[i] = (i >> 12) & 255;
  ASSERT_EQ(rtBufferUnmap(ballast), RT_SUCCESS);
  RTvariable v;
  ASSERT_EQ(rtContextDeclareVariable(ctx, "ballast", &v), RT_SUCCESS);
  ASSERT_EQ(rtVariableSetObject(v, ballast), RT_SUCCESS);
}

// A worker stopped or killed while the first launch's state streams to it: the stream cannot hold
// the host (a stopped worker stops reading, and the host's writes used to block for good), the
// device is dropped, and the launch succeeds on the other.
TEST_F(StartFaultTest, AWorkerLostDuringTheFirstStateUpdateIsALostDevice) {
  const std::string reference = Reference();
  ScopedEnv timeout("TESSERA_WORKER_TIMEOUT", kDeadline);
  for (int sig : {SIGSTOP, SIGKILL}) {
    SCOPED_TRACE(sig == SIGSTOP ? "SIGSTOP" : "SIGKILL");
    Create("local:2");
    AddBallast(ctx_, RTsize{64} << 20);
    g_signal = sig;
    g_faults = 0;
    Ok(rtContextSetTimeoutCallback(ctx_, &SignalOneWorkerOnce, 0.001));
    double seconds = 0;
    std::string said;
    RTresult r = TimedLaunch(&seconds, &said);
    ASSERT_EQ(r, RT_SUCCESS) << ErrorText(ctx_, r) << "\n" << said;
    ASSERT_EQ(g_faults.load(), 1);
    EXPECT_TRUE(ReadBytes(scene_.image) == reference);
    EXPECT_NE(said.find("was lost"), std::string::npos) << said;
    EXPECT_LT(seconds, 20.0);
    Ok(rtContextSetTimeoutCallback(ctx_, nullptr, 0));
    r = TimedLaunch(&seconds, &said);
    ASSERT_EQ(r, RT_SUCCESS) << ErrorText(ctx_, r);
    EXPECT_EQ(ChildrenNamed(getpid(), kWorker).size(), 2u);
  }
}

}  // namespace
}  // namespace tessera::e2e

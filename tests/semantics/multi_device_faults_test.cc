// Faults (docs/devices.md "Faults") on device sets of 1, 2 and 4 worker processes: a worker killed
// or stopped mid-launch costs time, not results; a program that crashes its worker fails the
// launch naming the device and the program, and the next launch works; every device lost is
// RT_ERROR_CONNECTION_FAILED, never a hang. An in-process device cannot be lost without its
// application: with one worker, the kill and stop rules run on `inproc,local:1`, whose in-process
// device takes over; a crash in an in-process program is the application's crash, as in OptiX.
#include <signal.h>
#include <stdlib.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <string>
#include <vector>

#include "multi_device_fixture.h"
#include "worker_processes.h"

namespace tessera::testing {
namespace {

using Clock = std::chrono::steady_clock;
constexpr char kModule[] = "fault_programs";
constexpr RTsize kW = 192, kH = 128;
// About half a second of work on two cores: a fault lands in the middle of the launch.
constexpr unsigned kIterations = 20000;

// The timeout callback runs on the launching thread while tiles run: the fault lands there.
std::atomic<int> g_signal{0};
std::atomic<bool> g_every_worker{false};
std::atomic<int> g_faults{0};
int SignalWorkers() {
  if (g_faults.load() == 0) {
    std::vector<pid_t> workers = WorkersOf(getpid());
    if (!g_every_worker.load() && !workers.empty()) workers.resize(1);
    for (pid_t w : workers) {
      if (kill(w, g_signal.load()) == 0) ++g_faults;
    }
  }
  return 0;
}

class FaultRulesTest : public MultiDeviceFixture, public ::testing::WithParamInterface<DeviceCase> {
 protected:
  void TearDown() override {
    unsetenv("TESSERA_WORKER_TIMEOUT");
    MultiDeviceFixture::TearDown();
  }

  // slow_hash over kW x kH in 8x8 tiles (every worker has tiles in flight when a fault lands) on
  // the test's devices; the launch that starts the workers and ships the state is done. The first
  // test also renders it on one in-process device: what every fault-free run gives.
  void SetUpSlowHash() {
    if (Reference().empty()) {
      SlowHashOn("inproc");
      Reference() = Contents<unsigned>(hashes_);
      ASSERT_NE(Reference()[0], Reference()[1]) << "slow_hash wrote nothing";
    }
    SlowHashOn(GetParam().spec);
  }
  void SlowHashOn(const char* spec) {
    UseDevices(spec);
    Ok(rtContextSetRayGenerationProgram(ctx_, 0, RtFixture::Program(kModule, "slow_hash")));
    hashes_ = Buffer(RT_BUFFER_OUTPUT, RT_FORMAT_UNSIGNED_INT, {kW, kH}, "hashes");
    SetUint("iterations", kIterations);
    SetUint("bad_address", 0);
    TileSize({8, 8});
    Launch2D(kW, kH);
  }
  static std::vector<unsigned>& Reference() {
    static std::vector<unsigned> reference;
    return reference;
  }

  // Launches with `signal` sent to one worker (or every worker) at the first progress callback;
  // returns the result, and stderr in `said`.
  RTresult LaunchWithFault(int signal, bool every_worker, std::string* said) {
    g_signal = signal;
    g_every_worker = every_worker;
    g_faults = 0;
    Ok(rtContextSetTimeoutCallback(ctx_, &SignalWorkers, 0.05));
    ::testing::internal::CaptureStderr();
    const auto start = Clock::now();
    RTresult r = rtContextLaunch2D(ctx_, 0, kW, kH);
    seconds_ = std::chrono::duration<double>(Clock::now() - start).count();
    *said = ::testing::internal::GetCapturedStderr();
    Ok(rtContextSetTimeoutCallback(ctx_, nullptr, 0));
    return r;
  }

  // The next launch runs on every worker again (the lost ones started anew) and gives the
  // fault-free image.
  void NextLaunchWorks() {
    ::testing::internal::CaptureStderr();
    RTresult r = rtContextLaunch2D(ctx_, 0, kW, kH);
    ::testing::internal::GetCapturedStderr();
    Ok(r);
    EXPECT_EQ(Contents<unsigned>(hashes_), Reference());
    EXPECT_EQ(WorkersOf(getpid()).size(), Workers());
  }

  // Worker processes of the test's device set.
  size_t Workers() const {
    const std::string spec = GetParam().spec;
    return std::strtoul(spec.substr(spec.find("local:") + 6).c_str(), nullptr, 10);
  }

  RTbuffer hashes_ = nullptr;
  double seconds_ = 0;
};

using SurvivorsTest = FaultRulesTest;  // a device is left when one worker is lost
using WorkersOnlyTest = FaultRulesTest;

TEST_P(SurvivorsTest, AWorkerKilledMidLaunchCostsTimeNotResults) {
  SetUpSlowHash();
  std::string said;
  RTresult r = LaunchWithFault(SIGKILL, /*every_worker=*/false, &said);
  ASSERT_EQ(r, RT_SUCCESS) << Error(r) << "\n" << said;
  ASSERT_EQ(g_faults.load(), 1);
  EXPECT_EQ(Contents<unsigned>(hashes_), Reference()) << "the output differs from a fault-free run";
  EXPECT_NE(said.find("was lost during launch"), std::string::npos) << said;
  EXPECT_NE(said.find("Its tiles ran on the other devices"), std::string::npos) << said;
  NextLaunchWorks();
}

TEST_P(SurvivorsTest, AWorkerThatStopsAnsweringMissesItsDeadline) {
  // 1 s, the shortest deadline; workers built with the sanitizers (tools/sanitize.sh) can take most
  // of that to start on a loaded machine, and one that has not said where it listens by then is
  // dropped: there 5 s.
#ifdef TESSERA_SANITIZER_BUILD
  const std::string deadline = "5";
#else
  const std::string deadline = "1";
#endif
  setenv("TESSERA_WORKER_TIMEOUT", deadline.c_str(), 1);
  SetUpSlowHash();
  std::string said;
  RTresult r = LaunchWithFault(SIGSTOP, /*every_worker=*/false, &said);
  for (pid_t w : WorkersOf(getpid())) kill(w, SIGCONT);  // the lost one is dropped and reaped
  ASSERT_EQ(r, RT_SUCCESS) << Error(r) << "\n" << said;
  ASSERT_EQ(g_faults.load(), 1);
  EXPECT_EQ(Contents<unsigned>(hashes_), Reference()) << "the output differs from a fault-free run";
  EXPECT_NE(said.find("sent nothing for " + deadline + "s"), std::string::npos) << said;
  EXPECT_LT(seconds_, 30.0);
  NextLaunchWorks();
}

TEST_P(WorkersOnlyTest, ACrashingProgramFailsTheLaunchNamingDeviceAndProgram) {
  SetUpSlowHash();
  Ok(rtContextSetRayGenerationProgram(ctx_, 0, RtFixture::Program(kModule, "crash_at_5_5")));
  ::testing::internal::CaptureStderr();
  RTresult r = rtContextLaunch2D(ctx_, 0, kW, kH);
  const std::string said = ::testing::internal::GetCapturedStderr();
  const std::string message = Error(r);
  ASSERT_EQ(r, RT_ERROR_LAUNCH_FAILED) << message << "\n" << said;
  EXPECT_NE(message.find("Tessera local worker"), std::string::npos) << message;
  EXPECT_NE(message.find("ray generation program 'crash_at_5_5'"), std::string::npos) << message;
  Ok(rtContextSetRayGenerationProgram(ctx_, 0, RtFixture::Program(kModule, "slow_hash")));
  NextLaunchWorks();
}

TEST_P(WorkersOnlyTest, EveryDeviceLostIsConnectionFailed) {
  SetUpSlowHash();
  std::string said;
  RTresult r = LaunchWithFault(SIGKILL, /*every_worker=*/true, &said);
  EXPECT_EQ(r, RT_ERROR_CONNECTION_FAILED) << Error(r) << "\n" << said;
  EXPECT_EQ(g_faults.load(), static_cast<int>(Workers()));
  EXPECT_NE(Error(r).find("every device was lost"), std::string::npos) << Error(r);
  EXPECT_NE(said.find("No other device was left"), std::string::npos) << said;
  EXPECT_LT(seconds_, 30.0);
  NextLaunchWorks();
}

const DeviceCase kSurvivorCases[] = {
    {"Inproc_Local1", "inproc,local:1", 2},
    {"Local2", "local:2", 2},
    {"Local4", "local:4", 4},
};
INSTANTIATE_TEST_SUITE_P(Devices, SurvivorsTest, ::testing::ValuesIn(kSurvivorCases),
                         DeviceCaseName);

const DeviceCase kWorkerCases[] = {
    {"Local1", "local:1", 1},
    {"Local2", "local:2", 2},
    {"Local4", "local:4", 4},
};
INSTANTIATE_TEST_SUITE_P(Devices, WorkersOnlyTest, ::testing::ValuesIn(kWorkerCases),
                         DeviceCaseName);

}  // namespace
}  // namespace tessera::testing

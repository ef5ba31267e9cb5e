// Faults (issue 3 point 8) with real worker processes: a worker killed or stopped mid-launch costs
// time, not results; a program that crashes its worker fails the launch with a message naming the
// device and the program, and the next launch works on a respawned worker; every device lost is
// RT_ERROR_CONNECTION_FAILED, never a hang.
#include <gtest/gtest.h>
#include <signal.h>
#include <stdlib.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "e2e_scene.h"
#include "process_util.h"
#include "tessera/rt_ext.h"
#include "transport/worker_process.h"

#ifdef TESSERA_SANITIZER_BUILD
// LeakSanitizer's hook (tools/sanitize.sh): no leak check in a child forked without exec
// (ForkedChildRendersInProcess…). There the parent's threads are still in ASan's thread registry
// but not in the process, so what they held is never scanned ("Running thread N was not
// suspended. False leaks are possible.") and reads as leaked. ASan and UBSan still check the
// child, and the leak check of the test itself stays on.
namespace {
const pid_t g_test_pid = getpid();
}  // namespace
extern "C" int __lsan_is_turned_off() {
  if (getpid() == g_test_pid) return 0;
  std::fprintf(stderr,
               "sanitize: no leak check in this test's forked child: the parent's threads, which "
               "hold its memory, are not in the child\n");
  return 1;
}
#endif

namespace tessera::e2e {
namespace {

using Clock = std::chrono::steady_clock;
constexpr char kWorker[] = "tessera-worker";
constexpr unsigned kW = 96, kH = 64;
// render_slow traces this many rays per launch index: long enough (a second or so on two cores)
// for a fault to land in the middle of the launch.
constexpr int kIterations = 300;

class FaultTest : public ::testing::Test {
 protected:
  void TearDown() override {
    if (ctx_ != nullptr) rtContextDestroy(ctx_);
  }
  void Ok(RTresult code) { ASSERT_EQ(code, RT_SUCCESS) << ErrorText(ctx_, code); }
  void Create(const std::string& spec) {
    if (ctx_ != nullptr) rtContextDestroy(ctx_);
    ctx_ = nullptr;
    Ok(rtContextCreate(&ctx_));
    Ok(tesseraContextSetDeviceSpec(ctx_, spec.c_str()));
    std::string error;
    ASSERT_EQ(BuildScene(ctx_, kW, kH, &scene_, &error), RT_SUCCESS) << error;
    Ok(rtVariableSet1i(scene_.iterations, kIterations));
  }
  // The image of render_slow on one in-process device: what every fault-free run must give.
  std::string Reference() {
    Create("inproc");
    Ok(rtContextLaunch2D(ctx_, 1, kW, kH));
    return ReadBytes(scene_.image);
  }

  // Launches `program` (render_crash by default), which ends its worker; returns the launch's
  // result and message, and its stderr in `warning` when given.
  RTresult LaunchCrashingProgram(std::string* message, const char* program = "render_crash",
                                 std::string* warning = nullptr) {
    RTprogram crash;
    EXPECT_EQ(rtProgramCreateFromPTXFile(ctx_, ModulePath(), program, &crash), RT_SUCCESS);
    EXPECT_EQ(rtContextSetRayGenerationProgram(ctx_, 0, crash), RT_SUCCESS);
    testing::internal::CaptureStderr();
    RTresult r = rtContextLaunch2D(ctx_, 0, kW, kH);
    const std::string said = testing::internal::GetCapturedStderr();
    if (warning != nullptr) *warning = said;
    *message = ErrorText(ctx_, r);
    return r;
  }
  // After a program ended a worker: the host keeps running, and the next launch works on the
  // respawned worker.
  void NextLaunchWorks() {
    RTprogram render;
    Ok(rtProgramCreateFromPTXFile(ctx_, ModulePath(), "render", &render));
    Ok(rtContextSetRayGenerationProgram(ctx_, 0, render));
    testing::internal::CaptureStderr();
    RTresult r = rtContextLaunch2D(ctx_, 0, kW, kH);
    testing::internal::GetCapturedStderr();
    Ok(r);
    EXPECT_EQ(ChildrenNamed(getpid(), kWorker).size(), 2u);
  }

  // Launches entry point `entry`, returning its result, how long it took and its stderr.
  RTresult TimedLaunch(unsigned entry, double* seconds, std::string* warning) {
    testing::internal::CaptureStderr();
    const auto start = Clock::now();
    RTresult r = rtContextLaunch2D(ctx_, entry, kW, kH);
    *seconds = std::chrono::duration<double>(Clock::now() - start).count();
    *warning = testing::internal::GetCapturedStderr();
    return r;
  }

  RTcontext ctx_ = nullptr;
  Scene scene_;
};

// The timeout callback runs on the launching thread during the launch: the fault lands there.
std::atomic<int> g_signal{0};
std::atomic<int> g_faults{0};
int SignalOneWorker() {
  if (g_faults.load() == 0) {
    std::vector<pid_t> workers = ChildrenNamed(getpid(), kWorker);
    if (!workers.empty() && kill(workers.front(), g_signal.load()) == 0) ++g_faults;
  }
  return 0;
}

TEST_F(FaultTest, KilledWorkerCostsTimeNotResults) {
  const std::string reference = Reference();
  Create("local:3");
  // Many small tiles: every worker has a batch in flight whenever the fault lands.
  const RTsize tile[2] = {8, 8};
  Ok(tesseraContextSetTileSize(ctx_, 2, tile));
  Ok(rtContextLaunch2D(ctx_, 0, kW, kH));  // workers up and synced
  g_signal = SIGKILL;
  g_faults = 0;
  Ok(rtContextSetTimeoutCallback(ctx_, &SignalOneWorker, 0.05));
  testing::internal::CaptureStderr();
  RTresult r = rtContextLaunch2D(ctx_, 1, kW, kH);
  std::string warning = testing::internal::GetCapturedStderr();
  ASSERT_EQ(r, RT_SUCCESS) << ErrorText(ctx_, r);
  ASSERT_EQ(g_faults.load(), 1);
  EXPECT_TRUE(ReadBytes(scene_.image) == reference) << "the image differs from a fault-free run";
  EXPECT_NE(warning.find("was lost"), std::string::npos) << warning;
  EXPECT_NE(warning.find("killed by signal 9"), std::string::npos) << warning;
  // The scene holds no GPU_LOCAL buffer: nothing of the kind is said to be gone
  // (DeviceSetProbeTest.SurvivorsKeepTheirGpuLocalPixelsWhenAWorkerDiedBetweenLaunches has one).
  EXPECT_EQ(warning.find("GPU_LOCAL"), std::string::npos) << warning;

  // The next launch runs on a respawned third worker.
  Ok(rtContextSetTimeoutCallback(ctx_, nullptr, 0));
  Ok(rtContextLaunch2D(ctx_, 1, kW, kH));
  EXPECT_TRUE(ReadBytes(scene_.image) == reference);
  EXPECT_EQ(ChildrenNamed(getpid(), kWorker).size(), 3u);
}

TEST_F(FaultTest, StoppedWorkerMissesItsDeadline) {
  const std::string reference = Reference();
  setenv("TESSERA_WORKER_TIMEOUT", kDeadline.c_str(), 1);
  Create("local:2");
  Ok(rtContextLaunch2D(ctx_, 0, kW, kH));
  g_signal = SIGSTOP;
  g_faults = 0;
  Ok(rtContextSetTimeoutCallback(ctx_, &SignalOneWorker, 0.05));
  double seconds = 0;
  std::string warning;
  RTresult r = TimedLaunch(1, &seconds, &warning);
  unsetenv("TESSERA_WORKER_TIMEOUT");
  ASSERT_EQ(r, RT_SUCCESS) << ErrorText(ctx_, r);
  ASSERT_EQ(g_faults.load(), 1);
  EXPECT_TRUE(ReadBytes(scene_.image) == reference) << "the image differs from a fault-free run";
  EXPECT_NE(warning.find("sent nothing for " + kDeadline + "s"), std::string::npos) << warning;
  EXPECT_LT(seconds, 30.0);
}

// A worker that stops between launches misses the deadline while it takes the next state update
// too, instead of holding that launch for gRPC's keepalive (about 50 s).
TEST_F(FaultTest, WorkerStoppedBetweenLaunchesMissesItsDeadline) {
  const std::string reference = Reference();
  setenv("TESSERA_WORKER_TIMEOUT", kDeadline.c_str(), 1);
  Create("local:2");
  Ok(rtContextLaunch2D(ctx_, 0, kW, kH));
  std::vector<pid_t> workers = ChildrenNamed(getpid(), kWorker);
  ASSERT_EQ(workers.size(), 2u);
  ASSERT_EQ(kill(workers.front(), SIGSTOP), 0);
  ASSERT_TRUE(WaitUntilStopped(workers.front(), std::chrono::seconds(5)));
  RTvariable changed = nullptr;  // a state update for every device
  Ok(rtContextDeclareVariable(ctx_, "unused_by_programs", &changed));
  Ok(rtVariableSet1f(changed, 1.f));
  double seconds = 0;
  std::string warning;
  RTresult r = TimedLaunch(1, &seconds, &warning);
  unsetenv("TESSERA_WORKER_TIMEOUT");
  kill(workers.front(), SIGKILL);
  ASSERT_EQ(r, RT_SUCCESS) << ErrorText(ctx_, r);
  EXPECT_TRUE(ReadBytes(scene_.image) == reference) << "the image differs from a fault-free run";
  EXPECT_NE(warning.find("did not take the state update within " + kDeadline + "s"),
            std::string::npos)
      << warning;
  EXPECT_LT(seconds, 30.0);
}

// A process forked from a host (without exec) inherits its contexts but not their workers'
// threads and connections: calls on an inherited context fail clearly. It inherits gRPC's state
// without gRPC's threads too, and crashed inside gRPC about once in 40 forks when it started
// workers of its own: worker devices are refused there with a message saying why, and the default
// devices become the in-process one, which renders the same image. The child's exit leaves the
// parent's workers (and their logs, which name a crashing program) alone.
TEST_F(FaultTest, ForkedChildRendersInProcessAndLeavesTheParentsWorkersAlone) {
  const std::string reference = Reference();
  Create("local:2");
  Ok(rtContextLaunch2D(ctx_, 1, kW, kH));
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    alarm(60);  // a hang fails the test instead of stalling it
    unsetenv("TESSERA_DEVICES");
    int failures = 0;
    if (rtContextLaunch2D(ctx_, 1, kW, kH) != RT_ERROR_INVALID_CONTEXT) failures |= 1;
    RTcontext own = nullptr;
    Scene scene;
    std::string error;
    if (rtContextCreate(&own) != RT_SUCCESS) {
      failures |= 2;
    } else {
      const RTresult refused = tesseraContextSetDeviceSpec(own, "local:1");
      if (refused != RT_ERROR_NOT_SUPPORTED ||
          ErrorText(own, refused).find("forked (without exec) from process") == std::string::npos) {
        failures |= 16;
      }
      if (BuildScene(own, kW, kH, &scene, &error) != RT_SUCCESS ||
          rtVariableSet1i(scene.iterations, kIterations) != RT_SUCCESS ||
          rtContextLaunch2D(own, 1, kW, kH) != RT_SUCCESS) {
        failures |= 2;
      } else if (ReadBytes(scene.image) != reference) {
        failures |= 4;
      }
      if (rtContextDestroy(own) != RT_SUCCESS) failures |= 8;
    }
    std::exit(failures);  // exit, not _exit: the host's exit handlers run in the child
  }
  int status = 0;
  ASSERT_EQ(waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFEXITED(status)) << "the child was killed by signal " << WTERMSIG(status);
  EXPECT_EQ(WEXITSTATUS(status), 0)
      << "1: the inherited context was usable, 2: the child's own launch on the default devices "
         "failed, 4: its image differs, 8: destroy failed, 16: local workers were not refused "
         "with a message naming the fork";
  EXPECT_EQ(ChildrenNamed(getpid(), kWorker).size(), 2u);
  Ok(rtContextLaunch2D(ctx_, 1, kW, kH));
  EXPECT_TRUE(ReadBytes(scene_.image) == reference);
  std::string message;
  ASSERT_EQ(LaunchCrashingProgram(&message), RT_ERROR_LAUNCH_FAILED) << message;
  EXPECT_NE(message.find("ray generation program 'render_crash'"), std::string::npos) << message;
}

// A worker timeout that is not a number of seconds from 1 up (workers send a heartbeat twice a
// second, so 0.01 would lose every working worker) is said on stderr and the default used.
TEST_F(FaultTest, AnUnusableWorkerTimeoutIsSaidAndTheDefaultUsed) {
  const std::string reference = Reference();
  setenv("TESSERA_WORKER_TIMEOUT", "0.01", 1);
  testing::internal::CaptureStderr();
  Create("local:1");
  RTresult r = rtContextLaunch2D(ctx_, 1, kW, kH);
  const std::string warning = testing::internal::GetCapturedStderr();
  unsetenv("TESSERA_WORKER_TIMEOUT");
  ASSERT_EQ(r, RT_SUCCESS) << ErrorText(ctx_, r);
  EXPECT_TRUE(ReadBytes(scene_.image) == reference);
  EXPECT_NE(warning.find("TESSERA_WORKER_TIMEOUT='0.01' is not a number of seconds from 1 up"),
            std::string::npos)
      << warning;
}

// A cancelled launch whose program never returns, on workers that cannot interrupt it (interrupts
// off; tests/semantics EndlessTest has them on), leaves its workers busy for good: the next launch
// takes them for hung after the deadline and goes on without them, instead of waiting behind the
// cancelled call forever (its queued call used to send heartbeats meanwhile).
int g_cancel_polls = 0;
int CancelOnSecondPoll() { return ++g_cancel_polls >= 2 ? 1 : 0; }

TEST_F(FaultTest, ACancelledEndlessProgramDoesNotWedgeTheNextLaunch) {
  setenv("TESSERA_WORKER_TIMEOUT", kDeadline.c_str(), 1);
  setenv("TESSERA_INTERRUPT_SIGNAL", "0", 1);  // read by the workers this starts
  Create("local:2");
  // The workers started and took the scene first, so that the cancel lands while they run the
  // endless program: workers that start slowly (built with sanitizers, or on a loaded machine)
  // were still taking the state when it came, and nothing was left running to wedge the next one.
  Ok(rtContextLaunch2D(ctx_, 0, kW, kH));
  Ok(rtVariableSet1i(scene_.iterations, std::numeric_limits<int>::max()));  // hours per index
  g_cancel_polls = 0;
  Ok(rtContextSetTimeoutCallback(ctx_, &CancelOnSecondPoll, 0.05));
  RTresult r = rtContextLaunch2D(ctx_, 1, kW, kH);
  EXPECT_EQ(r, RT_TIMEOUT_CALLBACK) << ErrorText(ctx_, r);
  Ok(rtContextSetTimeoutCallback(ctx_, nullptr, 0));
  double seconds = 0;
  std::string warning;
  r = TimedLaunch(0, &seconds, &warning);
  unsetenv("TESSERA_WORKER_TIMEOUT");
  unsetenv("TESSERA_INTERRUPT_SIGNAL");
  // Both workers may be stuck: then no device is left for this launch, and the next one runs on
  // respawned workers.
  EXPECT_TRUE(r == RT_SUCCESS || r == RT_ERROR_CONNECTION_FAILED) << ErrorText(ctx_, r);
  Ok(rtContextLaunch2D(ctx_, 0, kW, kH));
  // Here the host resends the INPUT_OUTPUT buffer the cancelled launch left unknown, so the
  // state update finds the workers hung; without one, the launch call itself does.
  EXPECT_TRUE(warning.find("sent nothing for " + kDeadline + "s") != std::string::npos ||
              warning.find("did not take the state update within " + kDeadline + "s") !=
                  std::string::npos)
      << warning;
  EXPECT_LT(seconds, 30.0);
}

// The timeout callback can ask how far the launch got: tiles done never go down and end at the
// tile count.
RTcontext g_progress_context = nullptr;
std::vector<std::pair<RTsize, RTsize>> g_progress;
int RecordProgress() {
  RTsize done = 0, total = 0;
  if (tesseraContextGetLaunchProgress(g_progress_context, &done, &total) == RT_SUCCESS) {
    g_progress.emplace_back(done, total);
  }
  return 0;
}

// Launches entry 1 in 8x8 tiles on `spec` while the timeout callback records the progress, and
// checks what holds for every launch: tiles in all are 0 while state ships (no tiles made yet),
// then the tile count; tiles done never go down and end at the tile count. Returns whether some
// poll saw the launch part-way.
constexpr RTsize kTiles = (kW / 8) * (kH / 8);
bool ProgressOfALaunch(RTcontext ctx) {
  const RTsize tile[2] = {8, 8};
  EXPECT_EQ(tesseraContextSetTileSize(ctx, 2, tile), RT_SUCCESS);
  g_progress_context = ctx;
  g_progress.clear();
  EXPECT_EQ(rtContextSetTimeoutCallback(ctx, &RecordProgress, 0.01), RT_SUCCESS);
  EXPECT_EQ(rtContextLaunch2D(ctx, 1, kW, kH), RT_SUCCESS);
  bool midway = false;
  for (size_t i = 0; i < g_progress.size(); ++i) {
    const auto [done, total] = g_progress[i];
    EXPECT_TRUE(total == 0 || total == kTiles) << total;
    EXPECT_LE(done, total);
    if (i > 0) {
      EXPECT_GE(done, g_progress[i - 1].first);
    }
    midway = midway || (done > 0 && done < kTiles);
  }
  RTsize done = 0, total = 0;
  EXPECT_EQ(tesseraContextGetLaunchProgress(ctx, &done, &total), RT_SUCCESS);
  EXPECT_EQ(done, kTiles);
  EXPECT_EQ(total, kTiles);
  return midway;
}

TEST_F(FaultTest, ProgressGrowsToTheTileCountDuringALaunch) {
  Create("local:2");
  ProgressOfALaunch(ctx_);
  EXPECT_FALSE(g_progress.empty());
  Ok(tesseraContextGetLaunchProgress(ctx_, nullptr, nullptr));
}

// One device takes a launch in one call; it still says how far the call got while it runs, so a
// long render on one device does not show 0 tiles done until the end.
TEST_F(FaultTest, ProgressMovesWhileOneDeviceRunsTheWholeLaunch) {
  for (const char* spec : {"inproc", "local:1"}) {
    SCOPED_TRACE(spec);
    Create(spec);
    Ok(rtVariableSet1i(scene_.iterations, 4 * kIterations));  // about a second on two cores
    EXPECT_TRUE(ProgressOfALaunch(ctx_))
        << "no progress seen before the launch ended (" << g_progress.size() << " polls)";
  }
}

TEST_F(FaultTest, CrashingProgramNamesDeviceAndProgram) {
  Create("local:2");
  std::string message, warning;
  ASSERT_EQ(LaunchCrashingProgram(&message, "render_crash", &warning), RT_ERROR_LAUNCH_FAILED)
      << message;
  EXPECT_NE(message.find("Tessera local worker"), std::string::npos) << message;
  EXPECT_NE(message.find("SIGSEGV"), std::string::npos) << message;
  EXPECT_NE(message.find("ray generation program 'render_crash'"), std::string::npos) << message;
  // The other worker is alive: the warning must not say that no device was left.
  EXPECT_EQ(warning.find("No other device was left"), std::string::npos) << warning;
  EXPECT_NE(warning.find("The launch ended without its tiles"), std::string::npos) << warning;
  NextLaunchWorks();
}

// exit() in a program is a crash of that program, not a lost worker: before, the tile moved to
// the other worker, ended it too, and the launch failed with "every device was lost".
TEST_F(FaultTest, ExitInAProgramNamesDeviceAndProgram) {
  Create("local:2");
  std::string message;
  ASSERT_EQ(LaunchCrashingProgram(&message, "render_exit"), RT_ERROR_LAUNCH_FAILED) << message;
  EXPECT_NE(message.find("Tessera local worker"), std::string::npos) << message;
  EXPECT_NE(message.find("exit() called in ray generation program 'render_exit'"),
            std::string::npos)
      << message;
  NextLaunchWorks();
}

// Workers a test runs itself, so that the host cannot start them again; their addresses as a
// device spec in `spec`.
void SpawnOwnWorkers(int count, std::vector<std::unique_ptr<transport::WorkerProcess>>* workers,
                     std::string* spec) {
  for (int i = 0; i < count; ++i) {
    transport::WorkerProcess::Options options;
    options.listen = "127.0.0.1:0";
    options.index = i;
    auto worker = transport::WorkerProcess::Spawn(options);
    ASSERT_TRUE(worker.ok()) << worker.status();
    *spec += (spec->empty() ? "" : ",") + (*worker)->address();
    workers->push_back(*std::move(worker));
  }
}

TEST_F(FaultTest, EveryDeviceLostIsConnectionFailed) {
  std::vector<std::unique_ptr<transport::WorkerProcess>> workers;
  std::string spec;
  ASSERT_NO_FATAL_FAILURE(SpawnOwnWorkers(2, &workers, &spec));
  Create(spec);
  Ok(rtContextLaunch2D(ctx_, 0, kW, kH));
  for (auto& worker : workers) {
    ASSERT_EQ(kill(worker->pid(), SIGKILL), 0);
    bool crashed = false;
    EXPECT_FALSE(worker->WaitForExit(absl::Seconds(10), &crashed).empty());
  }
  for (int attempt = 0; attempt < 2; ++attempt) {
    const auto start = Clock::now();
    testing::internal::CaptureStderr();
    RTresult r = rtContextLaunch2D(ctx_, 0, kW, kH);
    const std::string warning = testing::internal::GetCapturedStderr();
    EXPECT_EQ(r, RT_ERROR_CONNECTION_FAILED) << ErrorText(ctx_, r);
    if (attempt == 0) {  // the warning says what happened, not what a surviving device did
      // Lost taking the launch's state: the launch tries to start them again once, in vain.
      EXPECT_NE(warning.find("No device was left: the launch starts its devices again once"),
                std::string::npos)
          << warning;
      EXPECT_EQ(warning.find("ran on the other devices"), std::string::npos) << warning;
    }
    EXPECT_NE(ErrorText(ctx_, r).find("every device was lost"), std::string::npos)
        << ErrorText(ctx_, r);
    EXPECT_LT(std::chrono::duration<double>(Clock::now() - start).count(), 30.0);
  }
}

// A program that crashes remote workers (whose crash reports stay in their own logs) takes down
// one after the other as its tile moves: still a connection failure, but the message points at
// the program.
TEST_F(FaultTest, AProgramEndingEveryRemoteWorkerIsNamedTheLikelyCause) {
  std::vector<std::unique_ptr<transport::WorkerProcess>> workers;
  std::string spec;
  ASSERT_NO_FATAL_FAILURE(SpawnOwnWorkers(2, &workers, &spec));
  Create(spec);
  std::string message;
  ASSERT_EQ(LaunchCrashingProgram(&message), RT_ERROR_CONNECTION_FAILED) << message;
  EXPECT_NE(message.find("every device was lost"), std::string::npos) << message;
  EXPECT_NE(message.find("was running on two of them, a program may be crashing them"),
            std::string::npos)
      << message;
}

// With a third worker left, the tile that took two remote workers down is blamed once the second
// said it started running it alone (report_start): the launch fails naming the tile, instead of
// taking the third down too. (Workers killed at one moment never say so: DispatcherTest.)
TEST_F(FaultTest, ATileThatEndsTwoRemoteWorkersIsBlamedBeforeTheThird) {
  std::vector<std::unique_ptr<transport::WorkerProcess>> workers;
  std::string spec;
  ASSERT_NO_FATAL_FAILURE(SpawnOwnWorkers(3, &workers, &spec));
  Create(spec);
  std::string message;
  ASSERT_EQ(LaunchCrashingProgram(&message), RT_ERROR_LAUNCH_FAILED) << message;
  EXPECT_NE(message.find("was running alone on"), std::string::npos) << message;
  EXPECT_NE(message.find("a program may be crashing them"), std::string::npos) << message;
  int alive = 0;
  for (auto& worker : workers) {
    bool crashed = false;
    // A crashed worker may still be dying (writing its report) when the launch returns.
    alive += worker->WaitForExit(absl::Seconds(2), &crashed).empty() ? 1 : 0;
  }
  EXPECT_EQ(alive, 1);
}

// A remote worker that hangs is lost once, at the launch that found it silent (which costs the
// silence deadline); later launches do not wait for it: it is tried again in the background
// (docs/devices.md "Running workers as a service"), and said once, not at every launch.
TEST_F(FaultTest, AHungRemoteWorkerCostsOnlyTheLaunchThatLostIt) {
  std::vector<std::unique_ptr<transport::WorkerProcess>> workers;
  std::string spec;
  ASSERT_NO_FATAL_FAILURE(SpawnOwnWorkers(2, &workers, &spec));
  setenv("TESSERA_WORKER_TIMEOUT", kDeadline.c_str(), 1);
  Create(spec);
  Ok(rtContextLaunch2D(ctx_, 0, kW, kH));
  ASSERT_EQ(kill(workers[1]->pid(), SIGSTOP), 0);
  ASSERT_TRUE(WaitUntilStopped(workers[1]->pid(), std::chrono::seconds(10)));
  std::vector<double> seconds(3);
  std::vector<std::string> warnings(seconds.size());
  for (size_t i = 0; i < seconds.size(); ++i) {
    RTresult r = TimedLaunch(0, &seconds[i], &warnings[i]);
    EXPECT_EQ(r, RT_SUCCESS) << ErrorText(ctx_, r);
  }
  unsetenv("TESSERA_WORKER_TIMEOUT");
  kill(workers[1]->pid(), SIGCONT);
  EXPECT_LT(seconds[0], kDeadlineSeconds + 4.0);
  EXPECT_NE(warnings[0].find("reached again in the background"), std::string::npos) << warnings[0];
  // The later launches wait for nothing; the second says once that the worker is not answering,
  // the third says nothing more (a worker down for hours must not log at every launch).
  for (size_t i = 1; i < seconds.size(); ++i) EXPECT_LT(seconds[i], kDeadlineSeconds) << i;
  EXPECT_NE(warnings[1].find(workers[1]->address() +
                             " not answering; continuing with 1 devices, retrying in background"),
            std::string::npos)
      << warnings[1];
  EXPECT_EQ(warnings[2].find("not answering"), std::string::npos) << warnings[2];
}

// A worker says nothing while it builds its copy of a large state update: that silence is work,
// not a hang, even with the shortest deadline.
TEST_F(FaultTest, ALargeStateUpdateIsNotTakenForAHang) {
  setenv("TESSERA_WORKER_TIMEOUT", kDeadline.c_str(), 1);
  Create("local:2");
  constexpr RTsize kBytes = RTsize{1024} << 20;  // seconds to take on a slow machine
  RTbuffer ballast;
  Ok(rtBufferCreate(ctx_, RT_BUFFER_INPUT, &ballast));
  Ok(rtBufferSetFormat(ballast, RT_FORMAT_UNSIGNED_BYTE));
  Ok(rtBufferSetSize1D(ballast, kBytes));
  void* data = nullptr;
  Ok(rtBufferMap(ballast, &data));
  for (RTsize i = 0; i < kBytes; i += 4096) static_cast<unsigned char*>(data)[i] = (i >> 12) & 255;
  Ok(rtBufferUnmap(ballast));
  RTvariable v;
  Ok(rtContextDeclareVariable(ctx_, "ballast", &v));
  Ok(rtVariableSetObject(v, ballast));
  double seconds = 0;
  std::string warning;
  RTresult r = TimedLaunch(0, &seconds, &warning);
  unsetenv("TESSERA_WORKER_TIMEOUT");
  EXPECT_EQ(r, RT_SUCCESS) << ErrorText(ctx_, r);
  EXPECT_EQ(warning.find("did not take the state update"), std::string::npos) << warning;
}

// A module whose static constructor crashes its worker: the message names the module.
TEST_F(FaultTest, AModuleWhoseConstructorCrashesIsNamed) {
  setenv("TESSERA_TEST_CRASH_IN_CONSTRUCTOR", "1", 1);
  Create("local:2");
  RTprogram loaded;
  Ok(rtProgramCreateFromPTXFile(ctx_, TESSERA_E2E_CONSTRUCTOR_CRASH_MODULE, "render_loaded",
                                &loaded));
  Ok(rtContextSetRayGenerationProgram(ctx_, 0, loaded));
  testing::internal::CaptureStderr();
  RTresult r = rtContextLaunch2D(ctx_, 0, kW, kH);
  const std::string warning = testing::internal::GetCapturedStderr();
  unsetenv("TESSERA_TEST_CRASH_IN_CONSTRUCTOR");
  EXPECT_NE(r, RT_SUCCESS);
  const std::string message = ErrorText(ctx_, r) + "\n" + warning;
  EXPECT_NE(message.find("while loading program module"), std::string::npos) << message;
  EXPECT_NE(message.find("e2e_constructor_crash.so"), std::string::npos) << message;
}

}  // namespace
}  // namespace tessera::e2e

// The C API on worker processes: the same scene gives bit-identical buffers on inproc, local:1,
// local:2, a mixed inproc + worker set and running workers on 127.0.0.1 ports; a context's workers
// end with it, and with its process if that crashes; the timeout callback cancels workers promptly;
// an unreachable worker is RT_ERROR_CONNECTION_FAILED.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/prctl.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstring>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "e2e_scene.h"
#include "process_util.h"
#include "tessera/rt_ext.h"
#include "transport/worker_process.h"

extern char** environ;

namespace tessera::e2e {
namespace {

using Clock = std::chrono::steady_clock;
constexpr char kWorker[] = "tessera-worker";

class RenderTest : public ::testing::Test {
 protected:
  void TearDown() override {
    if (ctx_ != nullptr) rtContextDestroy(ctx_);
  }
  void Ok(RTresult code) { ASSERT_EQ(code, RT_SUCCESS) << ErrorText(ctx_, code); }

  // A context on `spec` holding the e2e scene.
  void Create(const char* spec, unsigned width, unsigned height) {
    if (ctx_ != nullptr) rtContextDestroy(ctx_);
    ctx_ = nullptr;
    Ok(rtContextCreate(&ctx_));
    Ok(tesseraContextSetDeviceSpec(ctx_, spec));
    std::string error;
    ASSERT_EQ(BuildScene(ctx_, width, height, &scene_, &error), RT_SUCCESS) << error;
  }

  RTcontext ctx_ = nullptr;
  Scene scene_;
};

struct Output {
  std::string image, accum;
};

TEST_F(RenderTest, SameBuffersInprocAndOnWorkerProcesses) {
  constexpr unsigned kW = 640, kH = 480;  // 4.7 MiB per float4 buffer: more than one message
  // Two running workers on ephemeral TCP ports of 127.0.0.1, as remote ones are reached.
  std::vector<std::unique_ptr<transport::WorkerProcess>> tcp_workers;
  std::string tcp;
  for (int i = 0; i < 2; ++i) {
    transport::WorkerProcess::Options options;
    options.listen = "127.0.0.1:0";
    options.index = i;
    auto worker = transport::WorkerProcess::Spawn(options);
    ASSERT_TRUE(worker.ok()) << worker.status();
    tcp += (tcp.empty() ? "" : ",") + (*worker)->address();
    tcp_workers.push_back(*std::move(worker));
  }
  std::vector<Output> outputs;
  for (const std::string& spec :
       std::vector<std::string>{"inproc", "local:1", "local:2", "inproc,local:1", tcp}) {
    SCOPED_TRACE(spec);
    Create(spec.c_str(), kW, kH);
    Ok(rtContextLaunch2D(ctx_, 0, kW, kH));
    // Change part of an INPUT buffer between launches: only changed chunks travel, and the
    // INPUT_OUTPUT accumulator must carry the merged first launch into the second.
    void* p = nullptr;
    Ok(rtBufferMap(scene_.noise, &p));
    for (unsigned i = 0; i < kW * 4; ++i) static_cast<float*>(p)[i] = 500.f;
    Ok(rtBufferUnmap(scene_.noise));
    auto start = Clock::now();
    Ok(rtContextLaunch2D(ctx_, 0, kW, kH));
    double ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
    std::printf("[ info ] %s: second %ux%u launch %.1f ms\n", spec.c_str(), kW, kH, ms);
    outputs.push_back({ReadBytes(scene_.image), ReadBytes(scene_.accum)});
  }
  const Output& inproc = outputs[0];
  ASSERT_EQ(inproc.image.size(), size_t{kW} * kH * 16);
  // The image shows spheres and background, and the accumulator holds two launches.
  std::vector<float> image(inproc.image.size() / 4), accum(image.size());
  std::memcpy(image.data(), inproc.image.data(), inproc.image.size());
  std::memcpy(accum.data(), inproc.accum.data(), inproc.accum.size());
  const size_t center = 4 * (size_t{kH} / 2 * kW + kW / 2), corner = 4 * (size_t{kH} - 1) * kW;
  EXPECT_NE(image[center], image[corner]);
  EXPECT_GT(accum[center + 3], 1.9f);  // alpha 1 + noise/1000, twice
  for (size_t i = 1; i < outputs.size(); ++i) {
    EXPECT_TRUE(outputs[i].image == inproc.image) << "image differs on device set " << i;
    EXPECT_TRUE(outputs[i].accum == inproc.accum) << "accumulator differs on device set " << i;
  }
}

TEST_F(RenderTest, DestroyingTheContextReapsItsWorkers) {
  std::vector<pid_t> before = ChildrenNamed(getpid(), kWorker);
  Create("local:2", 32, 32);
  Ok(rtContextLaunch2D(ctx_, 0, 32, 32));
  std::vector<pid_t> workers = ChildrenNamed(getpid(), kWorker);
  ASSERT_EQ(workers.size(), before.size() + 2);
  Ok(rtContextDestroy(ctx_));
  ctx_ = nullptr;
  for (pid_t pid : workers) {
    EXPECT_EQ(kill(pid, 0), -1) << "worker " << pid << " is still there (or a zombie)";
    EXPECT_EQ(errno, ESRCH);
  }
  EXPECT_TRUE(ChildrenNamed(getpid(), kWorker).empty());
}

// rtContextSetDevices on a subset of worker processes: the others are not started, and the image
// is the one every device set renders.
TEST_F(RenderTest, ASubsetOfWorkerProcessesRendersTheSameImage) {
  constexpr unsigned kW = 64, kH = 48;
  Create("inproc", kW, kH);
  Ok(rtContextLaunch2D(ctx_, 0, kW, kH));
  const std::string reference = ReadBytes(scene_.image);
  const size_t before = ChildrenNamed(getpid(), kWorker).size();
  Create("local:3", kW, kH);
  const int subset[] = {0, 2};
  Ok(rtContextSetDevices(ctx_, 2, subset));
  Ok(rtContextLaunch2D(ctx_, 0, kW, kH));
  unsigned count = 0;
  Ok(rtContextGetDeviceCount(ctx_, &count));
  EXPECT_EQ(count, 2u);
  EXPECT_EQ(ChildrenNamed(getpid(), kWorker).size(), before + 2);
  EXPECT_TRUE(ReadBytes(scene_.image) == reference);
}

// Reads `fd` until `text` appeared (empty: until it closes) or 20 s passed.
std::string ReadUntil(int fd, const std::string& text) {
  std::string output;
  const auto deadline = Clock::now() + std::chrono::seconds(20);
  while ((text.empty() || output.find(text) == std::string::npos) && Clock::now() < deadline) {
    pollfd p{fd, POLLIN, 0};
    if (poll(&p, 1, 100) <= 0) continue;
    char buf[256];
    ssize_t n = read(fd, buf, sizeof(buf));
    if (n <= 0) break;
    output.append(buf, static_cast<size_t>(n));
  }
  return output;
}

// Starts e2e_host on local:2 with `flag` (--wait, --keep-context); returns its pid (0 on failure)
// and the read end of its stdout in `out_fd`.
pid_t SpawnHost(const char* flag, int* out_fd) {
  int out[2];
  if (pipe2(out, O_CLOEXEC) != 0) return 0;
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, out[1], STDOUT_FILENO);
  std::string host = TESSERA_E2E_HOST;
  char* argv[] = {host.data(), const_cast<char*>("--spec"), const_cast<char*>("local:2"),
                  const_cast<char*>(flag), nullptr};
  pid_t pid = 0;
  if (posix_spawn(&pid, argv[0], &actions, nullptr, argv, environ) != 0) pid = 0;
  posix_spawn_file_actions_destroy(&actions);
  close(out[1]);
  *out_fd = out[0];
  return pid;
}

// A host that returns from main without destroying its context leaves no worker behind.
TEST(HostExitTest, WorkersEndWhenTheirHostExitsWithoutDestroyingItsContext) {
  // Orphans are re-parented to this process, so it sees (and reaps) any worker that outlives its
  // host.
  ASSERT_EQ(prctl(PR_SET_CHILD_SUBREAPER, 1), 0);
  ASSERT_TRUE(ChildrenNamed(getpid(), kWorker).empty());
  int out = -1;
  const pid_t host_pid = SpawnHost("--keep-context", &out);
  ASSERT_NE(host_pid, 0);
  const std::string output = ReadUntil(out, "");
  close(out);
  int status = 0;
  ASSERT_TRUE(WaitForExit(host_pid, std::chrono::seconds(10), &status));
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "status " << status << output;
  ASSERT_NE(output.find("launch 0 local:2"), std::string::npos) << output;  // it had workers
  // Reap what ends; fail if a worker is still alive after the deadline.
  const auto deadline = Clock::now() + std::chrono::seconds(10);
  while (!ChildrenNamed(getpid(), kWorker).empty() && Clock::now() < deadline) {
    while (waitpid(-1, &status, WNOHANG) > 0) {
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  EXPECT_TRUE(ChildrenNamed(getpid(), kWorker).empty()) << "a worker outlived its host";
  while (waitpid(-1, &status, WNOHANG) > 0) {
  }
}

TEST(HostCrashTest, WorkersDieWithTheirHost) {
  // Orphans are re-parented to this process, so it can reap them and see how they ended.
  ASSERT_EQ(prctl(PR_SET_CHILD_SUBREAPER, 1), 0);
  int out = -1;
  const pid_t host_pid = SpawnHost("--wait", &out);
  ASSERT_NE(host_pid, 0);
  const std::string output = ReadUntil(out, "ready\n");
  close(out);
  ASSERT_NE(output.find("ready\n"), std::string::npos) << "host said: " << output;
  std::vector<pid_t> workers = ChildrenNamed(host_pid, kWorker);
  ASSERT_EQ(workers.size(), 2u);
  // A killed host cannot remove its workers' directories (socket, log and host.pid); the next host
  // to spawn workers would, this test does.
  std::vector<std::string> directories;
  for (pid_t pid : workers) {
    std::string socket = ListenAddress(pid);
    if (socket.rfind("unix:", 0) == 0) directories.push_back(DirName(socket.substr(5)));
  }

  ASSERT_EQ(kill(host_pid, SIGKILL), 0);
  int status = 0;
  ASSERT_TRUE(WaitForExit(host_pid, std::chrono::seconds(10), &status));
  for (pid_t pid : workers) {
    ASSERT_TRUE(WaitForExit(pid, std::chrono::seconds(10), &status))
        << "worker " << pid << " outlived its host";
    EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL) << "status " << status;
  }
  for (const std::string& directory : directories) {
    for (const char* name : {"/w0.sock", "/w0.log", "/w1.sock", "/w1.log", "/host.pid"}) {
      unlink((directory + name).c_str());
    }
    EXPECT_EQ(rmdir(directory.c_str()), 0) << directory;
  }
}

std::atomic<int> g_polls{0};
std::atomic<int64_t> g_cancelled_at{0};  // steady-clock nanoseconds when the callback said stop
int CancelOnSecondPoll() {
  if (++g_polls < 2) return 0;
  g_cancelled_at = Clock::now().time_since_epoch().count();
  return 1;
}

TEST_F(RenderTest, TimeoutCallbackCancelsWorkerProcessesPromptly) {
  Create("local:2", 64, 64);
  // 64×64×200000 traces: minutes on two cores if the cancel does not reach the workers.
  Ok(rtVariableSet1i(scene_.iterations, 200000));
  Ok(rtContextSetTimeoutCallback(ctx_, &CancelOnSecondPoll, 0.05));
  g_polls = 0;
  RTresult r = rtContextLaunch2D(ctx_, 1, 64, 64);
  const auto returned = Clock::now().time_since_epoch().count();
  EXPECT_EQ(r, RT_TIMEOUT_CALLBACK) << ErrorText(ctx_, r);
  ASSERT_GE(g_polls.load(), 2);
  const double latency_ms = (returned - g_cancelled_at.load()) / 1e6;
  std::printf("[ info ] cancel to return: %.1f ms\n", latency_ms);
  EXPECT_LT(latency_ms, 5000.0);

  // The workers stopped and take the next launch.
  Ok(rtContextSetTimeoutCallback(ctx_, nullptr, 0.0));
  Ok(rtVariableSet1i(scene_.iterations, 1));
  Ok(rtContextLaunch2D(ctx_, 1, 64, 64));
  std::string bytes = ReadBytes(scene_.image);
  float first[4];
  std::memcpy(first, bytes.data(), sizeof(first));
  EXPECT_EQ(first[3], 1.f);
}

TEST_F(RenderTest, DefaultDevicesAreOneWorkerProcessPerCore) {
  Create("inproc", 64, 48);
  Ok(rtContextLaunch2D(ctx_, 0, 64, 48));
  const std::string reference = ReadBytes(scene_.image);
  rtContextDestroy(ctx_);
  ctx_ = nullptr;

  unsetenv("TESSERA_DEVICES");  // ctest sets it for tests that do not name devices
  const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
  unsigned count = 0;
  Ok(rtDeviceGetDeviceCount(&count));
  EXPECT_EQ(count, cores);
  Ok(rtContextCreate(&ctx_));
  std::string error;
  ASSERT_EQ(BuildScene(ctx_, 64, 48, &scene_, &error), RT_SUCCESS) << error;
  Ok(rtContextLaunch2D(ctx_, 0, 64, 48));
  EXPECT_EQ(ChildrenNamed(getpid(), kWorker).size(), cores);
  EXPECT_TRUE(ReadBytes(scene_.image) == reference);
  int threads = 0;
  Ok(rtDeviceGetAttribute(0, RT_DEVICE_ATTRIBUTE_MULTIPROCESSOR_COUNT, sizeof(threads), &threads));
  EXPECT_EQ(threads, 1);  // each worker gets its share of the cores
}

TEST_F(RenderTest, UnreachableWorkerIsConnectionFailed) {
  Create("unix:/nonexistent/tessera-e2e.sock", 8, 8);
  RTresult r = rtContextLaunch2D(ctx_, 0, 8, 8);
  EXPECT_EQ(r, RT_ERROR_CONNECTION_FAILED);
  EXPECT_NE(ErrorText(ctx_, r).find("unix:/nonexistent/tessera-e2e.sock"), std::string::npos)
      << ErrorText(ctx_, r);
}

}  // namespace
}  // namespace tessera::e2e

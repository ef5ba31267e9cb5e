// Bounded workers as an application sees them (tessera-worker --max-sessions and
// --session-idle-timeout, docs/devices.md), and a host refused another machine's worker for want
// of TLS and a token (docs/security.md): each is a clear RTresult with a message naming the
// worker and what to change, and a context recovers once the cause is gone.
#include <gtest/gtest.h>
#include <stdlib.h>

#include <chrono>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "e2e_scene.h"
#include "tessera/rt_ext.h"
#include "transport/worker_process.h"

namespace tessera::e2e {
namespace {

using Clock = std::chrono::steady_clock;
constexpr unsigned kW = 32, kH = 32;

// A context rendering the e2e scene on `spec`.
struct Rendering {
  RTcontext ctx = nullptr;
  Scene scene;
  ~Rendering() {
    if (ctx != nullptr) rtContextDestroy(ctx);
  }
  void Create(const std::string& spec) {
    ASSERT_EQ(rtContextCreate(&ctx), RT_SUCCESS);
    ASSERT_EQ(tesseraContextSetDeviceSpec(ctx, spec.c_str()), RT_SUCCESS)
        << ErrorText(ctx, RT_ERROR_INVALID_VALUE);
    std::string error;
    ASSERT_EQ(BuildScene(ctx, kW, kH, &scene, &error), RT_SUCCESS) << error;
  }
  // Launches entry 0; its message in `message` and its stderr in `warning` when given.
  RTresult Launch(std::string* message = nullptr, std::string* warning = nullptr) {
    testing::internal::CaptureStderr();
    const RTresult r = rtContextLaunch2D(ctx, 0, kW, kH);
    const std::string said = testing::internal::GetCapturedStderr();
    if (message != nullptr) *message = ErrorText(ctx, r);
    if (warning != nullptr) *warning = said;
    return r;
  }
};

// A worker the test runs itself on loopback TCP, as a user would run a shared one.
std::unique_ptr<transport::WorkerProcess> StartWorker(std::vector<std::string> args) {
  transport::WorkerProcess::Options options;
  options.listen = "127.0.0.1:0";
  options.threads = 1;
  options.extra_args = std::move(args);
  auto worker = transport::WorkerProcess::Spawn(options);
  EXPECT_TRUE(worker.ok()) << worker.status();
  return worker.ok() ? *std::move(worker) : nullptr;
}

// Before, the refusal was RT_ERROR_INVALID_CONTEXT, which sent users looking at their context.
TEST(WorkerLimitsTest, AnotherMachinesWorkerWithoutTlsAndATokenIsAnAuthenticationFailure) {
  for (const char* name : {"TESSERA_TLS_CA", "TESSERA_TOKEN", "TESSERA_TOKEN_FILE"}) {
    unsetenv(name);
  }
  Rendering r;
  // 192.0.2.0/24 is reserved for documentation: nothing answers there, and nothing is tried.
  ASSERT_NO_FATAL_FAILURE(r.Create("192.0.2.1:7000"));
  const auto start = Clock::now();
  std::string message;
  EXPECT_EQ(r.Launch(&message), RT_ERROR_AUTHENTICATION_FAILED) << message;
  EXPECT_LT(Clock::now() - start, std::chrono::seconds(5)) << "refused only after connecting";
  for (const char* part : {"192.0.2.1:7000", "not on this machine", "set TESSERA_TLS_CA",
                           "TESSERA_TOKEN or TESSERA_TOKEN_FILE", "docs/security.md"}) {
    EXPECT_NE(message.find(part), std::string::npos) << part << ": " << message;
  }
}

TEST(WorkerLimitsTest, AWorkerAtItsSessionLimitRefusesAnotherContextClearly) {
  std::unique_ptr<transport::WorkerProcess> worker = StartWorker({"--max-sessions", "1"});
  ASSERT_NE(worker, nullptr);
  auto first = std::make_unique<Rendering>();
  ASSERT_NO_FATAL_FAILURE(first->Create(worker->address()));
  ASSERT_EQ(first->Launch(), RT_SUCCESS);

  Rendering second;
  ASSERT_NO_FATAL_FAILURE(second.Create(worker->address()));
  std::string message;
  // The worker cannot serve this context now: to the host it is a device that cannot be reached.
  EXPECT_EQ(second.Launch(&message), RT_ERROR_CONNECTION_FAILED) << message;
  for (const char* part : {worker->address().c_str(), "already holds 1 sessions",
                           "--max-sessions 1", "Destroy contexts that are done"}) {
    EXPECT_NE(message.find(part), std::string::npos) << part << ": " << message;
  }
  // A context destroyed ends its session there, which makes room.
  first.reset();
  EXPECT_EQ(second.Launch(&message), RT_SUCCESS) << message;
}

// A host that made no call for the idle timeout finds its session gone: the worker says so as a
// lost device, and the host starts afresh on it, sending the whole state.
TEST(WorkerLimitsTest, AHostWhoseSessionWasDroppedStartsAfresh) {
  std::unique_ptr<transport::WorkerProcess> worker = StartWorker({"--session-idle-timeout", "1"});
  ASSERT_NE(worker, nullptr);
  Rendering reference;
  ASSERT_NO_FATAL_FAILURE(reference.Create("inproc"));
  ASSERT_EQ(reference.Launch(), RT_SUCCESS);
  const std::string image = ReadBytes(reference.scene.image);

  Rendering r;
  ASSERT_NO_FATAL_FAILURE(r.Create("inproc," + worker->address()));
  ASSERT_EQ(r.Launch(), RT_SUCCESS);
  std::this_thread::sleep_for(std::chrono::milliseconds(2000));  // 1.25 timeouts and more
  RTvariable changed = nullptr;  // a state update for the worker, which no longer holds the rest
  ASSERT_EQ(rtContextDeclareVariable(r.ctx, "unused_by_programs", &changed), RT_SUCCESS);
  ASSERT_EQ(rtVariableSet1f(changed, 1.f), RT_SUCCESS);
  std::string message, warning;
  ASSERT_EQ(r.Launch(&message, &warning), RT_SUCCESS) << message;
  EXPECT_EQ(ReadBytes(r.scene.image), image);
  EXPECT_NE(warning.find("dropped session"), std::string::npos) << warning;
  EXPECT_NE(warning.find("--session-idle-timeout 1"), std::string::npos) << warning;
  // The next launch runs on the worker again, in a new session.
  ASSERT_EQ(rtVariableSet1f(changed, 2.f), RT_SUCCESS);
  ASSERT_EQ(r.Launch(&message, &warning), RT_SUCCESS) << message;
  EXPECT_EQ(warning.find("dropped session"), std::string::npos) << warning;
  EXPECT_EQ(ReadBytes(r.scene.image), image);
  EXPECT_NE(worker->LogTail().find("dropped 1 session(s) without a call for 1 s"),
            std::string::npos)
      << worker->LogTail();
}

// A worker at its session limit is one device that cannot take this launch: with another device
// left, the launch runs there and says so once, instead of failing.
TEST(WorkerLimitsTest, AWorkerAtItsSessionLimitLeavesTheLaunchToTheOthers) {
  std::unique_ptr<transport::WorkerProcess> worker = StartWorker({"--max-sessions", "1"});
  ASSERT_NE(worker, nullptr);
  Rendering first;
  ASSERT_NO_FATAL_FAILURE(first.Create(worker->address()));
  ASSERT_EQ(first.Launch(), RT_SUCCESS);
  const std::string image = ReadBytes(first.scene.image);

  Rendering second;
  ASSERT_NO_FATAL_FAILURE(second.Create("inproc," + worker->address()));
  std::string message, warning;
  ASSERT_EQ(second.Launch(&message, &warning), RT_SUCCESS) << message;
  EXPECT_EQ(ReadBytes(second.scene.image), image);
  EXPECT_NE(warning.find("--max-sessions 1"), std::string::npos) << warning;
}

// The dropped session of a context's only device: the launch that finds it gone starts the device
// again with the whole state, instead of failing for want of a device.
TEST(WorkerLimitsTest, ADroppedSessionOnTheOnlyDeviceCostsNoLaunch) {
  std::unique_ptr<transport::WorkerProcess> worker = StartWorker({"--session-idle-timeout", "1"});
  ASSERT_NE(worker, nullptr);
  Rendering r;
  ASSERT_NO_FATAL_FAILURE(r.Create(worker->address()));
  ASSERT_EQ(r.Launch(), RT_SUCCESS);
  const std::string image = ReadBytes(r.scene.image);
  std::this_thread::sleep_for(std::chrono::milliseconds(2000));
  RTvariable changed = nullptr;
  ASSERT_EQ(rtContextDeclareVariable(r.ctx, "unused_by_programs", &changed), RT_SUCCESS);
  ASSERT_EQ(rtVariableSet1f(changed, 1.f), RT_SUCCESS);
  std::string message, warning;
  ASSERT_EQ(r.Launch(&message, &warning), RT_SUCCESS) << message;
  EXPECT_EQ(ReadBytes(r.scene.image), image);
  EXPECT_NE(warning.find("the launch starts its devices again once"), std::string::npos) << warning;
}

}  // namespace
}  // namespace tessera::e2e

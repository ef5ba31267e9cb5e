// Crash reports that always name the program (worker/core crash_report.h), on local:N worker
// processes: a program that overflows its stack (the SIGSEGV handler runs on the thread's
// alternate signal stack) and one that calls exit() or quick_exit(), in ray generation programs
// (threads that run tiles) and bounding box programs (threads that build accelerations). Each
// fails the launch with RT_ERROR_LAUNCH_FAILED naming the device and the program, rather than
// taking every worker down one after the other (RT_ERROR_CONNECTION_FAILED); the next launch works
// on a respawned worker.
#include <gtest/gtest.h>
#include <unistd.h>

#include <string>

#include "../common/scoped_env.h"
#include "e2e_scene.h"
#include "process_util.h"
#include "tessera/rt_ext.h"

namespace tessera::e2e {
namespace {

constexpr char kWorker[] = "tessera-worker";
constexpr unsigned kW = 32, kH = 32;

class CrashReportTest : public ::testing::Test {
 protected:
  void TearDown() override {
    if (ctx_ != nullptr) rtContextDestroy(ctx_);
  }
  void Ok(RTresult code) { ASSERT_EQ(code, RT_SUCCESS) << ErrorText(ctx_, code); }
  // `warm`: workers up and holding the scene before the test's launch (a program set afterwards
  // arrives in a state update); otherwise the test's launch starts them.
  void Create(const std::string& spec, bool warm) {
    Ok(rtContextCreate(&ctx_));
    Ok(tesseraContextSetDeviceSpec(ctx_, spec.c_str()));
    std::string error;
    ASSERT_EQ(BuildScene(ctx_, kW, kH, &scene_, &error), RT_SUCCESS) << error;
    if (warm) Ok(rtContextLaunch2D(ctx_, 0, kW, kH));
  }
  RTprogram Program(const char* function) {
    RTprogram program = nullptr;
    EXPECT_EQ(rtProgramCreateFromPTXFile(ctx_, TESSERA_E2E_CRASH_MODULE, function, &program),
              RT_SUCCESS)
        << ErrorText(ctx_, RT_ERROR_INVALID_VALUE);
    return program;
  }
  // The scene's one geometry (spheres), through the graph the scene hangs from top_object.
  RTgeometry Geometry() {
    RTvariable top = nullptr;
    RTobject object = nullptr;
    RTgeometryinstance instance = nullptr;
    RTgeometry geometry = nullptr;
    EXPECT_EQ(rtContextQueryVariable(ctx_, "top_object", &top), RT_SUCCESS);
    EXPECT_EQ(rtVariableGetObject(top, &object), RT_SUCCESS);
    EXPECT_EQ(rtGeometryGroupGetChild(reinterpret_cast<RTgeometrygroup>(object), 0, &instance),
              RT_SUCCESS);
    EXPECT_EQ(rtGeometryInstanceGetGeometry(instance, &geometry), RT_SUCCESS);
    return geometry;
  }
  // Launches entry 0, returning its result, its message in `message` and its stderr in `warning`.
  RTresult Launch(std::string* message, std::string* warning) {
    testing::internal::CaptureStderr();
    const RTresult r = rtContextLaunch2D(ctx_, 0, kW, kH);
    *warning = testing::internal::GetCapturedStderr();
    *message = ErrorText(ctx_, r);
    return r;
  }
  // After a program ended a worker: the next launch of a working program runs on a respawned one.
  void NextLaunchWorks(RTgeometry geometry, size_t workers) {
    RTprogram bounds = nullptr, render = nullptr;
    Ok(rtProgramCreateFromPTXFile(ctx_, ModulePath(), "sphere_bounds", &bounds));
    Ok(rtProgramCreateFromPTXFile(ctx_, ModulePath(), "render", &render));
    if (geometry != nullptr) Ok(rtGeometrySetBoundingBoxProgram(geometry, bounds));
    Ok(rtContextSetRayGenerationProgram(ctx_, 0, render));
    testing::internal::CaptureStderr();
    const RTresult r = rtContextLaunch2D(ctx_, 0, kW, kH);
    testing::internal::GetCapturedStderr();
    Ok(r);
    EXPECT_EQ(ChildrenNamed(getpid(), kWorker).size(), workers);
  }

  // render_overflow on local:2 fails the launch with a report naming the device and the program,
  // and the next launch works.
  void ExpectRayGenerationOverflowReport() {
    ASSERT_NO_FATAL_FAILURE(Create("local:2", /*warm=*/true));
    Ok(rtContextSetRayGenerationProgram(ctx_, 0, Program("render_overflow")));
    std::string message, warning;
    ASSERT_EQ(Launch(&message, &warning), RT_ERROR_LAUNCH_FAILED) << message << "\n" << warning;
    for (const char* part : {"Tessera local worker", "signal 11 (SIGSEGV)",
                             "in ray generation program 'render_overflow'"}) {
      EXPECT_NE(message.find(part), std::string::npos) << part << ": " << message;
    }
    EXPECT_EQ(warning.find("No other device was left"), std::string::npos) << warning;
    NextLaunchWorks(nullptr, 2);
  }

  RTcontext ctx_ = nullptr;
  Scene scene_;
};

// Before the alternate signal stack, the overflowing worker died without a report, the tile moved
// to the other worker and ended it too, and the launch failed with "every device was lost".
TEST_F(CrashReportTest, AStackOverflowInARayGenerationProgramNamesDeviceAndProgram) {
  ExpectRayGenerationOverflowReport();
}

// Batched, the overflow comes in the run that collects each launch index's first ray for a packet
// (docs/programs.md, "Batched tracing"): the report names the program all the same.
TEST_F(CrashReportTest, AStackOverflowWhileCollectingRaysNamesDeviceAndProgram) {
  const test::ScopedEnv batching("TESSERA_BATCHING", "1");
  ExpectRayGenerationOverflowReport();
}

TEST_F(CrashReportTest, AStackOverflowInABoundingBoxProgramNamesDeviceAndProgram) {
  ASSERT_NO_FATAL_FAILURE(Create("local:1", /*warm=*/false));
  const RTgeometry geometry = Geometry();
  Ok(rtGeometrySetBoundingBoxProgram(geometry, Program("bounds_overflow")));
  std::string message, warning;
  ASSERT_EQ(Launch(&message, &warning), RT_ERROR_LAUNCH_FAILED) << message << "\n" << warning;
  for (const char* part : {"Tessera local worker", "signal 11 (SIGSEGV)",
                           "in bounding box program 'bounds_overflow'"}) {
    EXPECT_NE(message.find(part), std::string::npos) << part << ": " << message;
  }
  NextLaunchWorks(geometry, 1);
}

// exit() runs the calling thread's thread_local destructors before the exit hook: the report
// names the program without reading the thread's freed state.
TEST_F(CrashReportTest, ExitInABoundingBoxProgramNamesDeviceAndProgram) {
  ASSERT_NO_FATAL_FAILURE(Create("local:1", /*warm=*/false));
  const RTgeometry geometry = Geometry();
  Ok(rtGeometrySetBoundingBoxProgram(geometry, Program("bounds_exit")));
  std::string message, warning;
  ASSERT_EQ(Launch(&message, &warning), RT_ERROR_LAUNCH_FAILED) << message << "\n" << warning;
  for (const char* part :
       {"Tessera local worker", "exit() called in bounding box program 'bounds_exit'"}) {
    EXPECT_NE(message.find(part), std::string::npos) << part << ": " << message;
  }
  NextLaunchWorks(geometry, 1);
}

TEST_F(CrashReportTest, QuickExitInARayGenerationProgramNamesDeviceAndProgram) {
  ASSERT_NO_FATAL_FAILURE(Create("local:2", /*warm=*/true));
  Ok(rtContextSetRayGenerationProgram(ctx_, 0, Program("render_quick_exit")));
  std::string message, warning;
  ASSERT_EQ(Launch(&message, &warning), RT_ERROR_LAUNCH_FAILED) << message << "\n" << warning;
  for (const char* part :
       {"Tessera local worker", "exit() called in ray generation program 'render_quick_exit'"}) {
    EXPECT_NE(message.find(part), std::string::npos) << part << ": " << message;
  }
  EXPECT_EQ(warning.find("No other device was left"), std::string::npos) << warning;
  NextLaunchWorks(nullptr, 2);
}

}  // namespace
}  // namespace tessera::e2e

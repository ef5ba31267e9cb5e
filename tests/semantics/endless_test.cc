// A program that never returns (an endless loop) does not hang a cancelled launch: the timeout
// callback's cancel ends the launch with RT_TIMEOUT_CALLBACK wherever the program loops, and the
// device runs the next launch at once. On an in-process device and on worker processes.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <string>
#include <thread>
#include <vector>

#include "rt_fixture.h"

#ifdef TESSERA_SANITIZER_BUILD
// What an interrupt's jump skips is not cleaned up, as docs/devices.md ("Faults") says: a program
// stopped in a print longer than 2 KiB loses the text being made (heap), one stopped in a catch
// block loses the exception it was handling. LeakSanitizer (tools/sanitize.sh) would report them
// when the test process exits: those tests turn its check off, with the reason on stderr. ASan
// and UBSan still check them.
namespace {
std::atomic<const char*> g_leak_check_off_because{nullptr};
}  // namespace
extern "C" int __lsan_is_turned_off() {
  const char* why = g_leak_check_off_because.load();
  if (why != nullptr) std::fprintf(stderr, "sanitize: no leak check in this test: %s\n", why);
  return why != nullptr ? 1 : 0;
}
#endif

namespace tessera::testing {
namespace {

// Under the sanitizers, turns LeakSanitizer's check off for this test process (above).
void ExpectLeaksOfTheJump(const char* why) {
#ifdef TESSERA_SANITIZER_BUILD
  g_leak_check_off_because = why;
#else
  (void)why;
#endif
}

constexpr char kModule[] = "endless_programs";
constexpr unsigned kWidth = 4, kHeight = 2;
constexpr int kEndlessAt = 1;  // launch index x that loops

int CancelAlways() { return 1; }

double Seconds(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

class EndlessTest : public OnDevicesFixture {
 protected:
  void SetUp() override {
    OnDevicesFixture::SetUp();
    result_ = Buffer2D("result", RT_BUFFER_OUTPUT, RT_FORMAT_FLOAT, kWidth, kHeight);
    Ok(rtVariableSet1i(ContextVar("endless_at"), kEndlessAt));
  }

  // A unit box at the origin every traced ray hits, with intersection and closest-hit programs
  // `intersect` and `closest_hit`; `miss` for rays of an empty scene instead when `hit` is false.
  void Scene(const char* intersect, const char* closest_hit, const char* miss, bool hit) {
    Instance box = MakeInstance(Program(kModule, intersect), Program(kModule, "unit_bounds"), 1,
                                Program(kModule, closest_hit));
    if (!hit) Ok(rtGeometryGroupSetChildCount(box.group, 0));
    Ok(rtVariableSetObject(ContextVar("top_object"), box.group));
    Ok(rtContextSetMissProgram(ctx_, 0, Program(kModule, miss)));
  }

  // Launches with `raygen` and a callback that cancels at its first poll: the launch must end as
  // cancelled. Then, with no index looping and no callback, the next launch must work at once
  // (a worker still spinning would hold it up for TESSERA_WORKER_TIMEOUT, 10 s) and write 1
  // everywhere. A launch with nothing looping comes first, so that the cancel finds the devices
  // running programs: on worker processes that start with the first launch, a cancel while the
  // state ships to them would end the launch before any program ran. `rebuild`: an acceleration
  // to build again in the cancelled launch (its bounding box programs loop).
  void ExpectCancelledThenWorking(const char* raygen, RTacceleration rebuild = nullptr) {
    Ok(rtContextSetRayGenerationProgram(ctx_, 0, Program(kModule, raygen)));
    Ok(rtVariableSet1i(ContextVar("endless_at"), -1));
    RTresult code = rtContextLaunch2D(ctx_, 0, kWidth, kHeight);
    ASSERT_EQ(code, RT_SUCCESS) << Error(code);
    Ok(rtVariableSet1i(ContextVar("endless_at"), kEndlessAt));
    if (rebuild != nullptr) Ok(rtAccelerationMarkDirty(rebuild));

    Ok(rtContextSetTimeoutCallback(ctx_, &CancelAlways, 0.05));
    auto start = std::chrono::steady_clock::now();
    code = rtContextLaunch2D(ctx_, 0, kWidth, kHeight);
    EXPECT_EQ(code, RT_TIMEOUT_CALLBACK) << Error(code);
    ExpectBatchedIfAsked();
    EXPECT_LT(Seconds(start), 30.0);

    Ok(rtContextSetTimeoutCallback(ctx_, nullptr, 0.0));
    Ok(rtVariableSet1i(ContextVar("endless_at"), -1));
    start = std::chrono::steady_clock::now();
    code = rtContextLaunch2D(ctx_, 0, kWidth, kHeight);
    ASSERT_EQ(code, RT_SUCCESS) << Error(code);
    EXPECT_LT(Seconds(start), 5.0) << "the device was still busy with the endless program";
    for (float v : ReadAs<float>(result_)) EXPECT_EQ(v, 1.f);
  }

  RTbuffer result_ = nullptr;
};

TEST_P(EndlessTest, ALoopInProgramCode) {
  Scene("quick_intersect", "quick_closest_hit", "loop_miss", true);
  ExpectCancelledThenWorking("loop_raygen");
}

// The loop spends its time in libm, outside program code, but for its own few instructions.
TEST_P(EndlessTest, ALoopCallingLibm) {
  Scene("quick_intersect", "quick_closest_hit", "loop_miss", true);
  ExpectCancelledThenWorking("libm_raygen");
}

// A loop of rtTrace calls spends its time in the engine and Embree.
TEST_P(EndlessTest, ALoopOfTraces) {
  Scene("quick_intersect", "quick_closest_hit", "loop_miss", true);
  ExpectCancelledThenWorking("trace_loop_raygen");
}

TEST_P(EndlessTest, AClosestHitProgramUnderTrace) {
  Scene("quick_intersect", "loop_closest_hit", "loop_miss", true);
  ExpectCancelledThenWorking("trace_raygen");
}

TEST_P(EndlessTest, AMissProgramUnderTrace) {
  Scene("quick_intersect", "quick_closest_hit", "loop_miss", false);
  ExpectCancelledThenWorking("trace_raygen");
}

// The intersection program runs inside Embree's traversal, which the jump leaves too.
TEST_P(EndlessTest, AnIntersectionProgramInsideTraversal) {
  Scene("loop_intersect", "quick_closest_hit", "loop_miss", true);
  ExpectCancelledThenWorking("trace_raygen");
}

// Bounding box programs run while the launch builds its accelerations, before any tile.
TEST_P(EndlessTest, ABoundingBoxProgram) {
  Instance box = MakeInstance(Program(kModule, "quick_intersect"), Program(kModule, "loop_bounds"),
                              1, Program(kModule, "quick_closest_hit"));
  Ok(rtVariableSetObject(ContextVar("top_object"), box.group));
  Ok(rtContextSetMissProgram(ctx_, 0, Program(kModule, "loop_miss")));
  RTacceleration accel = nullptr;
  Ok(rtGeometryGroupGetAcceleration(box.group, &accel));
  ExpectCancelledThenWorking("trace_raygen", accel);
}

// rtPrintf in a loop spends its time formatting, in libc and the engine.
TEST_P(EndlessTest, ALoopOfPrints) {
  ExpectLeaksOfTheJump("the interrupted print's 100 kB line (docs/devices.md, Faults)");
  Scene("quick_intersect", "quick_closest_hit", "loop_miss", true);
  Ok(rtContextSetPrintEnabled(ctx_, 1));
  ExpectCancelledThenWorking("print_loop_raygen");
}

// Throwing and catching C++ exceptions in a loop spends its time in the unwinder.
TEST_P(EndlessTest, ALoopOfCaughtExceptions) {
  Scene("quick_intersect", "quick_closest_hit", "loop_miss", true);
  ExpectCancelledThenWorking("throw_loop_raygen");
}

// A loop inside a catch block: the exception it was handling does not stay active on the thread.
TEST_P(EndlessTest, ALoopInACatchBlock) {
  ExpectLeaksOfTheJump(
      "the exception the interrupted catch block handled (docs/devices.md, Faults)");
  Scene("quick_intersect", "quick_closest_hit", "loop_miss", true);
  ExpectCancelledThenWorking("catch_loop_raygen");
}

// Several launches in a row, each interrupted: nothing the jumps skipped piles up or breaks
// the next launch.
TEST_P(EndlessTest, InterruptedAgainAndAgain) {
  Scene("loop_intersect", "loop_closest_hit", "loop_miss", true);
  for (int i = 0; i < 3; ++i) {
    ExpectCancelledThenWorking(i % 2 == 0 ? "trace_raygen" : "loop_raygen");
  }
}

// A bounding box program that never returns in one in-process context, whose launch nothing
// cancels yet, does not hold up acceleration builds of another context in the same process.
std::atomic<bool> g_other_done{false};
int CancelOnceOtherIsDone() { return g_other_done.load() ? 1 : 0; }

class EndlessContextsTest : public RtFixture {
 protected:
  // A context on an in-process device tracing a box whose bounding box program never returns
  // when `endless`. Made with the fixture's helpers, which work on ctx_.
  RTcontext BoxContext(bool endless) {
    RTcontext fixture_context = ctx_;
    EXPECT_EQ(rtContextCreate(&ctx_), RT_SUCCESS);
    RTcontext made = ctx_;
    Ok(tesseraContextSetDeviceSpec(ctx_, "inproc"));
    Ok(rtContextSetEntryPointCount(ctx_, 1));
    Ok(rtContextSetRayTypeCount(ctx_, 1));
    Buffer2D("result", RT_BUFFER_OUTPUT, RT_FORMAT_FLOAT, kWidth, kHeight);
    Ok(rtVariableSet1i(ContextVar("endless_at"), endless ? kEndlessAt : -1));
    Instance box =
        MakeInstance(Program(kModule, "quick_intersect"), Program(kModule, "loop_bounds"), 1,
                     Program(kModule, "quick_closest_hit"));
    Ok(rtVariableSetObject(ContextVar("top_object"), box.group));
    Ok(rtContextSetMissProgram(ctx_, 0, Program(kModule, "loop_miss")));
    Ok(rtContextSetRayGenerationProgram(ctx_, 0, Program(kModule, "trace_raygen")));
    ctx_ = fixture_context;
    return made;
  }
};

TEST_F(EndlessContextsTest, AStuckBuildDoesNotHoldUpAnotherContext) {
  g_other_done = false;
  RTcontext stuck = BoxContext(true);
  RTcontext other = BoxContext(false);
  ASSERT_EQ(rtContextSetTimeoutCallback(stuck, &CancelOnceOtherIsDone, 0.02), RT_SUCCESS);
  RTresult stuck_code = RT_SUCCESS;
  std::thread launcher([&] { stuck_code = rtContextLaunch2D(stuck, 0, kWidth, kHeight); });
  std::this_thread::sleep_for(std::chrono::milliseconds(200));  // its build is under way
  const auto start = std::chrono::steady_clock::now();
  EXPECT_EQ(rtContextLaunch2D(other, 0, kWidth, kHeight), RT_SUCCESS);
  EXPECT_LT(Seconds(start), 10.0);
  g_other_done = true;
  launcher.join();
  EXPECT_EQ(stuck_code, RT_TIMEOUT_CALLBACK);
  rtContextDestroy(stuck);
  rtContextDestroy(other);
}

// Batched, each launch index's ray generation program first runs alone up to its first rtTrace
// (its rays collected for a packet): a loop there, or in a loop of traces, must end the same way.
INSTANTIATE_TEST_SUITE_P(Devices, EndlessTest,
                         ::testing::Values("inproc", "local:2", "batched:inproc",
                                           "batched:local:2"),
                         DeviceName);

}  // namespace
}  // namespace tessera::testing

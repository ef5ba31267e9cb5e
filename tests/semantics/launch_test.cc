// Launch behaviour on the real in-process device: the timeout callback is polled during a long
// launch and cancels it promptly; CPU_NUM_THREADS is honoured.
#include <atomic>
#include <limits>

#include "rt_fixture.h"
#include "tessera/rt_ext.h"

namespace tessera::testing {
namespace {

constexpr char kModule[] = "semantics_programs";

std::atomic<int> g_polls{0};
int CancelOnSecondPoll() { return ++g_polls >= 2 ? 1 : 0; }
int NeverCancel() {
  ++g_polls;
  return 0;
}

class LaunchTest : public RtFixture {
 protected:
  void SetUp() override {
    RtFixture::SetUp();
    Ok(rtContextSetEntryPointCount(ctx_, 1));
    Ok(rtContextSetRayTypeCount(ctx_, 1));
    result_ = Float4Buffer("result", RT_BUFFER_OUTPUT, kW, kH);
    Float4Buffer("is_log", RT_BUFFER_OUTPUT, kW, kH);
    Float4Buffer("ah_log", RT_BUFFER_OUTPUT, kW, kH);
    Instance s =
        MakeInstance(Program(kModule, "sphere_intersect"), Program(kModule, "sphere_bounds"), 1,
                     Program(kModule, "closest_hit_ray"));
    RTvariable v = nullptr;
    Ok(rtGeometryDeclareVariable(s.geometry, "sphere", &v));
    Ok(rtVariableSet4f(v, 0.f, 0.f, 0.f, 1.f));
    Ok(rtVariableSetObject(ContextVar("top_object"), s.group));
    Ok(rtVariableSet3f(ContextVar("ray_origin"), 0.f, 0.f, -10.f));
    Ok(rtVariableSet3f(ContextVar("ray_dir"), 0.f, 0.f, 1.f));
    Ok(rtContextSetRayGenerationProgram(ctx_, 0, Program(kModule, "raygen_slow")));
    Ok(rtContextSetMissProgram(ctx_, 0, Program(kModule, "miss_ray")));
  }
  static constexpr size_t kW = 64, kH = 64;
  RTbuffer result_ = nullptr;
};

// Uncancelled, this launch traces 64*64*50000 rays (minutes on two cores); the callback
// cancels it on its second poll. A broken cancel shows up as the test's ctest timeout.
TEST_F(LaunchTest, TimeoutCallbackCancelsALongLaunch) {
  g_polls = 0;
  Ok(rtVariableSet1i(ContextVar("iterations"), 50000));
  Ok(rtContextSetTimeoutCallback(ctx_, &CancelOnSecondPoll, 0.02));
  RTresult r = rtContextLaunch2D(ctx_, 0, kW, kH);
  EXPECT_EQ(r, RT_TIMEOUT_CALLBACK) << Error(r);
  EXPECT_GE(g_polls.load(), 2);
  // The context stays usable: a short launch afterwards completes.
  Ok(rtContextSetTimeoutCallback(ctx_, &NeverCancel, 10.0));
  Ok(rtVariableSet1i(ContextVar("iterations"), 1));
  Ok(rtContextLaunch2D(ctx_, 0, kW, kH));
  EXPECT_NEAR(Read(result_)[0][0], 9.f, 1e-4f);  // one hit at t = 9
}

// An infinite polling interval means never (it overflowed the clock and polled in a busy loop).
TEST_F(LaunchTest, AnInfinitePollingIntervalNeverCalls) {
  g_polls = 0;
  Ok(rtVariableSet1i(ContextVar("iterations"), 20));
  Ok(rtContextSetTimeoutCallback(ctx_, &NeverCancel, std::numeric_limits<double>::infinity()));
  Ok(rtContextLaunch2D(ctx_, 0, kW, kH));
  EXPECT_EQ(g_polls.load(), 0);
}

// A callback that removes itself is not called again during the same launch.
RTcontext g_context = nullptr;
int RemoveItself() {
  ++g_polls;
  rtContextSetTimeoutCallback(g_context, nullptr, 0.0);
  return 0;
}
TEST_F(LaunchTest, ACallbackRemovedFromInsideItselfIsNotCalledAgain) {
  g_polls = 0;
  g_context = ctx_;
  Ok(rtVariableSet1i(ContextVar("iterations"), 2000));
  Ok(rtContextSetTimeoutCallback(ctx_, &RemoveItself, 0.001));
  Ok(rtContextLaunch2D(ctx_, 0, kW, kH));
  EXPECT_EQ(g_polls.load(), 1);
}

// The callback runs while the launch ships its state to devices (here 64 MiB of a new INPUT
// buffer), before any tile: tiles in all are still 0 then, and a cancel there ends the launch.
RTsize g_total_seen = 1;
int CancelAndSeeTotal() {
  ++g_polls;
  RTsize done = 0;
  tesseraContextGetLaunchProgress(g_context, &done, &g_total_seen);
  return 1;
}
TEST_F(LaunchTest, TheCallbackRunsAndCancelsWhileStateShips) {
  RTbuffer big = nullptr;
  Ok(rtBufferCreate(ctx_, RT_BUFFER_INPUT, &big));
  Ok(rtBufferSetFormat(big, RT_FORMAT_FLOAT4));
  Ok(rtBufferSetSize1D(big, (64u << 20) / 16));
  Ok(rtVariableSetObject(ContextVar("unused_big_input"), big));
  Ok(rtVariableSet1i(ContextVar("iterations"), 1));
  g_polls = 0;
  g_context = ctx_;
  g_total_seen = 1;
  Ok(rtContextSetTimeoutCallback(ctx_, &CancelAndSeeTotal, 0.001));
  RTresult r = rtContextLaunch2D(ctx_, 0, kW, kH);
  EXPECT_EQ(r, RT_TIMEOUT_CALLBACK) << Error(r);
  EXPECT_EQ(g_polls.load(), 1);
  EXPECT_EQ(g_total_seen, 0u) << "the first call came after tiles were made";
  Ok(rtContextSetTimeoutCallback(ctx_, nullptr, 0.0));
  Ok(rtContextLaunch2D(ctx_, 0, kW, kH));
  EXPECT_NEAR(Read(result_)[0][0], 9.f, 1e-4f);
}

TEST_F(LaunchTest, OneThreadGivesTheSameImageAsAllThreads) {
  Ok(rtVariableSet1i(ContextVar("iterations"), 3));
  Ok(rtContextLaunch2D(ctx_, 0, kW, kH));
  std::vector<Float4> all = Read(result_);
  int one = 1;
  Ok(rtContextSetAttribute(ctx_, RT_CONTEXT_ATTRIBUTE_CPU_NUM_THREADS, sizeof(one), &one));
  Ok(rtContextLaunch2D(ctx_, 0, kW, kH));
  EXPECT_EQ(Read(result_), all);
}

}  // namespace
}  // namespace tessera::testing

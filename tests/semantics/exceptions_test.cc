// Each exception of OptiX 3 (stack overflow, buffer index out of bounds, invalid ray, user codes),
// on and off per rtContextSetExceptionEnabled, with the exception program at its launch index;
// with single rays and batched (TESSERA_BATCHING=1: each ray generation program first runs alone
// up to its first rtTrace, where an exception must not be raised twice).
#include <string>

#include "rt_fixture.h"
#include "tessera/rt_ext.h"

namespace tessera::testing {
namespace {

constexpr char kModule[] = "semantics_programs";

class ExceptionsTest : public OnDevicesFixture {
 protected:
  static constexpr size_t kW = 3;
  void SetUp() override {
    OnDevicesFixture::SetUp();
    result_ = Float4Buffer("result", RT_BUFFER_OUTPUT, kW, 1);
    Float4Buffer("is_log", RT_BUFFER_OUTPUT, kW, 1);
    Float4Buffer("ah_log", RT_BUFFER_OUTPUT, kW, 1);
    Ok(rtContextSetExceptionProgram(ctx_, 0, Program(kModule, "exception_record")));
    Ok(rtContextSetMissProgram(ctx_, 0, Program(kModule, "miss_ray")));
    sphere_ = MakeInstance(Program(kModule, "sphere_intersect"), Program(kModule, "sphere_bounds"),
                           1, Program(kModule, "closest_hit_recurse"));
    RTvariable v = nullptr;
    Ok(rtGeometryDeclareVariable(sphere_.geometry, "sphere", &v));
    Ok(rtVariableSet4f(v, 0.f, 0.f, 0.f, 5.f));  // every ray hits it
    Ok(rtVariableSetObject(ContextVar("top_object"), sphere_.group));
    Ok(rtVariableSet3f(ContextVar("ray_origin"), 0.f, 0.f, -10.f));
    Ok(rtVariableSet3f(ContextVar("ray_dir"), 0.f, 0.f, 1.f));
  }
  std::vector<Float4> Run(const char* raygen, RTexception e, bool enabled) {
    Ok(rtContextSetExceptionEnabled(ctx_, e, enabled ? 1 : 0));
    Ok(rtContextSetRayGenerationProgram(ctx_, 0, Program(kModule, raygen)));
    RTresult r = rtContextLaunch2D(ctx_, 0, kW, 1);
    EXPECT_EQ(r, RT_SUCCESS) << Error(r);
    ExpectBatchedIfAsked();
    return Read(result_);
  }
  RTbuffer result_ = nullptr;
  Instance sphere_;
};

TEST_P(ExceptionsTest, StackOverflowIsOnByDefault) {
  int enabled = 0;
  Ok(rtContextGetExceptionEnabled(ctx_, RT_EXCEPTION_STACK_OVERFLOW, &enabled));
  EXPECT_EQ(enabled, 1);
  Ok(rtContextSetRayGenerationProgram(ctx_, 0, Program(kModule, "trace_camera")));
  Ok(rtContextLaunch2D(ctx_, 0, kW, 1));
  std::vector<Float4> r = Read(result_);
  for (size_t x = 0; x < kW; ++x) {
    EXPECT_EQ(r[x][0], float(RT_EXCEPTION_STACK_OVERFLOW));
    EXPECT_EQ(r[x][1], float(x));  // the exception program runs at the failing launch index
  }
}

TEST_P(ExceptionsTest, StackOverflowOffSkipsTheTooDeepTrace) {
  std::vector<Float4> r = Run("trace_camera", RT_EXCEPTION_STACK_OVERFLOW, false);
  EXPECT_EQ(r[0][0], 1.f);  // closest_hit_recurse's own write, after the skipped trace
}

// Programs' locals take native stack too: deep enough nesting of a program with large locals
// raises the stack overflow exception (or skips the trace) instead of crashing the device.
TEST_P(ExceptionsTest, StackOverflowWhenLocalsFillTheNativeStack) {
  Ok(rtContextSetStackSize(ctx_, 131072));  // 1024 levels
  Ok(rtMaterialSetClosestHitProgram(sphere_.material, 0,
                                    Program(kModule, "closest_hit_recurse_heavy")));
  std::vector<Float4> on = Run("trace_camera", RT_EXCEPTION_STACK_OVERFLOW, true);
  for (size_t x = 0; x < kW; ++x) EXPECT_EQ(on[x][0], float(RT_EXCEPTION_STACK_OVERFLOW));
  std::vector<Float4> off = Run("trace_camera", RT_EXCEPTION_STACK_OVERFLOW, false);
  EXPECT_EQ(off[0][0], 1.f);  // the program's own write, after the skipped trace
}

TEST_P(ExceptionsTest, UserExceptionOnlyWhenEnabled) {
  std::vector<Float4> off = Run("raygen_throw", RT_EXCEPTION_USER, false);
  EXPECT_EQ(off[1][0], 1.f);
  std::vector<Float4> on = Run("raygen_throw", RT_EXCEPTION_USER, true);
  EXPECT_EQ(on[0][0], 1.f);
  EXPECT_EQ(on[1][0], float(RT_EXCEPTION_USER + 7));
  EXPECT_EQ(on[2][0], 1.f);
}

// An exception raised inside the exception program ends its launch index and is reported like
// one no exception program handled, not lost.
TEST_P(ExceptionsTest, AnExceptionInTheExceptionProgramIsReported) {
  Ok(rtContextSetExceptionProgram(ctx_, 0, Program(kModule, "exception_out_of_bounds")));
  Ok(rtContextSetExceptionEnabled(ctx_, RT_EXCEPTION_BUFFER_INDEX_OUT_OF_BOUNDS, 1));
  Ok(rtContextSetPrintEnabled(ctx_, 1));
  ::testing::internal::CaptureStdout();
  Run("raygen_throw", RT_EXCEPTION_USER, true);
  const std::string out = ::testing::internal::GetCapturedStdout();
  RTsize count = 0;
  Ok(tesseraContextGetExceptionReportCount(ctx_, &count));
  EXPECT_EQ(count, 1u);
  // Named once: the details of the failed index say where it was (no "(raised in …)" repeating).
  const std::string where = "exception program 'exception_out_of_bounds'";
  const size_t at = out.find(where);
  ASSERT_NE(at, std::string::npos) << out;
  EXPECT_EQ(out.find(where, at + 1), std::string::npos) << out;
}

TEST_P(ExceptionsTest, BufferIndexOutOfBoundsOnlyWhenEnabled) {
  std::vector<Float4> off =
      Run("raygen_out_of_bounds", RT_EXCEPTION_BUFFER_INDEX_OUT_OF_BOUNDS, false);
  EXPECT_EQ(off[0][0], 1.f);
  std::vector<Float4> on =
      Run("raygen_out_of_bounds", RT_EXCEPTION_BUFFER_INDEX_OUT_OF_BOUNDS, true);
  EXPECT_EQ(on[0][0], float(RT_EXCEPTION_BUFFER_INDEX_OUT_OF_BOUNDS));
}

TEST_P(ExceptionsTest, InvalidRaysOnlyWhenEnabled) {
  for (int mode = 0; mode < 4; ++mode) {
    Ok(rtVariableSet1i(ContextVar("mode"), mode));
    std::vector<Float4> off = Run("raygen_invalid_ray", RT_EXCEPTION_INVALID_RAY, false);
    EXPECT_EQ(off[0][0], 1.f) << "mode " << mode;
    std::vector<Float4> on = Run("raygen_invalid_ray", RT_EXCEPTION_INVALID_RAY, true);
    EXPECT_EQ(on[0][0], float(RT_EXCEPTION_INVALID_RAY)) << "mode " << mode;
  }
}

TEST_P(ExceptionsTest, AllTogglesEveryCode) {
  Ok(rtContextSetExceptionEnabled(ctx_, RT_EXCEPTION_ALL, 1));
  for (RTexception e : {RT_EXCEPTION_STACK_OVERFLOW, RT_EXCEPTION_BUFFER_INDEX_OUT_OF_BOUNDS,
                        RT_EXCEPTION_INVALID_RAY, RT_EXCEPTION_USER}) {
    int enabled = 0;
    Ok(rtContextGetExceptionEnabled(ctx_, e, &enabled));
    EXPECT_EQ(enabled, 1) << e;
  }
  Ok(rtContextSetExceptionEnabled(ctx_, RT_EXCEPTION_ALL, 0));
  std::vector<Float4> r = Run("raygen_throw", RT_EXCEPTION_USER, false);
  EXPECT_EQ(r[1][0], 1.f);
}

TEST_P(ExceptionsTest, PrintReachesStdoutInLaunchIndexOrderBeforeLaunchReturns) {
  Ok(rtContextSetPrintEnabled(ctx_, 1));
  Ok(rtContextSetRayGenerationProgram(ctx_, 0, Program(kModule, "print_hello")));
  ::testing::internal::CaptureStdout();
  Ok(rtContextLaunch2D(ctx_, 0, kW, 1));
  std::string out = ::testing::internal::GetCapturedStdout();
  EXPECT_EQ(out, "hello from 0\nhello from 1\nhello from 2\n");
  Ok(rtContextSetPrintLaunchIndex(ctx_, 2, -1, -1));
  ::testing::internal::CaptureStdout();
  Ok(rtContextLaunch2D(ctx_, 0, kW, 1));
  EXPECT_EQ(::testing::internal::GetCapturedStdout(), "hello from 2\n");
  Ok(rtContextSetPrintEnabled(ctx_, 0));
  ::testing::internal::CaptureStdout();
  Ok(rtContextLaunch2D(ctx_, 0, kW, 1));
  EXPECT_EQ(::testing::internal::GetCapturedStdout(), "");
}

// Bounding box programs run outside any launch index, so their prints have no place in the
// launch's output; the first is reported on stderr rather than lost without a word.
TEST_P(ExceptionsTest, PrintsFromBoundingBoxProgramsAreReported) {
  Ok(rtContextSetPrintEnabled(ctx_, 1));
  Ok(rtGeometrySetBoundingBoxProgram(sphere_.geometry, Program(kModule, "printing_sphere_bounds")));
  Ok(rtContextSetRayGenerationProgram(ctx_, 0, Program(kModule, "raygen_value")));
  ::testing::internal::CaptureStdout();
  ::testing::internal::CaptureStderr();
  Ok(rtContextLaunch2D(ctx_, 0, kW, 1));
  const std::string err = ::testing::internal::GetCapturedStderr();
  EXPECT_EQ(::testing::internal::GetCapturedStdout(), "");
  EXPECT_NE(err.find("rtPrintf from bounding box program 'printing_sphere_bounds'"),
            std::string::npos)
      << err;
  EXPECT_NE(err.find("is not printed"), std::string::npos) << err;
}

TEST_P(ExceptionsTest, PrintsOfAnyLengthComeOutWhole) {
  Ok(rtContextSetPrintEnabled(ctx_, 1));
  Ok(rtContextSetRayGenerationProgram(ctx_, 0, Program(kModule, "print_wide")));
  ::testing::internal::CaptureStdout();
  Ok(rtContextLaunch2D(ctx_, 0, kW, 1));
  std::string expected;
  for (size_t x = 0; x < kW; ++x) expected += std::string(2999, ' ') + std::to_string(x) + "|\n";
  EXPECT_EQ(::testing::internal::GetCapturedStdout(), expected);
}

// With printing on, exceptions that reach no exception program are printed as
// rtPrintExceptionDetails would: only at the launch index rtContextSetPrintLaunchIndex selects.
TEST_P(ExceptionsTest, UnhandledExceptionReportsFollowThePrintLaunchIndex) {
  Ok(rtContextSetEntryPointCount(ctx_, 2));  // entry 1: no exception program
  Ok(rtContextSetRayGenerationProgram(ctx_, 0, Program(kModule, "trace_camera")));
  Ok(rtContextSetRayGenerationProgram(ctx_, 1, Program(kModule, "trace_camera")));
  Ok(rtContextSetPrintEnabled(ctx_, 1));
  Ok(rtContextSetPrintLaunchIndex(ctx_, 1, -1, -1));
  ::testing::internal::CaptureStdout();
  Ok(rtContextLaunch2D(ctx_, 1, kW, 1));
  const std::string out = ::testing::internal::GetCapturedStdout();
  EXPECT_NE(out.find("at launch index (1, 0, 0)"), std::string::npos) << out;
  EXPECT_EQ(out.find("at launch index (0, 0, 0)"), std::string::npos) << out;
  EXPECT_EQ(out.find("at launch index (2, 0, 0)"), std::string::npos) << out;
}

INSTANTIATE_TEST_SUITE_P(Devices, ExceptionsTest, ::testing::Values("inproc", "batched:inproc"),
                         DeviceName);

}  // namespace
}  // namespace tessera::testing

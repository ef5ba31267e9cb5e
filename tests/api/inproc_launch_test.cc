// End to end through libtessera with the real in-process device (worker/core): a program
// compiled from C++ source writes its launch index into an output buffer.
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <string>

#include "api_test_util.h"
#include "gtest/gtest.h"
#include "tessera/rt.h"
#include "tessera/rt_ext.h"

namespace tessera::test {
namespace {

constexpr const char* kSource = R"(
#include <optix.h>
#include <optixu/optixu_math_namespace.h>
using namespace optix;
rtDeclareVariable(uint2, launch_index, rtLaunchIndex, );
rtDeclareVariable(float, scale, , ) = 1.0f;
rtBuffer<float4, 2> output;
rtBuffer<float, 1> weights;
RT_PROGRAM void write_index() {
  output[launch_index] =
      make_float4(launch_index.x, launch_index.y, scale, weights[launch_index.x % 4]);
}
)";

class InprocLaunchTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("tessera_inproc_test_" + std::to_string(getpid()));
    cache_ = std::make_unique<ScopedEnv>("TESSERA_CACHE_DIR", dir_.c_str());
    devices_ = std::make_unique<ScopedEnv>("TESSERA_DEVICES", "inproc");
    ASSERT_EQ(rtContextCreate(&ctx), RT_SUCCESS);
  }
  void TearDown() override {
    EXPECT_EQ(rtContextDestroy(ctx), RT_SUCCESS);
    std::filesystem::remove_all(dir_);
  }

  std::filesystem::path dir_;
  std::unique_ptr<ScopedEnv> cache_;
  std::unique_ptr<ScopedEnv> devices_;
  RTcontext ctx = nullptr;
};

// Builds the scene on `ctx` and returns the program.
RTprogram BuildScene(RTcontext ctx, RTsize width, RTsize height, RTbuffer* output) {
  RTprogram program = nullptr;
  EXPECT_EQ(rtProgramCreateFromPTXString(ctx, kSource, "write_index", &program), RT_SUCCESS)
      << ErrorString(ctx, RT_ERROR_INVALID_SOURCE);
  EXPECT_EQ(rtContextSetEntryPointCount(ctx, 1), RT_SUCCESS);
  EXPECT_EQ(rtContextSetRayGenerationProgram(ctx, 0, program), RT_SUCCESS);
  RTbuffer weights;
  EXPECT_EQ(rtBufferCreate(ctx, RT_BUFFER_OUTPUT, output), RT_SUCCESS);
  EXPECT_EQ(rtBufferSetFormat(*output, RT_FORMAT_FLOAT4), RT_SUCCESS);
  EXPECT_EQ(rtBufferSetSize2D(*output, width, height), RT_SUCCESS);
  EXPECT_EQ(rtBufferCreate(ctx, RT_BUFFER_INPUT, &weights), RT_SUCCESS);
  EXPECT_EQ(rtBufferSetFormat(weights, RT_FORMAT_FLOAT), RT_SUCCESS);
  EXPECT_EQ(rtBufferSetSize1D(weights, 4), RT_SUCCESS);
  void* p;
  EXPECT_EQ(rtBufferMap(weights, &p), RT_SUCCESS);
  for (int i = 0; i < 4; ++i) static_cast<float*>(p)[i] = 10.0f * i;
  EXPECT_EQ(rtBufferUnmap(weights), RT_SUCCESS);
  RTvariable v;
  EXPECT_EQ(rtContextDeclareVariable(ctx, "output", &v), RT_SUCCESS);
  EXPECT_EQ(rtVariableSetObject(v, *output), RT_SUCCESS);
  EXPECT_EQ(rtContextDeclareVariable(ctx, "weights", &v), RT_SUCCESS);
  EXPECT_EQ(rtVariableSetObject(v, weights), RT_SUCCESS);
  return program;
}

// Launch indices whose output element is not what the program writes.
int CountWrong(RTbuffer output, RTsize width, RTsize height, float scale) {
  void* p = nullptr;
  EXPECT_EQ(rtBufferMap(output, &p), RT_SUCCESS);
  const float* px = static_cast<const float*>(p);
  int wrong = 0;
  for (RTsize y = 0; y < height; ++y) {
    for (RTsize x = 0; x < width; ++x) {
      const float* e = px + 4 * (y * width + x);
      const bool bad = e[0] != x || e[1] != y || e[2] != scale || e[3] != 10.0f * (x % 4);
      if (bad && wrong < 3) {
        ADD_FAILURE() << "(" << x << "," << y << ") = " << e[0] << " " << e[1] << " " << e[2] << " "
                      << e[3];
      }
      wrong += bad;
    }
  }
  EXPECT_EQ(rtBufferUnmap(output), RT_SUCCESS);
  return wrong;
}

TEST_F(InprocLaunchTest, WritesLaunchIndicesAndSeesVariableChanges) {
  constexpr RTsize kW = 70, kH = 33;  // not a multiple of the tile size
  RTbuffer output;
  RTprogram program = BuildScene(ctx, kW, kH, &output);
  ASSERT_EQ(rtContextLaunch2D(ctx, 0, kW, kH), RT_SUCCESS)
      << ErrorString(ctx, RT_ERROR_LAUNCH_FAILED) << ErrorString(ctx, RT_ERROR_INVALID_VALUE);
  EXPECT_EQ(CountWrong(output, kW, kH, 1.0f), 0);
  RTvariable s;
  ASSERT_EQ(rtProgramDeclareVariable(program, "scale", &s), RT_SUCCESS);
  ASSERT_EQ(rtVariableSet1f(s, 7.0f), RT_SUCCESS);
  ASSERT_EQ(rtContextLaunch2D(ctx, 0, kW, kH), RT_SUCCESS)
      << ErrorString(ctx, RT_ERROR_LAUNCH_FAILED);
  EXPECT_EQ(CountWrong(output, kW, kH, 7.0f), 0);
}

TEST_F(InprocLaunchTest, TwoDevicesGiveTheSameImage) {
  constexpr RTsize kW = 150, kH = 70;  // several tiles for each device
  ASSERT_EQ(tesseraContextSetDeviceSpec(ctx, "inproc,inproc"), RT_SUCCESS);
  RTbuffer output;
  BuildScene(ctx, kW, kH, &output);
  for (int launch = 0; launch < 2; ++launch) {
    ASSERT_EQ(rtContextLaunch2D(ctx, 0, kW, kH), RT_SUCCESS)
        << ErrorString(ctx, RT_ERROR_LAUNCH_FAILED);
    EXPECT_EQ(CountWrong(output, kW, kH, 1.0f), 0) << "launch " << launch;
  }
}

TEST_F(InprocLaunchTest, LaunchDimensionsBeyondUnsignedIntAreRefused) {
  RTbuffer output;
  BuildScene(ctx, 4, 4, &output);
  // rtLaunchIndex holds unsigned int components: 2^32 is one too many.
  EXPECT_EQ(rtContextLaunch2D(ctx, 0, RTsize{1} << 32, 1), RT_ERROR_INVALID_VALUE);
  std::string message = ErrorString(ctx, RT_ERROR_INVALID_VALUE);
  EXPECT_NE(message.find("launch dimension 0 is 4294967296"), std::string::npos) << message;
  EXPECT_EQ(rtContextLaunch3D(ctx, 0, 1, 1, RTsize{1} << 40), RT_ERROR_INVALID_VALUE);
  message = ErrorString(ctx, RT_ERROR_INVALID_VALUE);
  EXPECT_NE(message.find("launch dimension 2"), std::string::npos) << message;
  // The context is fine afterwards.
  EXPECT_EQ(rtContextLaunch2D(ctx, 0, 4, 4), RT_SUCCESS);
}

std::chrono::steady_clock::time_point g_huge_launch_start;
int StopAfterAMoment() {
  return std::chrono::steady_clock::now() - g_huge_launch_start > std::chrono::milliseconds(300);
}

// The largest launch there is (2^64 - 2^33 + 1 indices) starts at once, in a bounded tile list,
// and stops when the timeout callback asks.
TEST_F(InprocLaunchTest, LargestLaunchStartsAndCancels) {
  RTbuffer output;
  BuildScene(ctx, 4, 4, &output);  // indices past 4x4 write nowhere (bounds exception off)
  ASSERT_EQ(rtContextSetTimeoutCallback(ctx, StopAfterAMoment, 0.05), RT_SUCCESS);
  g_huge_launch_start = std::chrono::steady_clock::now();
  EXPECT_EQ(rtContextLaunch2D(ctx, 0, 0xFFFFFFFFu, 0xFFFFFFFFu), RT_TIMEOUT_CALLBACK);
  EXPECT_LT(std::chrono::steady_clock::now() - g_huge_launch_start, std::chrono::seconds(10));
}

}  // namespace
}  // namespace tessera::test

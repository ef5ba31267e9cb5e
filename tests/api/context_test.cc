// Context state through the C API: entry points and ray types, settings, exceptions,
// attributes, devices, and destruction with live objects.
#include <cstring>
#include <string>
#include <thread>

#include "api_test_util.h"
#include "gtest/gtest.h"
#include "optix_gl_interop.h"
#include "tessera/rt.h"

namespace tessera::test {
namespace {

class HostContextTest : public ::testing::Test {
 protected:
  void SetUp() override { ASSERT_EQ(rtContextCreate(&ctx), RT_SUCCESS); }
  void TearDown() override {
    if (ctx != nullptr) {
      EXPECT_EQ(rtContextDestroy(ctx), RT_SUCCESS);
    }
  }

  RTprogram Program(const char* function) {
    RTprogram p = nullptr;
    EXPECT_EQ(rtProgramCreateFromPTXFile(ctx, kTestModule, function, &p), RT_SUCCESS);
    return p;
  }

  RTcontext ctx = nullptr;
};

// Handles are never reused: after a context and its objects are destroyed, new ones made the
// same way (which may get the same memory) are not reachable through the old handles.
TEST(HandleTest, OldHandlesNeverReachLaterObjects) {
  for (int round = 0; round < 8; ++round) {
    RTcontext old_context = nullptr;
    ASSERT_EQ(rtContextCreate(&old_context), RT_SUCCESS);
    RTvariable old_variable = nullptr;
    ASSERT_EQ(rtContextDeclareVariable(old_context, "scale", &old_variable), RT_SUCCESS);
    RTgroup old_group = nullptr;
    ASSERT_EQ(rtGroupCreate(old_context, &old_group), RT_SUCCESS);
    ASSERT_EQ(rtContextDestroy(old_context), RT_SUCCESS);

    RTcontext context = nullptr;
    ASSERT_EQ(rtContextCreate(&context), RT_SUCCESS);
    RTvariable variable = nullptr;
    ASSERT_EQ(rtContextDeclareVariable(context, "scale", &variable), RT_SUCCESS);
    ASSERT_EQ(rtVariableSet1f(variable, 1.f), RT_SUCCESS);
    RTgroup group = nullptr;
    ASSERT_EQ(rtGroupCreate(context, &group), RT_SUCCESS);

    EXPECT_NE(old_context, context);
    EXPECT_EQ(rtContextSetRayTypeCount(old_context, 3), RT_ERROR_INVALID_CONTEXT);
    EXPECT_NE(rtVariableSet1f(old_variable, 99.f), RT_SUCCESS);
    EXPECT_NE(rtGroupSetChildCount(old_group, 5), RT_SUCCESS);
    unsigned ray_types = 0, children = 0;
    float value = 0.f;
    ASSERT_EQ(rtContextGetRayTypeCount(context, &ray_types), RT_SUCCESS);
    ASSERT_EQ(rtVariableGet1f(variable, &value), RT_SUCCESS);
    ASSERT_EQ(rtGroupGetChildCount(group, &children), RT_SUCCESS);
    EXPECT_NE(ray_types, 3u);
    EXPECT_EQ(value, 1.f);
    EXPECT_EQ(children, 0u);
    ASSERT_EQ(rtContextDestroy(context), RT_SUCCESS);
  }
}

// Destroyed handles are remembered for messages, but only the newest 65,536 of them: a
// long-lived context that makes and destroys objects does not grow without bound.
TEST(HandleTest, OnlyTheNewestDestroyedHandlesAreRemembered) {
  RTcontext context = nullptr;
  ASSERT_EQ(rtContextCreate(&context), RT_SUCCESS);
  constexpr int kDestroyed = (1 << 16) + 10;
  RTbuffer first = nullptr, last = nullptr;
  for (int i = 0; i < kDestroyed; ++i) {
    RTbuffer b = nullptr;
    ASSERT_EQ(rtBufferCreate(context, RT_BUFFER_INPUT, &b), RT_SUCCESS);
    ASSERT_EQ(rtBufferDestroy(b), RT_SUCCESS);
    if (i == 0) first = b;
    last = b;
  }
  RTformat format = RT_FORMAT_UNKNOWN;
  EXPECT_EQ(rtBufferGetFormat(first, &format), RT_ERROR_INVALID_VALUE);
  EXPECT_EQ(rtBufferGetFormat(last, &format), RT_ERROR_INVALID_VALUE);
  const char* message = nullptr;
  rtContextGetErrorString(context, RT_ERROR_INVALID_VALUE, &message);
  ASSERT_NE(message, nullptr);
  EXPECT_NE(std::string(message).find("destroyed"), std::string::npos) << message;
  ASSERT_EQ(rtContextDestroy(context), RT_SUCCESS);
}

TEST_F(HostContextTest, EntryPointsAndRayTypesResizeTheirProgramArrays) {
  unsigned n = 99;
  ASSERT_EQ(rtContextGetEntryPointCount(ctx, &n), RT_SUCCESS);
  EXPECT_EQ(n, 0u);
  ASSERT_EQ(rtContextSetEntryPointCount(ctx, 2), RT_SUCCESS);
  RTprogram rg = Program("ray_gen"), ex = Program("exception"), miss = Program("miss");
  ASSERT_EQ(rtContextSetRayGenerationProgram(ctx, 1, rg), RT_SUCCESS);
  ASSERT_EQ(rtContextSetExceptionProgram(ctx, 1, ex), RT_SUCCESS);
  RTprogram got;
  ASSERT_EQ(rtContextGetRayGenerationProgram(ctx, 1, &got), RT_SUCCESS);
  EXPECT_EQ(got, rg);
  ASSERT_EQ(rtContextGetRayGenerationProgram(ctx, 0, &got), RT_SUCCESS);
  EXPECT_EQ(got, nullptr);
  ASSERT_EQ(rtContextGetExceptionProgram(ctx, 1, &got), RT_SUCCESS);
  EXPECT_EQ(got, ex);
  ASSERT_EQ(rtContextSetEntryPointCount(ctx, 1), RT_SUCCESS);  // drops entry point 1
  ASSERT_EQ(rtContextSetEntryPointCount(ctx, 2), RT_SUCCESS);
  ASSERT_EQ(rtContextGetRayGenerationProgram(ctx, 1, &got), RT_SUCCESS);
  EXPECT_EQ(got, nullptr);

  ASSERT_EQ(rtContextSetRayTypeCount(ctx, 3), RT_SUCCESS);
  ASSERT_EQ(rtContextGetRayTypeCount(ctx, &n), RT_SUCCESS);
  EXPECT_EQ(n, 3u);
  ASSERT_EQ(rtContextSetMissProgram(ctx, 2, miss), RT_SUCCESS);
  ASSERT_EQ(rtContextGetMissProgram(ctx, 2, &got), RT_SUCCESS);
  EXPECT_EQ(got, miss);
  EXPECT_EQ(rtContextSetMissProgram(ctx, 3, miss), RT_ERROR_INVALID_VALUE);
  EXPECT_NE(ErrorString(ctx, RT_ERROR_INVALID_VALUE).find("ray type 3 is out of range (3"),
            std::string::npos);
}

// rtContextGetErrorString gives the newest message of the code asked for: an error of another
// code since (a call on a destroyed handle) must not erase it.
TEST_F(HostContextTest, EachCodeKeepsItsNewestMessage) {
  ASSERT_EQ(rtContextSetRayTypeCount(ctx, 1), RT_SUCCESS);
  EXPECT_EQ(rtContextSetMissProgram(ctx, 5, nullptr), RT_ERROR_INVALID_VALUE);
  ASSERT_EQ(rtContextSetEntryPointCount(ctx, 1), RT_SUCCESS);
  const RTresult other = rtContextValidate(ctx);  // no ray generation program
  ASSERT_NE(other, RT_SUCCESS);
  ASSERT_NE(other, RT_ERROR_INVALID_VALUE);
  EXPECT_NE(ErrorString(ctx, other), "");
  EXPECT_NE(ErrorString(ctx, RT_ERROR_INVALID_VALUE).find("rtContextSetMissProgram"),
            std::string::npos)
      << ErrorString(ctx, RT_ERROR_INVALID_VALUE);
}

TEST_F(HostContextTest, GlobalSettingsHaveOptixDefaults) {
  RTsize stack = 0;
  ASSERT_EQ(rtContextGetStackSize(ctx, &stack), RT_SUCCESS);
  EXPECT_EQ(stack, 1024u);
  ASSERT_EQ(rtContextSetStackSize(ctx, 4096), RT_SUCCESS);
  ASSERT_EQ(rtContextGetStackSize(ctx, &stack), RT_SUCCESS);
  EXPECT_EQ(stack, 4096u);

  int enabled = 1;
  ASSERT_EQ(rtContextGetPrintEnabled(ctx, &enabled), RT_SUCCESS);
  EXPECT_EQ(enabled, 0);
  ASSERT_EQ(rtContextSetPrintEnabled(ctx, 1), RT_SUCCESS);
  ASSERT_EQ(rtContextGetPrintEnabled(ctx, &enabled), RT_SUCCESS);
  EXPECT_EQ(enabled, 1);
  ASSERT_EQ(rtContextSetPrintBufferSize(ctx, 4096), RT_SUCCESS);
  RTsize size = 0;
  ASSERT_EQ(rtContextGetPrintBufferSize(ctx, &size), RT_SUCCESS);
  EXPECT_EQ(size, 4096u);
  int x = 0, y = 0, z = 0;
  ASSERT_EQ(rtContextGetPrintLaunchIndex(ctx, &x, &y, &z), RT_SUCCESS);
  EXPECT_EQ(x, -1);
  EXPECT_EQ(z, -1);
  ASSERT_EQ(rtContextSetPrintLaunchIndex(ctx, 3, -1, 0), RT_SUCCESS);
  ASSERT_EQ(rtContextGetPrintLaunchIndex(ctx, &x, nullptr, nullptr), RT_SUCCESS);
  EXPECT_EQ(x, 3);
  EXPECT_EQ(rtContextSetPrintLaunchIndex(ctx, -2, 0, 0), RT_ERROR_INVALID_VALUE);

  int running = 1;
  ASSERT_EQ(rtContextGetRunningState(ctx, &running), RT_SUCCESS);
  EXPECT_EQ(running, 0);
  EXPECT_EQ(rtContextSetTimeoutCallback(ctx, nullptr, -1.0), RT_ERROR_INVALID_VALUE);
  unsigned version = 0;
  ASSERT_EQ(rtGetVersion(&version), RT_SUCCESS);
  EXPECT_EQ(version, static_cast<unsigned>(OPTIX_VERSION));
}

TEST_F(HostContextTest, ExceptionEnables) {
  auto enabled = [&](RTexception e) {
    int on = -1;
    EXPECT_EQ(rtContextGetExceptionEnabled(ctx, e, &on), RT_SUCCESS);
    return on;
  };
  // OptiX default: only stack overflow.
  EXPECT_EQ(enabled(RT_EXCEPTION_STACK_OVERFLOW), 1);
  EXPECT_EQ(enabled(RT_EXCEPTION_BUFFER_INDEX_OUT_OF_BOUNDS), 0);
  EXPECT_EQ(enabled(RT_EXCEPTION_USER), 0);
  EXPECT_EQ(enabled(RT_EXCEPTION_ALL), 0);
  ASSERT_EQ(rtContextSetExceptionEnabled(ctx, RT_EXCEPTION_ALL, 1), RT_SUCCESS);
  for (RTexception e : {RT_EXCEPTION_PROGRAM_ID_INVALID, RT_EXCEPTION_TEXTURE_ID_INVALID,
                        RT_EXCEPTION_BUFFER_ID_INVALID, RT_EXCEPTION_INDEX_OUT_OF_BOUNDS,
                        RT_EXCEPTION_STACK_OVERFLOW, RT_EXCEPTION_BUFFER_INDEX_OUT_OF_BOUNDS,
                        RT_EXCEPTION_INVALID_RAY, RT_EXCEPTION_INTERNAL_ERROR, RT_EXCEPTION_USER,
                        RT_EXCEPTION_ALL}) {
    EXPECT_EQ(enabled(e), 1) << e;
  }
  ASSERT_EQ(rtContextSetExceptionEnabled(ctx, RT_EXCEPTION_INVALID_RAY, 0), RT_SUCCESS);
  EXPECT_EQ(enabled(RT_EXCEPTION_INVALID_RAY), 0);
  EXPECT_EQ(enabled(RT_EXCEPTION_ALL), 0);
  ASSERT_EQ(rtContextSetExceptionEnabled(ctx, RT_EXCEPTION_ALL, 0), RT_SUCCESS);
  EXPECT_EQ(enabled(RT_EXCEPTION_STACK_OVERFLOW), 0);
  EXPECT_EQ(rtContextSetExceptionEnabled(ctx, static_cast<RTexception>(0x3F0), 1),
            RT_ERROR_INVALID_VALUE);
  int on;
  EXPECT_EQ(rtContextGetExceptionEnabled(ctx, static_cast<RTexception>(5), &on),
            RT_ERROR_INVALID_VALUE);
}

TEST_F(HostContextTest, Attributes) {
  int threads = 0;
  ASSERT_EQ(rtContextGetAttribute(ctx, RT_CONTEXT_ATTRIBUTE_CPU_NUM_THREADS, sizeof(int), &threads),
            RT_SUCCESS);
  EXPECT_EQ(threads, static_cast<int>(std::max(1u, std::thread::hardware_concurrency())));
  int three = 3;
  ASSERT_EQ(rtContextSetAttribute(ctx, RT_CONTEXT_ATTRIBUTE_CPU_NUM_THREADS, sizeof(int), &three),
            RT_SUCCESS);
  ASSERT_EQ(rtContextGetAttribute(ctx, RT_CONTEXT_ATTRIBUTE_CPU_NUM_THREADS, sizeof(int), &threads),
            RT_SUCCESS);
  EXPECT_EQ(threads, 3);
  int zero = 0;
  EXPECT_EQ(rtContextSetAttribute(ctx, RT_CONTEXT_ATTRIBUTE_CPU_NUM_THREADS, sizeof(int), &zero),
            RT_ERROR_INVALID_VALUE);
  // Wrong sizes.
  EXPECT_EQ(rtContextGetAttribute(ctx, RT_CONTEXT_ATTRIBUTE_CPU_NUM_THREADS, 8, &threads),
            RT_ERROR_INVALID_VALUE);
  EXPECT_NE(ErrorString(ctx, RT_ERROR_INVALID_VALUE).find("needs size 4"), std::string::npos);
  RTsize bytes = 0;
  EXPECT_EQ(rtContextGetAttribute(ctx, RT_CONTEXT_ATTRIBUTE_USED_HOST_MEMORY, 4, &bytes),
            RT_ERROR_INVALID_VALUE);
  ASSERT_EQ(
      rtContextGetAttribute(ctx, RT_CONTEXT_ATTRIBUTE_USED_HOST_MEMORY, sizeof(RTsize), &bytes),
      RT_SUCCESS);
  EXPECT_EQ(bytes, 0u);
  int textures = -1;
  ASSERT_EQ(
      rtContextGetAttribute(ctx, RT_CONTEXT_ATTRIBUTE_MAX_TEXTURE_COUNT, sizeof(int), &textures),
      RT_SUCCESS);
  EXPECT_GE(textures, 0);
  RTsize available = 0;
  ASSERT_EQ(rtContextGetAttribute(ctx, RT_CONTEXT_ATTRIBUTE_AVAILABLE_DEVICE_MEMORY, sizeof(RTsize),
                                  &available),
            RT_SUCCESS);
  EXPECT_GT(available, 0u);
  int paging = -1;
  ASSERT_EQ(
      rtContextGetAttribute(ctx, RT_CONTEXT_ATTRIBUTE_GPU_PAGING_ACTIVE, sizeof(int), &paging),
      RT_SUCCESS);
  EXPECT_EQ(paging, 0);
  ASSERT_EQ(
      rtContextGetAttribute(ctx, RT_CONTEXT_ATTRIBUTE_GPU_PAGING_FORCED_OFF, sizeof(int), &paging),
      RT_SUCCESS);
  int one = 1;
  EXPECT_EQ(
      rtContextSetAttribute(ctx, RT_CONTEXT_ATTRIBUTE_GPU_PAGING_FORCED_OFF, sizeof(int), &one),
      RT_ERROR_NOT_SUPPORTED);
  EXPECT_NE(ErrorString(ctx, RT_ERROR_NOT_SUPPORTED).find("paging"), std::string::npos);
  EXPECT_EQ(
      rtContextSetAttribute(ctx, RT_CONTEXT_ATTRIBUTE_USED_HOST_MEMORY, sizeof(RTsize), &bytes),
      RT_ERROR_INVALID_VALUE);
  EXPECT_EQ(rtContextGetAttribute(ctx, static_cast<RTcontextattribute>(77), sizeof(int), &one),
            RT_ERROR_INVALID_VALUE);
}

TEST_F(HostContextTest, DevicesDescribeTheHost) {
  ScopedEnv env("TESSERA_DEVICES", "inproc");
  unsigned count = 0;
  ASSERT_EQ(rtDeviceGetDeviceCount(&count), RT_SUCCESS);
  ASSERT_EQ(count, 1u);
  char name[8];
  ASSERT_EQ(rtDeviceGetAttribute(0, RT_DEVICE_ATTRIBUTE_NAME, sizeof(name), name), RT_SUCCESS);
  EXPECT_EQ(std::strlen(name), 7u);  // truncated to the buffer, NUL-terminated
  int mp = 0;
  ASSERT_EQ(rtDeviceGetAttribute(0, RT_DEVICE_ATTRIBUTE_MULTIPROCESSOR_COUNT, sizeof(int), &mp),
            RT_SUCCESS);
  EXPECT_EQ(mp, static_cast<int>(std::max(1u, std::thread::hardware_concurrency())));
  RTsize memory = 0;
  ASSERT_EQ(rtDeviceGetAttribute(0, RT_DEVICE_ATTRIBUTE_TOTAL_MEMORY, sizeof(RTsize), &memory),
            RT_SUCCESS);
  EXPECT_GT(memory, 0u);
  int cc[2] = {7, 7};
  ASSERT_EQ(rtDeviceGetAttribute(0, RT_DEVICE_ATTRIBUTE_COMPUTE_CAPABILITY, sizeof(cc), cc),
            RT_SUCCESS);
  EXPECT_EQ(cc[0], 0);
  EXPECT_EQ(cc[1], 0);
  int ordinal = 0;
  ASSERT_EQ(rtDeviceGetAttribute(0, RT_DEVICE_ATTRIBUTE_CUDA_DEVICE_ORDINAL, sizeof(int), &ordinal),
            RT_SUCCESS);
  EXPECT_EQ(ordinal, -1);
  int clock = -1;
  ASSERT_EQ(rtDeviceGetAttribute(0, RT_DEVICE_ATTRIBUTE_CLOCK_RATE, sizeof(int), &clock),
            RT_SUCCESS);
  EXPECT_GE(clock, 0);
  int other = -1;
  ASSERT_EQ(rtDeviceGetAttribute(0, RT_DEVICE_ATTRIBUTE_TCC_DRIVER, sizeof(int), &other),
            RT_SUCCESS);
  EXPECT_EQ(other, 0);
  EXPECT_EQ(rtDeviceGetAttribute(0, RT_DEVICE_ATTRIBUTE_COMPUTE_CAPABILITY, sizeof(int), cc),
            RT_ERROR_INVALID_VALUE);

  ASSERT_EQ(rtContextGetDeviceCount(ctx, &count), RT_SUCCESS);
  EXPECT_EQ(count, 1u);
  int devices[1] = {-1};
  ASSERT_EQ(rtContextGetDevices(ctx, devices), RT_SUCCESS);
  EXPECT_EQ(devices[0], 0);
  ASSERT_EQ(rtContextSetDevices(ctx, 1, devices), RT_SUCCESS);
}

TEST_F(HostContextTest, DestroyingAContextDestroysEverythingInIt) {
  RTbuffer b;
  ASSERT_EQ(rtBufferCreate(ctx, RT_BUFFER_INPUT, &b), RT_SUCCESS);
  RTgroup g;
  ASSERT_EQ(rtGroupCreate(ctx, &g), RT_SUCCESS);
  RTvariable v;
  ASSERT_EQ(rtContextDeclareVariable(ctx, "top", &v), RT_SUCCESS);
  ASSERT_EQ(rtVariableSetObject(v, g), RT_SUCCESS);
  ASSERT_EQ(rtGroupSetChildCount(g, 1), RT_SUCCESS);
  RTtransform t;
  ASSERT_EQ(rtTransformCreate(ctx, &t), RT_SUCCESS);
  ASSERT_EQ(rtGroupSetChild(g, 0, t), RT_SUCCESS);
  ASSERT_EQ(rtTransformSetChild(t, g), RT_SUCCESS);  // a cycle of links is freed too
  ASSERT_EQ(rtContextDestroy(ctx), RT_SUCCESS);
  RTcontext dead = ctx;
  ctx = nullptr;
  EXPECT_EQ(rtBufferSetFormat(b, RT_FORMAT_FLOAT), RT_ERROR_INVALID_VALUE);
  EXPECT_EQ(rtGroupSetChildCount(g, 2), RT_ERROR_INVALID_VALUE);
  EXPECT_EQ(rtVariableSet1f(v, 1), RT_ERROR_INVALID_VALUE);
  EXPECT_EQ(rtContextDestroy(dead), RT_ERROR_INVALID_CONTEXT);
  EXPECT_NE(ErrorString(nullptr, RT_ERROR_INVALID_CONTEXT).find("destroyed context"),
            std::string::npos);
}

TEST_F(HostContextTest, ContextsAreIndependent) {
  RTcontext other;
  ASSERT_EQ(rtContextCreate(&other), RT_SUCCESS);
  RTbuffer mine, theirs;
  ASSERT_EQ(rtBufferCreate(ctx, RT_BUFFER_INPUT, &mine), RT_SUCCESS);
  ASSERT_EQ(rtBufferCreate(other, RT_BUFFER_INPUT, &theirs), RT_SUCCESS);
  int a = 0, b = 0;
  ASSERT_EQ(rtBufferGetId(mine, &a), RT_SUCCESS);
  ASSERT_EQ(rtBufferGetId(theirs, &b), RT_SUCCESS);
  EXPECT_EQ(a, b);  // ids are per context
  EXPECT_EQ(rtBufferSetFormat(theirs, static_cast<RTformat>(1)), RT_ERROR_INVALID_VALUE);
  // The failure is recorded on the context it belongs to.
  EXPECT_NE(ErrorString(other, RT_ERROR_INVALID_VALUE).find("rtBufferSetFormat"),
            std::string::npos);
  RTvariable v;
  ASSERT_EQ(rtContextDeclareVariable(ctx, "b", &v), RT_SUCCESS);
  EXPECT_EQ(rtVariableSetObject(v, theirs), RT_ERROR_INVALID_VALUE);
  EXPECT_EQ(rtContextDestroy(other), RT_SUCCESS);
}

// OpenGL interop is declared (applications build) and refused by name: devices have no OpenGL
// context. An application that falls back to plain buffers when it fails runs unchanged.
TEST_F(HostContextTest, OpenGlInteropIsRefusedNamingTheFunction) {
  RTbuffer buffer = reinterpret_cast<RTbuffer>(1);
  RTresult r = rtBufferCreateFromGLBO(ctx, RT_BUFFER_OUTPUT, 7, &buffer);
  EXPECT_EQ(r, RT_ERROR_NOT_SUPPORTED);
  EXPECT_EQ(buffer, nullptr);
  std::string message = ErrorString(ctx, r);
  EXPECT_NE(message.find("rtBufferCreateFromGLBO"), std::string::npos) << message;
  EXPECT_NE(message.find("OpenGL interop is not supported"), std::string::npos) << message;
  EXPECT_NE(message.find("rtBufferCreate "), std::string::npos) << message;

  RTtexturesampler sampler = nullptr;
  r = rtTextureSamplerCreateFromGLImage(ctx, 3, RT_TARGET_GL_TEXTURE_2D, &sampler);
  EXPECT_EQ(r, RT_ERROR_NOT_SUPPORTED);
  EXPECT_NE(ErrorString(ctx, r).find("rtTextureSamplerCreateFromGLImage"), std::string::npos);

  ASSERT_EQ(rtBufferCreate(ctx, RT_BUFFER_OUTPUT, &buffer), RT_SUCCESS);  // the fallback
  unsigned gl_id = 5;
  EXPECT_EQ(rtBufferGetGLBOId(buffer, &gl_id), RT_ERROR_NOT_SUPPORTED);
  EXPECT_EQ(gl_id, 0u);
  EXPECT_EQ(rtBufferGLRegister(buffer), RT_ERROR_NOT_SUPPORTED);
  EXPECT_EQ(rtBufferGLUnregister(buffer), RT_ERROR_NOT_SUPPORTED);
  ASSERT_EQ(rtTextureSamplerCreate(ctx, &sampler), RT_SUCCESS);
  EXPECT_EQ(rtTextureSamplerGetGLImageId(sampler, &gl_id), RT_ERROR_NOT_SUPPORTED);
  EXPECT_EQ(rtTextureSamplerGLRegister(sampler), RT_ERROR_NOT_SUPPORTED);
  EXPECT_EQ(rtTextureSamplerGLUnregister(sampler), RT_ERROR_NOT_SUPPORTED);
  // A null handle is the handle's error, as everywhere.
  EXPECT_EQ(rtBufferGLRegister(nullptr), RT_ERROR_INVALID_VALUE);
}

}  // namespace
}  // namespace tessera::test

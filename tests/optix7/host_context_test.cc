// The OptiX 7 host API as an SDK application calls it: the function table, error names, device
// contexts (properties, log callback, disk cache), and the functions Tessera does not support.
#include <cstring>
#include <string>

#include "host_api_fixture.h"

namespace tessera_test {
namespace {

TEST(OptixFunctionTableTest, FillsEverySlotOfAbi84Only) {
  OptixFunctionTable table{};
  EXPECT_EQ(tesseraOptixQueryFunctionTable(OPTIX_ABI_VERSION - 1, 0, nullptr, nullptr, &table,
                                           sizeof(table)),
            OPTIX_ERROR_UNSUPPORTED_ABI_VERSION);
  EXPECT_EQ(tesseraOptixQueryFunctionTable(OPTIX_ABI_VERSION, 0, nullptr, nullptr, &table,
                                           sizeof(table) - sizeof(void*)),
            OPTIX_ERROR_FUNCTION_TABLE_SIZE_MISMATCH);
  EXPECT_EQ(table.optixLaunch, nullptr);  // nothing written on failure
  ASSERT_EQ(
      tesseraOptixQueryFunctionTable(OPTIX_ABI_VERSION, 0, nullptr, nullptr, &table, sizeof(table)),
      OPTIX_SUCCESS);
  void* slots[sizeof(table) / sizeof(void*)];
  std::memcpy(slots, &table, sizeof(table));
  ASSERT_EQ(sizeof(slots) / sizeof(void*), 48u);
  for (size_t i = 0; i < 48; ++i) EXPECT_NE(slots[i], nullptr) << "slot " << i;

  ASSERT_EQ(optixInit(), OPTIX_SUCCESS);
  void* handle = reinterpret_cast<void*>(1);
  EXPECT_EQ(optixInitWithHandle(&handle), OPTIX_SUCCESS);
  EXPECT_EQ(handle, nullptr);
}

TEST(OptixFunctionTableTest, ErrorNamesAndStrings) {
  ASSERT_EQ(optixInit(), OPTIX_SUCCESS);
  EXPECT_STREQ(optixGetErrorName(OPTIX_SUCCESS), "OPTIX_SUCCESS");
  EXPECT_STREQ(optixGetErrorName(OPTIX_ERROR_INVALID_VALUE), "OPTIX_ERROR_INVALID_VALUE");
  EXPECT_STREQ(optixGetErrorName(OPTIX_ERROR_INVALID_INPUT), "OPTIX_ERROR_INVALID_INPUT");
  EXPECT_STREQ(optixGetErrorName(OPTIX_ERROR_NOT_SUPPORTED), "OPTIX_ERROR_NOT_SUPPORTED");
  EXPECT_STREQ(optixGetErrorName(OPTIX_ERROR_UNKNOWN), "OPTIX_ERROR_UNKNOWN");
  EXPECT_STREQ(optixGetErrorString(OPTIX_ERROR_NOT_SUPPORTED), "Feature not supported");
  EXPECT_STREQ(optixGetErrorString(OPTIX_ERROR_LAUNCH_FAILURE), "Launch failure");
  EXPECT_STREQ(optixGetErrorName(static_cast<OptixResult>(12345)), "Unknown OptixResult code");
  EXPECT_STREQ(optixGetErrorString(static_cast<OptixResult>(12345)), "Unknown OptixResult code");
}

using DeviceContextTest = OptixHostTest;

TEST_F(DeviceContextTest, CreateChecksItsArgumentsAndDestroyEndsTheHandle) {
  OptixDeviceContextOptions options{};
  EXPECT_EQ(optixDeviceContextCreate(0, &options, nullptr), OPTIX_ERROR_INVALID_VALUE);
  options.validationMode = static_cast<OptixDeviceContextValidationMode>(1);
  OptixDeviceContext c = nullptr;
  EXPECT_EQ(optixDeviceContextCreate(0, &options, &c), OPTIX_ERROR_INVALID_VALUE);
  options.validationMode = OPTIX_DEVICE_CONTEXT_VALIDATION_MODE_OFF;
  options.logCallbackLevel = 5;
  EXPECT_EQ(optixDeviceContextCreate(0, &options, &c), OPTIX_ERROR_INVALID_VALUE);
  EXPECT_EQ(c, nullptr);

  // No options, and any CUcontext (Tessera has one).
  ASSERT_EQ(optixDeviceContextCreate(reinterpret_cast<CUcontext>(0x1234), nullptr, &c),
            OPTIX_SUCCESS);
  ASSERT_NE(c, nullptr);
  EXPECT_EQ(optixDeviceContextDestroy(c), OPTIX_SUCCESS);
  EXPECT_EQ(optixDeviceContextDestroy(c), OPTIX_ERROR_INVALID_VALUE);
  EXPECT_EQ(optixDeviceContextDestroy(nullptr), OPTIX_ERROR_INVALID_VALUE);
  unsigned value = 0;
  EXPECT_EQ(optixDeviceContextGetProperty(c, OPTIX_DEVICE_PROPERTY_LIMIT_MAX_TRACE_DEPTH, &value,
                                          sizeof(value)),
            OPTIX_ERROR_INVALID_VALUE);
}

TEST_F(DeviceContextTest, PropertiesHaveTheDocumentedValues) {
  struct Expected {
    OptixDeviceProperty property;
    unsigned value;
  };
  const Expected expected[] = {
      {OPTIX_DEVICE_PROPERTY_LIMIT_MAX_TRACE_DEPTH, 31},
      {OPTIX_DEVICE_PROPERTY_LIMIT_MAX_TRAVERSABLE_GRAPH_DEPTH, 31},
      {OPTIX_DEVICE_PROPERTY_LIMIT_MAX_PRIMITIVES_PER_GAS, 1u << 29},
      {OPTIX_DEVICE_PROPERTY_LIMIT_MAX_INSTANCES_PER_IAS, 1u << 24},
      {OPTIX_DEVICE_PROPERTY_RTCORE_VERSION, 0},
      {OPTIX_DEVICE_PROPERTY_LIMIT_MAX_INSTANCE_ID, (1u << 28) - 1},
      {OPTIX_DEVICE_PROPERTY_LIMIT_NUM_BITS_INSTANCE_VISIBILITY_MASK, 8},
      {OPTIX_DEVICE_PROPERTY_LIMIT_MAX_SBT_RECORDS_PER_GAS, 1u << 24},
      {OPTIX_DEVICE_PROPERTY_LIMIT_MAX_SBT_OFFSET, (1u << 28) - 1},
  };
  for (const Expected& e : expected) {
    unsigned value = 12345;
    EXPECT_EQ(optixDeviceContextGetProperty(context_, e.property, &value, sizeof(value)),
              OPTIX_SUCCESS);
    EXPECT_EQ(value, e.value) << "property 0x" << std::hex << e.property;
  }
  unsigned long long wide = 0;
  EXPECT_EQ(optixDeviceContextGetProperty(context_, OPTIX_DEVICE_PROPERTY_RTCORE_VERSION, &wide,
                                          sizeof(wide)),
            OPTIX_ERROR_INVALID_VALUE);
  EXPECT_TRUE(Logged(2, "optixDeviceContextGetProperty: sizeInBytes is 8"));
  unsigned value = 0;
  EXPECT_EQ(optixDeviceContextGetProperty(context_, static_cast<OptixDeviceProperty>(0x2100),
                                          &value, sizeof(value)),
            OPTIX_ERROR_INVALID_VALUE);
  EXPECT_TRUE(Logged(2, "property 0x2100 is no OptixDeviceProperty"));
  EXPECT_EQ(
      optixDeviceContextGetProperty(context_, OPTIX_DEVICE_PROPERTY_RTCORE_VERSION, nullptr, 4),
      OPTIX_ERROR_INVALID_VALUE);
  EXPECT_TRUE(Logged(2, "value is null"));
}

TEST_F(DeviceContextTest, LogCallbackGetsMessagesUpToItsLevel) {
  std::vector<LogMessage> errors_only;
  auto collect = [](unsigned level, const char* tag, const char* message, void* data) {
    static_cast<std::vector<LogMessage>*>(data)->push_back({level, tag, message});
  };
  ASSERT_EQ(optixDeviceContextSetLogCallback(context_, collect, &errors_only, 2), OPTIX_SUCCESS);
  // A warning (level 3) is not delivered at level 2; an error is, tagged and naming the call.
  OptixDenoiser denoiser = nullptr;
  EXPECT_EQ(optixDenoiserCreate(context_, OPTIX_DENOISER_MODEL_KIND_HDR, nullptr, &denoiser),
            OPTIX_ERROR_NOT_SUPPORTED);
  ASSERT_EQ(errors_only.size(), 1u);
  EXPECT_EQ(errors_only[0].level, 2u);
  EXPECT_EQ(errors_only[0].tag, "ERROR");
  EXPECT_EQ(errors_only[0].message.rfind("optixDenoiserCreate: the OptiX AI denoiser is not "
                                         "supported",
                                         0),
            0u)
      << errors_only[0].message;
  EXPECT_EQ(optixDeviceContextSetLogCallback(context_, collect, &errors_only, 5),
            OPTIX_ERROR_INVALID_VALUE);
  EXPECT_EQ(errors_only.size(), 2u);  // the old callback still holds, and reports its own refusal
  ASSERT_EQ(optixDeviceContextSetLogCallback(context_, nullptr, nullptr, 0), OPTIX_SUCCESS);
  EXPECT_EQ(optixDenoiserCreate(context_, OPTIX_DENOISER_MODEL_KIND_HDR, nullptr, &denoiser),
            OPTIX_ERROR_NOT_SUPPORTED);
  EXPECT_EQ(errors_only.size(), 2u);
}

TEST_F(DeviceContextTest, CacheSettingsAreCheckedAndRemembered) {
  int enabled = -1;
  ASSERT_EQ(optixDeviceContextGetCacheEnabled(context_, &enabled), OPTIX_SUCCESS);
  EXPECT_EQ(enabled, 1);
  char location[1024];
  ASSERT_EQ(optixDeviceContextGetCacheLocation(context_, location, sizeof(location)),
            OPTIX_SUCCESS);
  EXPECT_STREQ(location, TESSERA_TEST_MODULE_CACHE);
  EXPECT_EQ(optixDeviceContextGetCacheLocation(context_, location, 4), OPTIX_ERROR_INVALID_VALUE);
  EXPECT_TRUE(Logged(2, "locationSize is 4"));

  EXPECT_EQ(optixDeviceContextSetCacheEnabled(context_, 2), OPTIX_ERROR_INVALID_VALUE);
  EXPECT_EQ(optixDeviceContextSetCacheEnabled(context_, 0), OPTIX_SUCCESS);
  ASSERT_EQ(optixDeviceContextGetCacheEnabled(context_, &enabled), OPTIX_SUCCESS);
  EXPECT_EQ(enabled, 0);
  EXPECT_EQ(optixDeviceContextSetCacheEnabled(context_, 1), OPTIX_SUCCESS);

  // A location that cannot be created is refused and disables the cache, as in OptiX.
  EXPECT_EQ(optixDeviceContextSetCacheLocation(context_, "/proc/self/no/such/dir"),
            OPTIX_ERROR_DISK_CACHE_INVALID_PATH);
  ASSERT_EQ(optixDeviceContextGetCacheEnabled(context_, &enabled), OPTIX_SUCCESS);
  EXPECT_EQ(enabled, 0);
  ASSERT_EQ(optixDeviceContextGetCacheLocation(context_, location, sizeof(location)),
            OPTIX_SUCCESS);
  EXPECT_STREQ(location, TESSERA_TEST_MODULE_CACHE);

  EXPECT_EQ(optixDeviceContextSetCacheDatabaseSizes(context_, 10, 5), OPTIX_ERROR_INVALID_VALUE);
  EXPECT_TRUE(Logged(2, "highWaterMark 5 is below lowWaterMark 10"));
  EXPECT_EQ(optixDeviceContextSetCacheDatabaseSizes(context_, 1 << 20, 1 << 30), OPTIX_SUCCESS);
  size_t low = 0, high = 0;
  ASSERT_EQ(optixDeviceContextGetCacheDatabaseSizes(context_, &low, &high), OPTIX_SUCCESS);
  EXPECT_EQ(low, size_t{1} << 20);
  EXPECT_EQ(high, size_t{1} << 30);
}

TEST_F(DeviceContextTest, DenoiserAndMicromapsAreNotSupportedAndSayWhy) {
  OptixDenoiser denoiser = reinterpret_cast<OptixDenoiser>(0x10);
  EXPECT_EQ(optixDenoiserCreate(context_, OPTIX_DENOISER_MODEL_KIND_LDR, nullptr, &denoiser),
            OPTIX_ERROR_NOT_SUPPORTED);
  EXPECT_EQ(denoiser, nullptr);
  EXPECT_TRUE(Logged(2, "NVIDIA's driver"));
  EXPECT_EQ(optixDenoiserCreateWithUserModel(context_, "x", 1, &denoiser),
            OPTIX_ERROR_NOT_SUPPORTED);
  EXPECT_EQ(optixDenoiserCreate(nullptr, OPTIX_DENOISER_MODEL_KIND_LDR, nullptr, &denoiser),
            OPTIX_ERROR_INVALID_VALUE);
  EXPECT_EQ(optixDenoiserDestroy(nullptr), OPTIX_ERROR_INVALID_VALUE);
  OptixDenoiserSizes sizes{};
  EXPECT_EQ(
      optixDenoiserComputeMemoryResources(reinterpret_cast<OptixDenoiser>(0x10), 64, 64, &sizes),
      OPTIX_ERROR_INVALID_VALUE);

  OptixMicromapBufferSizes micromap_sizes{};
  EXPECT_EQ(optixOpacityMicromapArrayComputeMemoryUsage(context_, nullptr, &micromap_sizes),
            OPTIX_ERROR_NOT_SUPPORTED);
  EXPECT_TRUE(Logged(2,
                     "optixOpacityMicromapArrayComputeMemoryUsage: opacity and displacement "
                     "micromaps are not supported: Embree"));
  EXPECT_EQ(optixDisplacementMicromapArrayBuild(context_, 0, nullptr, nullptr),
            OPTIX_ERROR_NOT_SUPPORTED);
  EXPECT_EQ(optixOpacityMicromapArrayRelocate(context_, 0, nullptr, 0, 0),
            OPTIX_ERROR_NOT_SUPPORTED);
}

}  // namespace
}  // namespace tessera_test

// Device spec parsing (docs/devices.md "Device specs"), the device table and the rt_ext.h spec
// functions.
#include "device_spec.h"

#include "api_test_util.h"
#include "device_table.h"
#include "gtest/gtest.h"
#include "status.h"
#include "tessera/rt_ext.h"

namespace tessera::api {
namespace {

using Type = DeviceSpecEntry::Type;

TEST(DeviceSpecTest, AcceptsAllFourForms) {
  auto entries = ParseDeviceSpec("inproc,local:4,render7.example.com:5000,unix:/tmp/w.sock");
  ASSERT_TRUE(entries.ok()) << entries.status();
  ASSERT_EQ(entries->size(), 4u);
  EXPECT_EQ((*entries)[0].type, Type::kInproc);
  EXPECT_EQ((*entries)[1].type, Type::kLocal);
  EXPECT_EQ((*entries)[1].count, 4);
  EXPECT_EQ((*entries)[2].type, Type::kTcp);
  EXPECT_EQ((*entries)[2].host, "render7.example.com");
  EXPECT_EQ((*entries)[2].port, 5000);
  EXPECT_EQ((*entries)[3].type, Type::kUnix);
  EXPECT_EQ((*entries)[3].path, "/tmp/w.sock");
}

TEST(DeviceSpecTest, AcceptsAddressesAndWhitespace) {
  auto entries = ParseDeviceSpec(" 127.0.0.1:1 , [::1]:65535,localhost:8080 ");
  ASSERT_TRUE(entries.ok()) << entries.status();
  ASSERT_EQ(entries->size(), 3u);
  EXPECT_EQ((*entries)[0].host, "127.0.0.1");
  EXPECT_EQ((*entries)[1].host, "::1");
  EXPECT_EQ((*entries)[1].port, 65535);
  EXPECT_EQ((*entries)[1].ToString(), "[::1]:65535");
  EXPECT_EQ((*entries)[2].ToString(), "localhost:8080");
}

TEST(DeviceSpecTest, RoundTripsThroughToString) {
  for (const char* spec : {"inproc", "local:12", "a-b.c:9", "unix:rel/path.sock"}) {
    auto entries = ParseDeviceSpec(spec);
    ASSERT_TRUE(entries.ok()) << spec;
    EXPECT_EQ((*entries)[0].ToString(), spec);
  }
}

TEST(DeviceSpecTest, RejectsBadInputWithAClearMessage) {
  struct Case {
    const char* spec;
    const char* expect;  // in the message
  };
  const Case cases[] = {
      {"", "empty"},
      {"   ", "empty"},
      {"inproc,", "entry 2 '' is empty"},
      {",inproc", "entry 1"},
      {"local:", "worker count"},
      {"local:0", "worker count"},
      {"local:-3", "worker count"},
      {"local:x", "worker count"},
      {"local:99999999", "worker count"},
      {"unix:", "socket path"},
      {"unix:/tmp/aaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaa"
       "aaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaa.sock",
       "at most 107"},
      {"host:0", "port"},
      {"host:65536", "port"},
      {"host:", "port"},
      {"host:80x", "port"},
      {":80", "bad host name"},
      {"bad_host:80", "bad host name"},
      {"-host:80", "bad host name"},
      {"INPROC", "is not one of inproc, local:N, HOST:PORT or unix:PATH"},
      {"gpu0", "is not one of"},
      {"[zz]:80", "IPv6"},
      {"::1:80", "bad host name"},
  };
  for (const Case& c : cases) {
    auto entries = ParseDeviceSpec(c.spec);
    ASSERT_FALSE(entries.ok()) << "'" << c.spec << "' parsed";
    EXPECT_EQ(ToRtResult(entries.status()), RT_ERROR_INVALID_VALUE);
    EXPECT_NE(entries.status().message().find(c.expect), std::string::npos)
        << "'" << c.spec << "': " << entries.status().message();
    if (c.spec[0] != '\0') {
      EXPECT_NE(entries.status().message().find(std::string("'") + c.spec + "'"), std::string::npos)
          << "the message quotes the spec: " << entries.status().message();
    }
  }
}

TEST(DeviceSpecTest, ExpandsLocalWorkersIntoDevices) {
  auto entries = ParseDeviceSpec("inproc,local:3,h:1");
  ASSERT_TRUE(entries.ok());
  std::vector<DeviceDesc> devices = ExpandDevices(*entries);
  ASSERT_EQ(devices.size(), 5u);
  EXPECT_EQ(devices[0].address, "inproc");
  EXPECT_EQ(devices[2].address, "local:3/1");
  EXPECT_EQ(devices[4].address, "h:1");
  EXPECT_TRUE(CheckInstantiable(devices[0]).ok());
  EXPECT_EQ(devices[1].local_index, 0);
  EXPECT_EQ(devices[2].local_index, 1);
  EXPECT_EQ(devices[2].local_count, 3);
  // tessera::api_core alone has no worker transport (libtessera installs it).
  absl::Status local = CheckInstantiable(devices[1]);
  EXPECT_EQ(ToRtResult(local), RT_ERROR_NOT_SUPPORTED);
  EXPECT_NE(local.message().find("no worker transport"), std::string::npos);
}

TEST(DeviceSpecTest, EnvironmentSelectsDevices) {
  {
    test::ScopedEnv env("TESSERA_DEVICES", nullptr);
    EXPECT_EQ(DeviceSpecFromEnvironment(), "inproc");
    unsigned count = 0;
    ASSERT_EQ(rtDeviceGetDeviceCount(&count), RT_SUCCESS);
    EXPECT_EQ(count, 1u);
  }
  {
    test::ScopedEnv env("TESSERA_DEVICES", "local:2,unix:/x");
    unsigned count = 0;
    ASSERT_EQ(rtDeviceGetDeviceCount(&count), RT_SUCCESS);
    EXPECT_EQ(count, 3u);
    char name[64];
    ASSERT_EQ(rtDeviceGetAttribute(2, RT_DEVICE_ATTRIBUTE_NAME, sizeof(name), name), RT_SUCCESS);
    EXPECT_STREQ(name, "Tessera worker unix:/x");
    // Worker devices parse, but without the transport (api_core alone) a context cannot use them.
    RTcontext ctx = nullptr;
    EXPECT_EQ(rtContextCreate(&ctx), RT_ERROR_NOT_SUPPORTED);
    EXPECT_EQ(ctx, nullptr);
    EXPECT_NE(test::ErrorString(nullptr, RT_ERROR_NOT_SUPPORTED).find("no worker transport"),
              std::string::npos);
  }
  {
    test::ScopedEnv env("TESSERA_DEVICES", "local:zero");
    unsigned count = 0;
    EXPECT_EQ(rtDeviceGetDeviceCount(&count), RT_ERROR_NO_DEVICE);
    EXPECT_NE(test::ErrorString(nullptr, RT_ERROR_NO_DEVICE).find("TESSERA_DEVICES"),
              std::string::npos);
    RTcontext ctx = nullptr;
    EXPECT_EQ(rtContextCreate(&ctx), RT_ERROR_INVALID_VALUE);
  }
}

TEST(DeviceSpecTest, ExtensionFunctions) {
  const char* error = "unchanged";
  EXPECT_EQ(tesseraDeviceSpecValidate("inproc,host:1", &error), RT_SUCCESS);
  EXPECT_EQ(error, nullptr);
  EXPECT_EQ(tesseraDeviceSpecValidate("inproc,,", &error), RT_ERROR_INVALID_VALUE);
  ASSERT_NE(error, nullptr);
  EXPECT_NE(std::string(error).find("entry 2"), std::string::npos) << error;
  EXPECT_EQ(tesseraDeviceSpecValidate(nullptr, &error), RT_ERROR_INVALID_VALUE);
  EXPECT_EQ(tesseraDeviceSpecValidate("bad spec", nullptr), RT_ERROR_INVALID_VALUE);

  RTcontext ctx;
  ASSERT_EQ(rtContextCreate(&ctx), RT_SUCCESS);
  EXPECT_EQ(tesseraContextSetDeviceSpec(ctx, "local:2"), RT_ERROR_NOT_SUPPORTED);
  EXPECT_NE(test::ErrorString(ctx, RT_ERROR_NOT_SUPPORTED).find("tesseraContextSetDeviceSpec"),
            std::string::npos);
  EXPECT_EQ(tesseraContextSetDeviceSpec(ctx, "nonsense"), RT_ERROR_INVALID_VALUE);
  ASSERT_EQ(tesseraContextSetDeviceSpec(ctx, "inproc,inproc"), RT_SUCCESS);
  unsigned count = 0;
  ASSERT_EQ(rtContextGetDeviceCount(ctx, &count), RT_SUCCESS);
  EXPECT_EQ(count, 2u);
  int devices[2] = {-1, -1};
  ASSERT_EQ(rtContextGetDevices(ctx, devices), RT_SUCCESS);
  EXPECT_EQ(devices[0], 0);
  EXPECT_EQ(devices[1], 1);
  const int second = 1;
  ASSERT_EQ(rtContextSetDevices(ctx, 1, &second), RT_SUCCESS);
  ASSERT_EQ(rtContextGetDeviceCount(ctx, &count), RT_SUCCESS);
  EXPECT_EQ(count, 1u);
  const int twice[2] = {0, 0};
  EXPECT_EQ(rtContextSetDevices(ctx, 2, twice), RT_ERROR_INVALID_VALUE);
  EXPECT_EQ(rtContextSetDevices(ctx, 0, twice), RT_ERROR_INVALID_VALUE);
  EXPECT_EQ(rtContextDestroy(ctx), RT_SUCCESS);
}

}  // namespace
}  // namespace tessera::api

// rtDeviceGetAttribute and tesseraDeviceGetAddress for every kind of device in TESSERA_DEVICES:
// a running worker is asked for its thread count and memory, local:N workers are described
// before they exist, and a worker that cannot be reached is RT_ERROR_CONNECTION_FAILED.
#include <gtest/gtest.h>
#include <stdlib.h>

#include <memory>
#include <optional>
#include <string>

#include "tessera/rt_ext.h"
#include "transport/worker_process.h"

namespace tessera::e2e {
namespace {

class DeviceAttributesTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (const char* env = getenv("TESSERA_DEVICES")) saved_ = env;
  }
  void TearDown() override {
    if (saved_) {
      setenv("TESSERA_DEVICES", saved_->c_str(), 1);
    } else {
      unsetenv("TESSERA_DEVICES");
    }
  }
  static std::string Address(int ordinal) {
    char address[256] = {};
    EXPECT_EQ(tesseraDeviceGetAddress(ordinal, sizeof(address), address), RT_SUCCESS);
    return address;
  }
  static std::string Name(int ordinal) {
    char name[256] = {};
    EXPECT_EQ(rtDeviceGetAttribute(ordinal, RT_DEVICE_ATTRIBUTE_NAME, sizeof(name), name),
              RT_SUCCESS);
    return name;
  }
  static std::string LastError(RTresult code) {
    const char* text = nullptr;
    rtContextGetErrorString(nullptr, code, &text);
    return text != nullptr ? text : "";
  }

  std::optional<std::string> saved_;
};

TEST_F(DeviceAttributesTest, RunningWorkerDescribesItsMachine) {
  transport::WorkerProcess::Options options;
  options.threads = 3;
  auto worker = transport::WorkerProcess::Spawn(options);
  ASSERT_TRUE(worker.ok()) << worker.status();
  const std::string address = (*worker)->address();
  setenv("TESSERA_DEVICES", ("inproc," + address + ",local:2").c_str(), 1);

  unsigned count = 0;
  ASSERT_EQ(rtDeviceGetDeviceCount(&count), RT_SUCCESS);
  ASSERT_EQ(count, 4u);
  EXPECT_EQ(Address(0), "inproc");
  EXPECT_EQ(Address(1), address);
  EXPECT_EQ(Address(2), "local:2/0");
  EXPECT_EQ(Address(3), "local:2/1");
  EXPECT_NE(Name(1).find(address), std::string::npos) << Name(1);

  int threads = 0;
  ASSERT_EQ(
      rtDeviceGetAttribute(1, RT_DEVICE_ATTRIBUTE_MULTIPROCESSOR_COUNT, sizeof(threads), &threads),
      RT_SUCCESS);
  EXPECT_EQ(threads, 3);
  RTsize memory = 0;
  ASSERT_EQ(rtDeviceGetAttribute(1, RT_DEVICE_ATTRIBUTE_TOTAL_MEMORY, sizeof(memory), &memory),
            RT_SUCCESS);
  EXPECT_GT(memory, RTsize{0});
  // The same machine: the same memory as the in-process device reports.
  RTsize local_memory = 0;
  ASSERT_EQ(rtDeviceGetAttribute(0, RT_DEVICE_ATTRIBUTE_TOTAL_MEMORY, sizeof(local_memory),
                                 &local_memory),
            RT_SUCCESS);
  EXPECT_EQ(memory, local_memory);
  int clock = -1, local_clock = -2;
  ASSERT_EQ(rtDeviceGetAttribute(1, RT_DEVICE_ATTRIBUTE_CLOCK_RATE, sizeof(clock), &clock),
            RT_SUCCESS);
  ASSERT_EQ(
      rtDeviceGetAttribute(0, RT_DEVICE_ATTRIBUTE_CLOCK_RATE, sizeof(local_clock), &local_clock),
      RT_SUCCESS);
  EXPECT_EQ(clock, local_clock);
}

TEST_F(DeviceAttributesTest, UnreachableWorkerIsConnectionFailedNamingIt) {
  const std::string address = "unix:/nonexistent/tessera-attributes.sock";
  setenv("TESSERA_DEVICES", address.c_str(), 1);
  // What needs no answer from the worker still works.
  EXPECT_EQ(Address(0), address);
  EXPECT_NE(Name(0).find(address), std::string::npos);
  int threads = -1;
  RTresult r =
      rtDeviceGetAttribute(0, RT_DEVICE_ATTRIBUTE_MULTIPROCESSOR_COUNT, sizeof(threads), &threads);
  EXPECT_EQ(r, RT_ERROR_CONNECTION_FAILED);
  EXPECT_NE(LastError(r).find(address), std::string::npos) << LastError(r);
  EXPECT_EQ(threads, -1) << "nothing written on failure";
}

TEST_F(DeviceAttributesTest, AddressArgumentsAreChecked) {
  setenv("TESSERA_DEVICES", "inproc", 1);
  char address[8] = {};
  EXPECT_EQ(tesseraDeviceGetAddress(1, sizeof(address), address), RT_ERROR_INVALID_VALUE);
  EXPECT_NE(LastError(RT_ERROR_INVALID_VALUE).find("out of range"), std::string::npos);
  EXPECT_EQ(tesseraDeviceGetAddress(-1, sizeof(address), address), RT_ERROR_INVALID_VALUE);
  EXPECT_EQ(tesseraDeviceGetAddress(0, sizeof(address), nullptr), RT_ERROR_INVALID_VALUE);
  EXPECT_EQ(tesseraDeviceGetAddress(0, 0, address), RT_ERROR_INVALID_VALUE);
  // Truncated to the size given, NUL-terminated.
  ASSERT_EQ(tesseraDeviceGetAddress(0, 3, address), RT_SUCCESS);
  EXPECT_STREQ(address, "in");
}

}  // namespace
}  // namespace tessera::e2e

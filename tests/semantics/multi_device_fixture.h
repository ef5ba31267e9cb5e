// A harness for multi-device semantics tests: a context on a named device set, typed buffers bound
// to context variables, tile sizes, transfer statistics, and a switch to stable tile ownership.
#ifndef TESSERA_TESTS_SEMANTICS_MULTI_DEVICE_FIXTURE_H_
#define TESSERA_TESTS_SEMANTICS_MULTI_DEVICE_FIXTURE_H_

#include <cstring>
#include <ostream>
#include <string>
#include <vector>

#include "rt_fixture.h"
#include "tessera/rt_ext.h"

namespace tessera::testing {

constexpr char kMultiDeviceModule[] = "multi_device_programs";

// One device set: a readable test name, its spec, and how many devices it makes.
struct DeviceCase {
  const char* name;
  const char* spec;
  unsigned devices;
};

// Failure messages name the device set by its spec.
inline void PrintTo(const DeviceCase& c, std::ostream* os) { *os << c.spec; }

// Cumulative buffer bytes of a context (tesseraContextGetTransferStats).
struct Transfer {
  unsigned long long sent = 0;
  unsigned long long received = 0;
  Transfer operator-(const Transfer& o) const { return {sent - o.sent, received - o.received}; }
};

class MultiDeviceFixture : public RtFixture {
 protected:
  // Replaces the fixture's context with a fresh one on `spec`, with one entry point.
  void UseDevices(const char* spec) {
    if (ctx_ != nullptr) rtContextDestroy(ctx_);
    ctx_ = nullptr;
    Ok(rtContextCreate(&ctx_));
    Ok(tesseraContextSetDeviceSpec(ctx_, spec));
    Ok(rtContextSetEntryPointCount(ctx_, 1));
    Ok(rtContextSetRayTypeCount(ctx_, 1));
  }

  RTprogram Program(const char* function) {
    return RtFixture::Program(kMultiDeviceModule, function);
  }
  void RayGen(const char* function) {
    Ok(rtContextSetRayGenerationProgram(ctx_, 0, Program(function)));
  }

  // A buffer of `type` (RT_BUFFER_* bits) bound to the context variable `name`.
  RTbuffer Buffer(unsigned type, RTformat format, std::vector<RTsize> dims, const char* name) {
    RTbuffer b = nullptr;
    EXPECT_EQ(rtBufferCreate(ctx_, type, &b), RT_SUCCESS);
    EXPECT_EQ(rtBufferSetFormat(b, format), RT_SUCCESS);
    EXPECT_EQ(rtBufferSetSizev(b, static_cast<unsigned>(dims.size()), dims.data()), RT_SUCCESS);
    EXPECT_EQ(rtVariableSetObject(ContextVar(name), b), RT_SUCCESS);
    return b;
  }

  template <typename T>
  void Write(RTbuffer b, const std::vector<T>& values) {
    void* p = nullptr;
    ASSERT_EQ(rtBufferMap(b, &p), RT_SUCCESS);
    std::memcpy(p, values.data(), values.size() * sizeof(T));
    ASSERT_EQ(rtBufferUnmap(b), RT_SUCCESS);
  }

  template <typename T>
  std::vector<T> Contents(RTbuffer b) {
    RTsize element = 0;
    EXPECT_EQ(rtBufferGetElementSize(b, &element), RT_SUCCESS);
    EXPECT_EQ(element, sizeof(T));
    RTsize dims[3] = {1, 1, 1};
    unsigned dimensionality = 0;
    EXPECT_EQ(rtBufferGetDimensionality(b, &dimensionality), RT_SUCCESS);
    EXPECT_EQ(rtBufferGetSizev(b, dimensionality, dims), RT_SUCCESS);
    std::vector<T> v(dims[0] * dims[1] * dims[2]);
    void* p = nullptr;
    EXPECT_EQ(rtBufferMap(b, &p), RT_SUCCESS);
    if (p != nullptr) std::memcpy(v.data(), p, v.size() * sizeof(T));
    EXPECT_EQ(rtBufferUnmap(b), RT_SUCCESS);
    return v;
  }

  // Tiles of `size` for later launches; {} restores the automatic choice.
  void TileSize(std::vector<RTsize> size) {
    Ok(tesseraContextSetTileSize(ctx_, static_cast<unsigned>(size.size()),
                                 size.empty() ? nullptr : size.data()));
  }

  // A context with a GPU_LOCAL buffer keeps tile i on device i mod N from launch to launch
  // (docs/devices.md "Buffers across devices"): with tiles >= devices every device then runs some
  // tile, and neighbouring tiles run on different devices whenever there are several.
  void PinTilesToDevices() {
    RTbuffer pin = nullptr;
    Ok(rtBufferCreate(ctx_, RT_BUFFER_INPUT_OUTPUT | RT_BUFFER_GPU_LOCAL, &pin));
    Ok(rtBufferSetFormat(pin, RT_FORMAT_INT));
    Ok(rtBufferSetSize1D(pin, 1));
    // Reachable through a context variable: an unreachable GPU_LOCAL buffer pins nothing.
    RTvariable v = nullptr;
    Ok(rtContextDeclareVariable(ctx_, "tessera_test_pin", &v));
    Ok(rtVariableSetObject(v, pin));
  }

  Transfer Stats() {
    Transfer t;
    EXPECT_EQ(tesseraContextGetTransferStats(ctx_, &t.sent, &t.received), RT_SUCCESS);
    return t;
  }

  void SetUint(const char* name, unsigned value) { Ok(rtVariableSet1ui(ContextVar(name), value)); }

  void Launch1D(RTsize n) {
    RTresult r = rtContextLaunch1D(ctx_, 0, n);
    ASSERT_EQ(r, RT_SUCCESS) << Error(r);
  }
  void Launch2D(RTsize w, RTsize h) {
    RTresult r = rtContextLaunch2D(ctx_, 0, w, h);
    ASSERT_EQ(r, RT_SUCCESS) << Error(r);
  }
  void Launch3D(RTsize w, RTsize h, RTsize d) {
    RTresult r = rtContextLaunch3D(ctx_, 0, w, h, d);
    ASSERT_EQ(r, RT_SUCCESS) << Error(r);
  }
};

// The device sets every multi-device rule runs on.
inline const DeviceCase kRuleDeviceCases[] = {
    {"Inproc", "inproc", 1},
    {"Local1", "local:1", 1},
    {"Local2", "local:2", 2},
    {"Local4", "local:4", 4},
};

inline std::string DeviceCaseName(const ::testing::TestParamInfo<DeviceCase>& info) {
  return info.param.name;
}

// A test run once per device set; each test file derives its own suite and instantiates it.
class MultiDeviceParamTest : public MultiDeviceFixture,
                             public ::testing::WithParamInterface<DeviceCase> {
 protected:
  void SetUp() override {
    MultiDeviceFixture::SetUp();
    UseDevices(GetParam().spec);
  }
  unsigned long long devices() const { return GetParam().devices; }
};

}  // namespace tessera::testing

#endif  // TESSERA_TESTS_SEMANTICS_MULTI_DEVICE_FIXTURE_H_

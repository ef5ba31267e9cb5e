// A small harness over the OptiX 3 C API for semantics tests: checked calls, program modules,
// float4 output buffers, and a sphere or slab scene.
#ifndef TESSERA_TESTS_SEMANTICS_RT_FIXTURE_H_
#define TESSERA_TESTS_SEMANTICS_RT_FIXTURE_H_

#include <gtest/gtest.h>

#include <array>
#include <cctype>
#include <cstring>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "../common/scoped_env.h"
#include "tessera/rt.h"
#include "tessera/rt_ext.h"

namespace tessera::testing {

using Float4 = std::array<float, 4>;

class RtFixture : public ::testing::Test {
 protected:
  void SetUp() override { ASSERT_EQ(rtContextCreate(&ctx_), RT_SUCCESS); }
  void TearDown() override { rtContextDestroy(ctx_); }

  std::string Error(RTresult code) const {
    const char* s = nullptr;
    rtContextGetErrorString(ctx_, code, &s);
    return s ? s : "";
  }
  // Asserts success with the context's message on failure.
  void Ok(RTresult code) { ASSERT_EQ(code, RT_SUCCESS) << Error(code); }

  RTprogram Program(const std::string& module, const std::string& function) {
    RTprogram p = nullptr;
    std::string path = std::string(TESSERA_TEST_MODULE_DIR) + "/" + module + ".so";
    EXPECT_EQ(rtProgramCreateFromPTXFile(ctx_, path.c_str(), function.c_str(), &p), RT_SUCCESS)
        << Error(RT_ERROR_UNKNOWN) << " " << function;
    return p;
  }

  RTvariable ContextVar(const std::string& name) {
    RTvariable v = nullptr;
    if (rtContextQueryVariable(ctx_, name.c_str(), &v) != RT_SUCCESS || v == nullptr) {
      EXPECT_EQ(rtContextDeclareVariable(ctx_, name.c_str(), &v), RT_SUCCESS);
    }
    return v;
  }

  // A float4 2D buffer bound to context variable `name`.
  RTbuffer Float4Buffer(const std::string& name, unsigned type, size_t w, size_t h) {
    return Buffer2D(name, type, RT_FORMAT_FLOAT4, w, h);
  }

  // A 2D buffer of any format bound to context variable `name`, and its contents as Ts.
  RTbuffer Buffer2D(const std::string& name, unsigned type, RTformat format, size_t w, size_t h) {
    RTbuffer b = nullptr;
    EXPECT_EQ(rtBufferCreate(ctx_, type, &b), RT_SUCCESS);
    EXPECT_EQ(rtBufferSetFormat(b, format), RT_SUCCESS);
    EXPECT_EQ(rtBufferSetSize2D(b, w, h), RT_SUCCESS);
    EXPECT_EQ(rtVariableSetObject(ContextVar(name), b), RT_SUCCESS);
    return b;
  }
  template <typename T>
  std::vector<T> ReadAs(RTbuffer b) {
    RTsize w = 0, h = 0;
    rtBufferGetSize2D(b, &w, &h);
    std::vector<T> out(w * h);
    void* p = nullptr;
    if (rtBufferMap(b, &p) != RT_SUCCESS) return out;
    std::memcpy(out.data(), p, out.size() * sizeof(T));
    rtBufferUnmap(b);
    return out;
  }

  std::vector<Float4> Read(RTbuffer b) { return ReadAs<Float4>(b); }

  RTacceleration Accel(const char* builder = "Bvh") {
    RTacceleration a = nullptr;
    EXPECT_EQ(rtAccelerationCreate(ctx_, &a), RT_SUCCESS);
    EXPECT_EQ(rtAccelerationSetBuilder(a, builder), RT_SUCCESS);
    // NoAccel takes only its own traverser, as in OptiX.
    EXPECT_EQ(rtAccelerationSetTraverser(a, std::string(builder) == "NoAccel" ? "NoAccel" : "Bvh"),
              RT_SUCCESS);
    return a;
  }

  struct Instance {
    RTgeometry geometry = nullptr;
    RTmaterial material = nullptr;
    RTgeometryinstance instance = nullptr;
    RTgeometrygroup group = nullptr;
  };

  // One GeometryGroup holding one instance of `primitives` primitives.
  Instance MakeInstance(RTprogram intersect, RTprogram bounds, unsigned primitives,
                        RTprogram closest_hit, RTprogram any_hit = nullptr, unsigned ray_type = 0) {
    Instance i;
    EXPECT_EQ(rtGeometryCreate(ctx_, &i.geometry), RT_SUCCESS);
    EXPECT_EQ(rtGeometrySetPrimitiveCount(i.geometry, primitives), RT_SUCCESS);
    EXPECT_EQ(rtGeometrySetIntersectionProgram(i.geometry, intersect), RT_SUCCESS);
    EXPECT_EQ(rtGeometrySetBoundingBoxProgram(i.geometry, bounds), RT_SUCCESS);
    EXPECT_EQ(rtMaterialCreate(ctx_, &i.material), RT_SUCCESS);
    if (closest_hit) {
      EXPECT_EQ(rtMaterialSetClosestHitProgram(i.material, ray_type, closest_hit), RT_SUCCESS);
    }
    if (any_hit) {
      EXPECT_EQ(rtMaterialSetAnyHitProgram(i.material, ray_type, any_hit), RT_SUCCESS);
    }
    EXPECT_EQ(rtGeometryInstanceCreate(ctx_, &i.instance), RT_SUCCESS);
    EXPECT_EQ(rtGeometryInstanceSetGeometry(i.instance, i.geometry), RT_SUCCESS);
    EXPECT_EQ(rtGeometryInstanceSetMaterialCount(i.instance, 1), RT_SUCCESS);
    EXPECT_EQ(rtGeometryInstanceSetMaterial(i.instance, 0, i.material), RT_SUCCESS);
    EXPECT_EQ(rtGeometryGroupCreate(ctx_, &i.group), RT_SUCCESS);
    EXPECT_EQ(rtGeometryGroupSetAcceleration(i.group, Accel()), RT_SUCCESS);
    EXPECT_EQ(rtGeometryGroupSetChildCount(i.group, 1), RT_SUCCESS);
    EXPECT_EQ(rtGeometryGroupSetChild(i.group, 0, i.instance), RT_SUCCESS);
    return i;
  }

  RTcontext ctx_ = nullptr;
};

// A context on the device set GetParam() names ("inproc", "local:2"), with one entry point and
// one ray type. "batched:" before the spec ("batched:local:2") makes the test's launches trace
// their first rays in packets (TESSERA_BATCHING=1, docs/programs.md "Batched tracing"), so that a
// suite checks that what it tests holds on that path too.
class OnDevicesFixture : public RtFixture, public ::testing::WithParamInterface<const char*> {
 protected:
  void SetUp() override {
    RtFixture::SetUp();
    std::string spec = GetParam();
    if (batched()) {
      spec.erase(0, sizeof(kBatched) - 1);
      batching_.emplace("TESSERA_BATCHING", "1");
    }
    Ok(tesseraContextSetDeviceSpec(ctx_, spec.c_str()));
    Ok(rtContextSetEntryPointCount(ctx_, 1));
    Ok(rtContextSetRayTypeCount(ctx_, 1));
  }
  // Whether the parameter asks for batched launches.
  bool batched() const {
    return std::string_view(GetParam()).substr(0, sizeof(kBatched) - 1) == kBatched;
  }
  // With a "batched:" parameter, the last launch reached its tiles batched (a launch that ended
  // before them, while state shipped, says not batched). A plain spec leaves the choice to the
  // environment (a run under TESSERA_BATCHING=auto may take packets), so nothing is checked.
  void ExpectBatchedIfAsked() {
    if (!batched()) return;
    int last = -1;
    Ok(tesseraContextGetLastLaunchBatched(ctx_, &last));
    EXPECT_EQ(last, 1) << GetParam();
  }

 private:
  static constexpr char kBatched[] = "batched:";
  std::optional<test::ScopedEnv> batching_;
};

// OnDevicesFixture with a width x height float OUTPUT buffer `result` that launches fill: launches
// that must succeed or fail, and a check of every element.
class GridFixture : public OnDevicesFixture {
 protected:
  GridFixture(unsigned width, unsigned height) : width_(width), height_(height) {}
  void SetUp() override {
    OnDevicesFixture::SetUp();
    result_ = Buffer2D("result", RT_BUFFER_OUTPUT, RT_FORMAT_FLOAT, width_, height_);
  }

  // Launches and returns the result buffer; fails the test with the launch's message.
  std::vector<float> Launch() {
    const RTresult code = rtContextLaunch2D(ctx_, 0, width_, height_);
    EXPECT_EQ(code, RT_SUCCESS) << Error(code);
    return ReadAs<float>(result_);
  }

  // The message of a launch that must fail.
  std::string FailedLaunch() {
    const RTresult code = rtContextLaunch2D(ctx_, 0, width_, height_);
    EXPECT_NE(code, RT_SUCCESS);
    return Error(code);
  }

  // Every element equals expected(x, y) of its launch index (unsigned components; a lambda that
  // takes floats gets them converted).
  template <typename F>
  void ExpectEach(const std::vector<float>& values, F expected) {
    ASSERT_EQ(values.size(), size_t{width_} * height_);
    for (unsigned y = 0; y < height_; ++y) {
      for (unsigned x = 0; x < width_; ++x) {
        EXPECT_EQ(values[y * width_ + x], expected(x, y))
            << "launch index (" << x << ", " << y << ")";
      }
    }
  }

  const unsigned width_, height_;
  RTbuffer result_ = nullptr;
};

// A test name for a device spec parameter: "inproc" -> "Inproc", "local:2" -> "Local2",
// "batched:local:2" -> "BatchedLocal2".
inline std::string DeviceName(const ::testing::TestParamInfo<const char*>& info) {
  std::string name;
  bool word_start = true;
  for (const char* c = info.param; *c != '\0'; ++c) {
    const auto u = static_cast<unsigned char>(*c);
    if (std::isalnum(u)) name += static_cast<char>(word_start ? std::toupper(u) : u);
    word_start = *c == ':' && !std::isdigit(static_cast<unsigned char>(c[1]));
  }
  return name;
}

}  // namespace tessera::testing

#endif  // TESSERA_TESTS_SEMANTICS_RT_FIXTURE_H_

// A context wired to fake devices, with a small scene, for tests of lowering and launch.
#ifndef TESSERA_TESTS_API_LAUNCH_FIXTURE_H_
#define TESSERA_TESTS_API_LAUNCH_FIXTURE_H_

#include <cstring>
#include <memory>
#include <vector>

#include "api_test_util.h"
#include "fake_device.h"
#include "gtest/gtest.h"
#include "tessera/rt.h"
#include "testing_hooks.h"

namespace tessera::test {

class LaunchTest : public ::testing::Test {
 protected:
  static constexpr int kWidth = 8;
  static constexpr int kHeight = 4;

  void SetUp() override {
    ASSERT_EQ(rtContextCreate(&ctx), RT_SUCCESS);
    UseFakes(1);
    ASSERT_EQ(rtContextSetEntryPointCount(ctx, 1), RT_SUCCESS);
    ASSERT_EQ(rtContextSetRayTypeCount(ctx, 1), RT_SUCCESS);
    raygen = MakeProgram("ray_gen");
    ASSERT_EQ(rtContextSetRayGenerationProgram(ctx, 0, raygen), RT_SUCCESS);

    ASSERT_EQ(rtBufferCreate(ctx, RT_BUFFER_OUTPUT, &output), RT_SUCCESS);
    ASSERT_EQ(rtBufferSetFormat(output, RT_FORMAT_FLOAT), RT_SUCCESS);
    ASSERT_EQ(rtBufferSetSize2D(output, kWidth, kHeight), RT_SUCCESS);
    ASSERT_EQ(rtBufferCreate(ctx, RT_BUFFER_INPUT, &input), RT_SUCCESS);
    ASSERT_EQ(rtBufferSetFormat(input, RT_FORMAT_INT), RT_SUCCESS);
    ASSERT_EQ(rtBufferSetSize1D(input, 16), RT_SUCCESS);
    void* p;
    ASSERT_EQ(rtBufferMap(input, &p), RT_SUCCESS);
    for (int i = 0; i < 16; ++i) static_cast<int*>(p)[i] = i;
    ASSERT_EQ(rtBufferUnmap(input), RT_SUCCESS);
    BindObject(ctx_var("output"), output);
    BindObject(ctx_var("input"), input);
    ASSERT_EQ(rtVariableSet1f(ctx_var("scale"), 2.5f), RT_SUCCESS);

    // top_object → group → transform → geometry group → instance (geometry, material).
    ASSERT_EQ(rtGeometryCreate(ctx, &geometry), RT_SUCCESS);
    ASSERT_EQ(rtGeometrySetPrimitiveCount(geometry, 1), RT_SUCCESS);
    ASSERT_EQ(rtGeometrySetIntersectionProgram(geometry, MakeProgram("intersect")), RT_SUCCESS);
    ASSERT_EQ(rtGeometrySetBoundingBoxProgram(geometry, MakeProgram("bounds")), RT_SUCCESS);
    ASSERT_EQ(rtMaterialCreate(ctx, &material), RT_SUCCESS);
    ASSERT_EQ(rtMaterialSetClosestHitProgram(material, 0, MakeProgram("closest_hit")), RT_SUCCESS);
    ASSERT_EQ(rtGeometryInstanceCreate(ctx, &instance), RT_SUCCESS);
    ASSERT_EQ(rtGeometryInstanceSetGeometry(instance, geometry), RT_SUCCESS);
    ASSERT_EQ(rtGeometryInstanceSetMaterialCount(instance, 1), RT_SUCCESS);
    ASSERT_EQ(rtGeometryInstanceSetMaterial(instance, 0, material), RT_SUCCESS);
    ASSERT_EQ(rtGeometryGroupCreate(ctx, &geometry_group), RT_SUCCESS);
    ASSERT_EQ(rtGeometryGroupSetChildCount(geometry_group, 1), RT_SUCCESS);
    ASSERT_EQ(rtGeometryGroupSetChild(geometry_group, 0, instance), RT_SUCCESS);
    geometry_accel = MakeAcceleration();
    ASSERT_EQ(rtGeometryGroupSetAcceleration(geometry_group, geometry_accel), RT_SUCCESS);
    ASSERT_EQ(rtTransformCreate(ctx, &transform), RT_SUCCESS);
    const float m[16] = {2, 0, 0, 1, 0, 2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 1};
    ASSERT_EQ(rtTransformSetMatrix(transform, 0, m, nullptr), RT_SUCCESS);
    ASSERT_EQ(rtTransformSetChild(transform, geometry_group), RT_SUCCESS);
    ASSERT_EQ(rtGroupCreate(ctx, &group), RT_SUCCESS);
    ASSERT_EQ(rtGroupSetChildCount(group, 1), RT_SUCCESS);
    ASSERT_EQ(rtGroupSetChild(group, 0, transform), RT_SUCCESS);
    group_accel = MakeAcceleration();
    ASSERT_EQ(rtGroupSetAcceleration(group, group_accel), RT_SUCCESS);
    BindObject(ctx_var("top_object"), group);
  }

  void TearDown() override { EXPECT_EQ(rtContextDestroy(ctx), RT_SUCCESS); }

  // Replaces the context's devices with `n` fakes; records_[i] belongs to device i.
  void UseFakes(int n) {
    records.clear();
    std::vector<std::unique_ptr<Device>> devices;
    for (int i = 0; i < n; ++i) {
      records.push_back(std::make_shared<FakeDevice::Record>());
      devices.push_back(std::make_unique<FakeDevice>(records.back(), "fake" + std::to_string(i)));
    }
    ASSERT_EQ(api::testing::UseDevices(ctx, std::move(devices)), RT_SUCCESS);
  }

  RTprogram MakeProgram(const char* function) {
    RTprogram p = nullptr;
    EXPECT_EQ(rtProgramCreateFromPTXFile(ctx, kTestModule, function, &p), RT_SUCCESS);
    return p;
  }

  RTacceleration MakeAcceleration() {
    RTacceleration a = nullptr;
    EXPECT_EQ(rtAccelerationCreate(ctx, &a), RT_SUCCESS);
    EXPECT_EQ(rtAccelerationSetBuilder(a, "Bvh"), RT_SUCCESS);
    EXPECT_EQ(rtAccelerationSetTraverser(a, "Bvh"), RT_SUCCESS);
    return a;
  }

  // The context variable `name`, declared on first use.
  RTvariable ctx_var(const char* name) {
    RTvariable v = nullptr;
    EXPECT_EQ(rtContextQueryVariable(ctx, name, &v), RT_SUCCESS);
    if (v == nullptr) {
      EXPECT_EQ(rtContextDeclareVariable(ctx, name, &v), RT_SUCCESS);
    }
    return v;
  }

  void BindObject(RTvariable v, void* object) {
    ASSERT_EQ(rtVariableSetObject(v, object), RT_SUCCESS);
  }

  static uint64_t Id(RTbuffer b) {
    int id = 0;
    EXPECT_EQ(rtBufferGetId(b, &id), RT_SUCCESS);
    return static_cast<uint64_t>(id);
  }

  RTresult Launch(RTsize w = kWidth, RTsize h = kHeight) {
    deltas_before_.clear();
    for (const auto& r : records) deltas_before_.push_back(r->deltas.size());
    return rtContextLaunch2D(ctx, 0, w, h);
  }

  // The delta the last Launch() sent `device`, or an empty one: a launch with nothing new for a
  // device sends it none.
  const v1::StateDelta& LastDelta(int device = 0) {
    static const v1::StateDelta kNothing;
    const auto& deltas = records[device]->deltas;
    const size_t before =
        static_cast<size_t>(device) < deltas_before_.size() ? deltas_before_[device] : 0;
    return deltas.size() > before ? deltas.back() : kNothing;
  }
  const v1::LaunchRequest& LastLaunch(int device = 0) { return records[device]->launches.back(); }

  RTcontext ctx = nullptr;
  std::vector<std::shared_ptr<FakeDevice::Record>> records;
  std::vector<size_t> deltas_before_;  // per device, when the last Launch() began
  RTprogram raygen = nullptr;
  RTbuffer output = nullptr;
  RTbuffer input = nullptr;
  RTgeometry geometry = nullptr;
  RTmaterial material = nullptr;
  RTgeometryinstance instance = nullptr;
  RTgeometrygroup geometry_group = nullptr;
  RTacceleration geometry_accel = nullptr;
  RTtransform transform = nullptr;
  RTgroup group = nullptr;
  RTacceleration group_accel = nullptr;
};

// Ids of the objects in a delta, by kind (the oneof case).
inline std::vector<v1::Object::KindCase> ObjectKinds(const v1::StateDelta& delta) {
  std::vector<v1::Object::KindCase> kinds;
  for (const v1::Object& o : delta.objects()) kinds.push_back(o.kind_case());
  return kinds;
}

}  // namespace tessera::test

#endif  // TESSERA_TESTS_API_LAUNCH_FIXTURE_H_

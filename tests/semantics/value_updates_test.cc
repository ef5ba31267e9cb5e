// Variable values and buffer contents changed between launches reach the next launch from every
// scope, also when a device keeps its launch plan across deltas of values alone
// (Replica::structure_generation): values that were equal, and so shared by all bindings of a
// module, may come to differ, and a variable added later still shadows. On an in-process device and
// on worker processes.
#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

#include "rt_fixture.h"

namespace tessera::testing {
namespace {

constexpr char kModule[] = "value_updates_programs";
constexpr unsigned kCount = 4;  // instances, one per launch index x

class ValueUpdatesTest : public OnDevicesFixture {
 protected:
  void SetUp() override {
    OnDevicesFixture::SetUp();
    result_ = Buffer2D("result", RT_BUFFER_OUTPUT, RT_FORMAT_FLOAT, kCount, 1);
    Ok(rtBufferCreate(ctx_, RT_BUFFER_INPUT, &bias_));
    Ok(rtBufferSetFormat(bias_, RT_FORMAT_FLOAT));
    Ok(rtBufferSetSize1D(bias_, kCount));
    Biases({0.f, 0.f, 0.f, 0.f});
    Ok(rtVariableSetObject(ContextVar("bias"), bias_));
    Ok(rtContextSetRayGenerationProgram(ctx_, 0, Program(kModule, "row_raygen")));
    Ok(rtContextSetMissProgram(ctx_, 0, Program(kModule, "row_miss")));
    Ok(rtVariableSet1f(ContextVar("frame"), 0.f));
    Ok(rtVariableSet1f(ContextVar("offset"), 0.f));
    closest_hit_ = Program(kModule, "row_closest_hit");
    Ok(rtGeometryCreate(ctx_, &geometry_));
    Ok(rtGeometrySetPrimitiveCount(geometry_, 1));
    Ok(rtGeometrySetIntersectionProgram(geometry_, Program(kModule, "square_intersect")));
    Ok(rtGeometrySetBoundingBoxProgram(geometry_, Program(kModule, "square_bounds")));
    RTgeometrygroup& group = geometry_group_;
    Ok(rtGeometryGroupCreate(ctx_, &group));
    Ok(rtGeometryGroupSetAcceleration(group, Accel()));
    Ok(rtGeometryGroupSetChildCount(group, kCount));
    for (unsigned i = 0; i < kCount; ++i) {
      Ok(rtMaterialCreate(ctx_, &materials_[i]));
      Ok(rtMaterialSetClosestHitProgram(materials_[i], 0, closest_hit_));
      Ok(rtGeometryInstanceCreate(ctx_, &instances_[i]));
      Ok(rtGeometryInstanceSetGeometry(instances_[i], geometry_));
      Ok(rtGeometryInstanceSetMaterialCount(instances_[i], 1));
      Ok(rtGeometryInstanceSetMaterial(instances_[i], 0, materials_[i]));
      Ok(rtVariableSet1f(Declare(instances_[i], "center"), 2.f * i));
      Ok(rtGeometryGroupSetChild(group, i, instances_[i]));
    }
    Ok(rtVariableSetObject(ContextVar("top_object"), group));
  }

  RTvariable Declare(RTgeometryinstance gi, const char* name) {
    RTvariable v = nullptr;
    if (rtGeometryInstanceQueryVariable(gi, name, &v) != RT_SUCCESS || v == nullptr) {
      EXPECT_EQ(rtGeometryInstanceDeclareVariable(gi, name, &v), RT_SUCCESS);
    }
    return v;
  }
  RTvariable Declare(RTmaterial m, const char* name) {
    RTvariable v = nullptr;
    if (rtMaterialQueryVariable(m, name, &v) != RT_SUCCESS || v == nullptr) {
      EXPECT_EQ(rtMaterialDeclareVariable(m, name, &v), RT_SUCCESS);
    }
    return v;
  }

  // Sets instance i's tint to tints[i].
  void InstanceTints(std::vector<float> tints) {
    for (unsigned i = 0; i < kCount; ++i)
      Ok(rtVariableSet1f(Declare(instances_[i], "tint"), tints[i]));
  }

  void Biases(std::vector<float> values) {
    void* p = nullptr;
    Ok(rtBufferMap(bias_, &p));
    std::memcpy(p, values.data(), sizeof(float) * kCount);
    Ok(rtBufferUnmap(bias_));
  }

  std::vector<float> Launch() {
    const RTresult code = rtContextLaunch2D(ctx_, 0, kCount, 1);
    EXPECT_EQ(code, RT_SUCCESS) << Error(code);
    return ReadAs<float>(result_);
  }

  RTbuffer result_ = nullptr, bias_ = nullptr;
  RTprogram closest_hit_ = nullptr;
  RTgeometry geometry_ = nullptr;
  RTgeometrygroup geometry_group_ = nullptr;
  RTmaterial materials_[kCount] = {};
  RTgeometryinstance instances_[kCount] = {};
};

using Floats = std::vector<float>;

TEST_P(ValueUpdatesTest, ContextValuesReachEveryLaunch) {
  InstanceTints({1.f, 2.f, 3.f, 4.f});
  for (int f = 0; f < 4; ++f) {
    Ok(rtVariableSet1f(ContextVar("frame"), 10.f * f));
    Ok(rtVariableSet1f(ContextVar("offset"), 100.f * f));
    const float add = 110.f * f;
    EXPECT_EQ(Launch(), (Floats{1.f + add, 2.f + add, 3.f + add, 4.f + add})) << "launch " << f;
  }
}

// Tints of 1 everywhere (the module's initializer too) are one value for every binding of the
// module; then one instance's changes, and the device must stop sharing it.
TEST_P(ValueUpdatesTest, EqualInstanceValuesMayComeToDiffer) {
  InstanceTints({1.f, 1.f, 1.f, 1.f});
  EXPECT_EQ(Launch(), (Floats{1.f, 1.f, 1.f, 1.f}));
  Ok(rtVariableSet1f(Declare(instances_[2], "tint"), 5.f));
  EXPECT_EQ(Launch(), (Floats{1.f, 1.f, 5.f, 1.f}));
  Ok(rtVariableSet1f(Declare(instances_[2], "tint"), 1.f));
  EXPECT_EQ(Launch(), (Floats{1.f, 1.f, 1.f, 1.f}));
  Ok(rtVariableSet1f(Declare(instances_[0], "tint"), 7.f));
  Ok(rtVariableSet1f(ContextVar("frame"), 0.5f));
  EXPECT_EQ(Launch(), (Floats{7.5f, 1.5f, 1.5f, 1.5f}));
}

TEST_P(ValueUpdatesTest, MaterialAndProgramValues) {
  for (unsigned i = 0; i < kCount; ++i) Ok(rtVariableSet1f(Declare(materials_[i], "tint"), 2.f));
  EXPECT_EQ(Launch(), (Floats{2.f, 2.f, 2.f, 2.f}));
  Ok(rtVariableSet1f(Declare(materials_[1], "tint"), 3.f));
  EXPECT_EQ(Launch(), (Floats{2.f, 3.f, 2.f, 2.f}));
  RTvariable scale = nullptr;
  Ok(rtProgramDeclareVariable(closest_hit_, "scale", &scale));
  Ok(rtVariableSet1f(scale, 10.f));
  EXPECT_EQ(Launch(), (Floats{20.f, 30.f, 20.f, 20.f}));
  Ok(rtVariableSet1f(scale, 0.5f));
  EXPECT_EQ(Launch(), (Floats{1.f, 1.5f, 1.f, 1.f}));
}

// The intersection program reads half_width from the geometry: 0 makes every ray miss.
TEST_P(ValueUpdatesTest, GeometryValuesReachIntersectionPrograms) {
  InstanceTints({1.f, 2.f, 3.f, 4.f});
  RTvariable half_width = nullptr;
  Ok(rtGeometryDeclareVariable(geometry_, "half_width", &half_width));
  Ok(rtVariableSet1f(half_width, 0.5f));
  EXPECT_EQ(Launch(), (Floats{1.f, 2.f, 3.f, 4.f}));
  Ok(rtVariableSet1f(half_width, 0.f));
  EXPECT_EQ(Launch(), (Floats{-1000.f, -1000.f, -1000.f, -1000.f}));
  Ok(rtVariableSet1f(half_width, 0.25f));
  EXPECT_EQ(Launch(), (Floats{1.f, 2.f, 3.f, 4.f}));
}

// An INPUT buffer's new contents, alone or with new variable values.
TEST_P(ValueUpdatesTest, BufferContents) {
  InstanceTints({1.f, 2.f, 3.f, 4.f});
  EXPECT_EQ(Launch(), (Floats{1.f, 2.f, 3.f, 4.f}));
  Biases({10.f, 20.f, 30.f, 40.f});
  EXPECT_EQ(Launch(), (Floats{11.f, 22.f, 33.f, 44.f}));
  Biases({0.f, 0.f, 0.f, 0.5f});
  Ok(rtVariableSet1f(ContextVar("frame"), 1.f));
  EXPECT_EQ(Launch(), (Floats{2.f, 3.f, 4.f, 5.5f}));
}

// After launches that changed values alone, a tint declared on an instance shadows its
// material's (Table 5), and removing it uncovers the material's again.
TEST_P(ValueUpdatesTest, AVariableAddedLaterShadows) {
  for (unsigned i = 0; i < kCount; ++i) Ok(rtVariableSet1f(Declare(materials_[i], "tint"), 2.f));
  for (int f = 0; f < 2; ++f) {
    Ok(rtVariableSet1f(ContextVar("frame"), f));
    EXPECT_EQ(Launch(), (Floats{2.f + f, 2.f + f, 2.f + f, 2.f + f}));
  }
  Ok(rtVariableSet1f(Declare(instances_[3], "tint"), 9.f));
  EXPECT_EQ(Launch(), (Floats{3.f, 3.f, 3.f, 10.f}));
  RTvariable tint = Declare(instances_[3], "tint");
  Ok(rtGeometryInstanceRemoveVariable(instances_[3], tint));
  EXPECT_EQ(Launch(), (Floats{3.f, 3.f, 3.f, 3.f}));
}

// Graph changes between launches (a transform moved, a group's children, an acceleration's
// builder), alone and with new values, which devices take keeping their bindings.
TEST_P(ValueUpdatesTest, GraphChanges) {
  InstanceTints({1.f, 2.f, 3.f, 4.f});
  RTtransform transform = nullptr;
  Ok(rtTransformCreate(ctx_, &transform));
  Ok(rtTransformSetChild(transform, geometry_group_));
  RTgroup top = nullptr;
  Ok(rtGroupCreate(ctx_, &top));
  Ok(rtGroupSetAcceleration(top, Accel()));
  Ok(rtGroupSetChildCount(top, 1));
  Ok(rtGroupSetChild(top, 0, transform));
  Ok(rtVariableSetObject(ContextVar("top_object"), top));
  constexpr float kMiss = -1000.f;
  // Moved right by 2 * shift, instance j lies under launch index j + shift.
  auto shifted = [&](int shift) {
    Floats out;
    for (int i = 0; i < static_cast<int>(kCount); ++i) {
      const int j = i - shift;
      out.push_back(j >= 0 && j < static_cast<int>(kCount) ? 1.f + j : kMiss);
    }
    return out;
  };
  for (int shift = 0; shift < 3; ++shift) {
    const float m[16] = {1, 0, 0, 2.f * shift, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    Ok(rtTransformSetMatrix(transform, 0, m, nullptr));
    EXPECT_EQ(Launch(), shifted(shift)) << "shift " << shift;
  }
  const float back[16] = {1, 0, 0, -2.f, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  Ok(rtTransformSetMatrix(transform, 0, back, nullptr));
  Ok(rtVariableSet1f(ContextVar("frame"), 0.5f));
  Floats expected = shifted(-1);
  for (float& v : expected) v += 0.5f;
  EXPECT_EQ(Launch(), expected);
  Ok(rtGroupSetChildCount(top, 0));
  EXPECT_EQ(Launch(), (Floats{kMiss + 0.5f, kMiss + 0.5f, kMiss + 0.5f, kMiss + 0.5f}));
  // Both: the geometry group where it is, and through the transform moved left by 2 and nearer
  // by 1, which hides it where both lie under a launch index.
  const float nearer[16] = {1, 0, 0, -2.f, 0, 1, 0, 0, 0, 0, 1, -1.f, 0, 0, 0, 1};
  Ok(rtTransformSetMatrix(transform, 0, nearer, nullptr));
  Ok(rtGroupSetChildCount(top, 2));
  Ok(rtGroupSetChild(top, 0, geometry_group_));
  Ok(rtGroupSetChild(top, 1, transform));
  EXPECT_EQ(Launch(), (Floats{2.5f, 3.5f, 4.5f, 4.5f}));
  RTacceleration accel = nullptr;
  Ok(rtGroupGetAcceleration(top, &accel));
  Ok(rtAccelerationSetBuilder(accel, "NoAccel"));
  Ok(rtAccelerationSetTraverser(accel, "NoAccel"));
  Ok(rtGroupSetChild(top, 1, geometry_group_));  // the same child twice
  EXPECT_EQ(Launch(), (Floats{1.5f, 2.5f, 3.5f, 4.5f}));
}

INSTANTIATE_TEST_SUITE_P(Devices, ValueUpdatesTest, ::testing::Values("inproc", "local:2"),
                         DeviceName);

}  // namespace
}  // namespace tessera::testing

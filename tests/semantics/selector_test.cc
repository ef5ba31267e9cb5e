// Selectors (OptiX 3 guide, "Selector" and "Selector Programs"): a visit program runs where a ray
// reaches the selector and traverses the children it picks with rtIntersectChild; it searches its
// own scope and the selector's (Table 5), sees the ray in the selector's space (Table 6), the
// payload and the closest distance so far (Table 4). Selectors at the top of the graph, under a
// Group and under a Transform, on an in-process device and on worker processes.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "rt_fixture.h"
#include "tessera/rt_ext.h"

namespace tessera::testing {
namespace {

constexpr char kModule[] = "selector_programs";
constexpr unsigned kWidth = 4, kHeight = 2;

class SelectorTest : public OnDevicesFixture {
 protected:
  void SetUp() override {
    OnDevicesFixture::SetUp();
    Ok(rtContextSetRayGenerationProgram(ctx_, 0, Program(kModule, "trace_raygen")));
    Ok(rtContextSetMissProgram(ctx_, 0, Program(kModule, "miss")));
    result_ = Float4Buffer("result", RT_BUFFER_OUTPUT, kWidth, kHeight);
  }

  // A GeometryGroup holding a plane at z = `z` whose closest hit reports `value`.
  RTgeometrygroup Plane(float z, float value) {
    Instance i = MakeInstance(Program(kModule, "plane_intersect"), Program(kModule, "plane_bounds"),
                              1, Program(kModule, "closest_hit"));
    RTvariable v = nullptr;
    Ok(rtGeometryDeclareVariable(i.geometry, "plane_z", &v));
    Ok(rtVariableSet1f(v, z));
    Ok(rtMaterialDeclareVariable(i.material, "value", &v));
    Ok(rtVariableSet1f(v, value));
    return i.group;
  }

  RTselector Selector(const char* visit, std::vector<RTobject> children) {
    RTselector s = nullptr;
    Ok(rtSelectorCreate(ctx_, &s));
    Ok(rtSelectorSetVisitProgram(s, Program(kModule, visit)));
    Ok(rtSelectorSetChildCount(s, static_cast<unsigned>(children.size())));
    for (unsigned i = 0; i < children.size(); ++i) Ok(rtSelectorSetChild(s, i, children[i]));
    return s;
  }

  std::vector<Float4> Launch() {
    const RTresult code = rtContextLaunch2D(ctx_, 0, kWidth, kHeight);
    EXPECT_EQ(code, RT_SUCCESS) << Error(code);
    return Read(result_);
  }

  std::string FailedLaunch() {
    const RTresult code = rtContextLaunch2D(ctx_, 0, kWidth, kHeight);
    EXPECT_NE(code, RT_SUCCESS);
    return Error(code);
  }

  void SetTop(RTobject node) { Ok(rtVariableSetObject(ContextVar("top_object"), node)); }

  RTbuffer result_ = nullptr;
};

// Even rows go up (child 0, value 10), odd rows down (child 1, value 20).
TEST_P(SelectorTest, TheGuidesVisitProgramPicksAChildByDirection) {
  SetTop(Selector("visit_by_direction", {Plane(1.f, 10.f), Plane(2.f, 20.f)}));
  const std::vector<Float4> r = Launch();
  for (unsigned y = 0; y < kHeight; ++y) {
    for (unsigned x = 0; x < kWidth; ++x) {
      SCOPED_TRACE(::testing::Message() << "launch index (" << x << ", " << y << ")");
      const Float4& p = r[y * kWidth + x];
      EXPECT_EQ(p[0], y % 2 == 0 ? 10.f : 20.f);
      EXPECT_EQ(p[1], y % 2 == 0 ? 1.f : 2.f);
      EXPECT_EQ(p[2], 1.f);  // one visit, its payload write kept
      EXPECT_EQ(p[3], static_cast<float>(x));
    }
  }
}

TEST_P(SelectorTest, VisitProgramsSearchTheirOwnScopeThenTheSelectors) {
  RTprogram visit = Program(kModule, "visit_by_choice");
  RTselector s = nullptr;
  Ok(rtSelectorCreate(ctx_, &s));
  Ok(rtSelectorSetVisitProgram(s, visit));
  Ok(rtSelectorSetChildCount(s, 2));
  Ok(rtSelectorSetChild(s, 0, Plane(1.f, 10.f)));
  Ok(rtSelectorSetChild(s, 1, Plane(2.f, 20.f)));
  SetTop(s);
  // Not the context's (Table 5 lists Program and Node only): unset, `choice` is 0.
  Ok(rtVariableSet1ui(ContextVar("choice"), 1));
  for (const Float4& p : Launch()) EXPECT_EQ(p[0], 10.f);
  RTvariable v = nullptr;
  Ok(rtSelectorDeclareVariable(s, "choice", &v));
  Ok(rtVariableSet1ui(v, 1));
  for (const Float4& p : Launch()) EXPECT_EQ(p[0], 20.f);
  Ok(rtProgramDeclareVariable(visit, "choice", &v));
  Ok(rtVariableSet1ui(v, 0));
  for (const Float4& p : Launch()) EXPECT_EQ(p[0], 10.f);
}

// Child 0's plane is farther: the nearer of both hits wins whichever child comes first, and the
// visit program sees the distance child 0 left.
TEST_P(SelectorTest, AVisitProgramMayTraverseSeveralChildren) {
  SetTop(Selector("visit_both", {Plane(2.f, 10.f), Plane(1.f, 20.f)}));
  for (const Float4& p : Launch()) {
    EXPECT_EQ(p[0], 20.f);
    EXPECT_EQ(p[1], 1.f);
    EXPECT_EQ(p[3], 2.f);
  }
}

// Under a Transform the visit program sees the ray in object space; under a Group (an Embree
// scene of children) it runs where the ray reaches the selector's bounds.
TEST_P(SelectorTest, SelectorsUnderTransformsAndGroups) {
  RTselector s = Selector("visit_by_direction", {Plane(1.f, 10.f), Plane(2.f, 20.f)});
  RTtransform t = nullptr;
  Ok(rtTransformCreate(ctx_, &t));
  const float translate[16] = {1, 0, 0, 100, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  Ok(rtTransformSetMatrix(t, 0, translate, nullptr));
  Ok(rtTransformSetChild(t, s));
  RTgroup g = nullptr;
  Ok(rtGroupCreate(ctx_, &g));
  Ok(rtGroupSetAcceleration(g, Accel()));
  Ok(rtGroupSetChildCount(g, 1));
  Ok(rtGroupSetChild(g, 0, t));
  SetTop(g);
  const std::vector<Float4> r = Launch();
  for (unsigned y = 0; y < kHeight; ++y) {
    for (unsigned x = 0; x < kWidth; ++x) {
      const Float4& p = r[y * kWidth + x];
      EXPECT_EQ(p[0], y % 2 == 0 ? 10.f : 20.f) << x << ", " << y;
      EXPECT_EQ(p[3], static_cast<float>(x) - 100.f) << x << ", " << y;
    }
  }
}

// A callable program of another module, set on the selector (a visit program's scopes are its
// own and the selector's), sees the visit program's ray, payload and distance.
TEST_P(SelectorTest, AVisitProgramsCalleePicksTheChild) {
  RTselector s = Selector("visit_via_callable", {Plane(1.f, 10.f), Plane(2.f, 20.f)});
  SetTop(s);
  RTprogram pick = Program("selector_other_programs", "pick_by_direction");
  Ok(rtVariableSetObject(ContextVar("pick"), pick));
  const std::string message = FailedLaunch();
  EXPECT_NE(message.find("on the program or its selector (visit programs do not search the "
                         "context)"),
            std::string::npos)
      << message;

  RTvariable v = nullptr;
  Ok(rtSelectorDeclareVariable(s, "pick", &v));
  Ok(rtVariableSetObject(v, pick));
  const std::vector<Float4> r = Launch();
  for (unsigned y = 0; y < kHeight; ++y) {
    for (unsigned x = 0; x < kWidth; ++x) {
      const Float4& p = r[y * kWidth + x];
      const float t = y % 2 == 0 ? 1.f : 2.f;
      EXPECT_EQ(p, (Float4{10.f * t, t, 11.f, t})) << x << ", " << y;
    }
  }
}

TEST_P(SelectorTest, MistakesInVisitProgramsAreNamed) {
  SetTop(Selector("visit_out_of_range", {Plane(1.f, 10.f), Plane(2.f, 20.f)}));
  std::string message = FailedLaunch();
  EXPECT_NE(message.find("rtIntersectChild(5) from visit program 'visit_out_of_range'"),
            std::string::npos)
      << message;
  EXPECT_NE(message.find("has 2 children"), std::string::npos) << message;

  SetTop(Selector("visit_traces", {Plane(1.f, 10.f)}));
  message = FailedLaunch();
  EXPECT_NE(message.find("rtTrace called from visit program 'visit_traces'"), std::string::npos)
      << message;
  EXPECT_NE(message.find("not allowed in a visit program"), std::string::npos) << message;
}

INSTANTIATE_TEST_SUITE_P(Devices, SelectorTest, ::testing::Values("inproc", "local:2"), DeviceName);

}  // namespace
}  // namespace tessera::testing

// The OptiX 3 guide's Table 4 (semantic variables per program kind), Table 5 (scope search order)
// and Table 6 (object vs world space), row by row, through the C API. The Visit rows are in
// selector_test.cc, with the selectors they need.
#include <cmath>
#include <cstring>
#include <limits>

#include "rt_fixture.h"

namespace tessera::testing {
namespace {

constexpr char kModule[] = "semantics_programs";

class TablesTest : public RtFixture {
 protected:
  void SetUp() override {
    RtFixture::SetUp();
    Ok(rtContextSetEntryPointCount(ctx_, 1));
    Ok(rtContextSetRayTypeCount(ctx_, 1));
    result_ = Float4Buffer("result", RT_BUFFER_OUTPUT, kW, 1);
    is_log_ = Float4Buffer("is_log", RT_BUFFER_OUTPUT, kW, 1);
    ah_log_ = Float4Buffer("ah_log", RT_BUFFER_OUTPUT, kW, 1);
    Ok(rtVariableSet3f(ContextVar("ray_origin"), 0.f, 0.f, -10.f));
    Ok(rtVariableSet3f(ContextVar("ray_dir"), 0.f, 0.f, 1.f));
  }
  // A unit sphere at the origin; `camera` traces from (x, 0, -10) toward +z for x = 0, 1.
  Instance Sphere(const char* closest_hit, const char* any_hit = nullptr) {
    Instance i =
        MakeInstance(Program(kModule, "sphere_intersect"), Program(kModule, "sphere_bounds"), 1,
                     closest_hit ? Program(kModule, closest_hit) : nullptr,
                     any_hit ? Program(kModule, any_hit) : nullptr);
    RTvariable s = nullptr;
    EXPECT_EQ(rtGeometryDeclareVariable(i.geometry, "sphere", &s), RT_SUCCESS);
    EXPECT_EQ(rtVariableSet4f(s, 0.f, 0.f, 0.f, 1.f), RT_SUCCESS);
    return i;
  }
  void Launch(RTobject top, const char* raygen = "trace_camera", const char* miss = "miss_ray") {
    Ok(rtContextSetRayGenerationProgram(ctx_, 0, Program(kModule, raygen)));
    Ok(rtContextSetMissProgram(ctx_, 0, Program(kModule, miss)));
    if (top) Ok(rtVariableSetObject(ContextVar("top_object"), top));
    Ok(rtContextLaunch2D(ctx_, 0, kW, 1));
  }
  static constexpr size_t kW = 2;
  RTbuffer result_ = nullptr, is_log_ = nullptr, ah_log_ = nullptr;
};

// ---- Table 4 -------------------------------------------------------------------------------

TEST_F(TablesTest, Table4RayGenerationSeesLaunchIndexAndDim) {
  Instance s = Sphere("closest_hit_ray");
  Launch(s.group, "raygen_launch_semantics");
  std::vector<Float4> r = Read(result_);
  EXPECT_EQ(r[1], (Float4{1.f, 0.f, 2.f, 1.f}));
}

TEST_F(TablesTest, Table4ClosestHitSeesRayPayloadAndDistance) {
  Instance s = Sphere("closest_hit_ray");
  Launch(s.group);
  std::vector<Float4> r = Read(result_);
  // Ray from (0,0,-10) hits the unit sphere at t = 9.
  EXPECT_EQ(r[0][2], -10.f);
  EXPECT_NEAR(r[0][3], 9.f, 1e-4f);
}

TEST_F(TablesTest, Table4MissSeesRayAndPayload) {
  Instance s = Sphere("closest_hit_ray");
  Launch(s.group);
  std::vector<Float4> r = Read(result_);
  // x = 1 grazes the sphere's silhouette: it misses (disc == 0) and the miss program reports
  // the ray's origin and tmax.
  EXPECT_EQ(r[1][0], 1.f);
  EXPECT_EQ(r[1][2], -10.f);
  EXPECT_GT(r[1][3], 1e26f);
}

TEST_F(TablesTest, Table4IntersectionSeesRayAndAnyHitSeesDistance) {
  Instance s = Sphere("closest_hit_ray", "any_hit_ray");
  Launch(s.group);
  std::vector<Float4> is = Read(is_log_);
  EXPECT_EQ(is[0][2], -10.f);  // the intersection program's ray
  std::vector<Float4> ah = Read(ah_log_);
  EXPECT_EQ(ah[0][2], -10.f);
  EXPECT_NEAR(ah[0][3], 9.f, 1e-4f);  // rtIntersectionDistance in any hit: the candidate's t
}

// ---- Table 5 -------------------------------------------------------------------------------

TEST_F(TablesTest, Table5ClosestHitSearchesProgramInstanceMaterialContext) {
  RTprogram ch = Program(kModule, "closest_hit_value");
  Instance s =
      MakeInstance(Program(kModule, "sphere_intersect"), Program(kModule, "sphere_bounds"), 1, ch);
  RTvariable sphere = nullptr;
  Ok(rtGeometryDeclareVariable(s.geometry, "sphere", &sphere));
  Ok(rtVariableSet4f(sphere, 0.f, 0.f, 0.f, 1.f));
  RTvariable vc = nullptr, vm = nullptr, vi = nullptr, vp = nullptr, vg = nullptr;
  Ok(rtContextDeclareVariable(ctx_, "value", &vc));
  Ok(rtVariableSet1f(vc, 1.f));
  Ok(rtMaterialDeclareVariable(s.material, "value", &vm));
  Ok(rtVariableSet1f(vm, 2.f));
  Ok(rtGeometryInstanceDeclareVariable(s.instance, "value", &vi));
  Ok(rtVariableSet1f(vi, 3.f));
  Ok(rtProgramDeclareVariable(ch, "value", &vp));
  Ok(rtVariableSet1f(vp, 4.f));
  // A Geometry definition is not in a closest-hit program's scope chain.
  Ok(rtGeometryDeclareVariable(s.geometry, "value", &vg));
  Ok(rtVariableSet1f(vg, 99.f));
  Launch(s.group);
  EXPECT_EQ(Read(result_)[0][0], 4.f);
  Ok(rtProgramRemoveVariable(ch, vp));
  Launch(s.group);
  EXPECT_EQ(Read(result_)[0][0], 3.f);  // GeometryInstance shadows Material
  Ok(rtGeometryInstanceRemoveVariable(s.instance, vi));
  Launch(s.group);
  EXPECT_EQ(Read(result_)[0][0], 2.f);
  Ok(rtMaterialRemoveVariable(s.material, vm));
  Launch(s.group);
  EXPECT_EQ(Read(result_)[0][0], 1.f);
  Ok(rtContextRemoveVariable(ctx_, vc));
  Launch(s.group);
  EXPECT_EQ(Read(result_)[0][0], -1.f);  // the static initializer
}

TEST_F(TablesTest, Table5IntersectionSearchesProgramInstanceGeometryContext) {
  RTprogram is = Program(kModule, "sphere_intersect");
  Instance s =
      MakeInstance(is, Program(kModule, "sphere_bounds"), 1, Program(kModule, "closest_hit_ray"));
  RTvariable sphere = nullptr;
  Ok(rtGeometryDeclareVariable(s.geometry, "sphere", &sphere));
  Ok(rtVariableSet4f(sphere, 0.f, 0.f, 0.f, 1.f));
  RTvariable vc = nullptr, vg = nullptr, vi = nullptr, vp = nullptr, vm = nullptr;
  Ok(rtContextDeclareVariable(ctx_, "value", &vc));
  Ok(rtVariableSet1f(vc, 11.f));
  Ok(rtGeometryDeclareVariable(s.geometry, "value", &vg));
  Ok(rtVariableSet1f(vg, 12.f));
  Ok(rtGeometryInstanceDeclareVariable(s.instance, "value", &vi));
  Ok(rtVariableSet1f(vi, 13.f));
  Ok(rtProgramDeclareVariable(is, "value", &vp));
  Ok(rtVariableSet1f(vp, 14.f));
  Ok(rtMaterialDeclareVariable(s.material, "value", &vm));  // not in scope for intersection
  Ok(rtVariableSet1f(vm, 99.f));
  Launch(s.group);
  EXPECT_EQ(Read(is_log_)[0][3], 14.f);
  Ok(rtProgramRemoveVariable(is, vp));
  Launch(s.group);
  EXPECT_EQ(Read(is_log_)[0][3], 13.f);
  Ok(rtGeometryInstanceRemoveVariable(s.instance, vi));
  Launch(s.group);
  EXPECT_EQ(Read(is_log_)[0][3], 12.f);
  Ok(rtGeometryRemoveVariable(s.geometry, vg));
  Launch(s.group);
  EXPECT_EQ(Read(is_log_)[0][3], 11.f);
}

TEST_F(TablesTest, Table5RayGenerationAndMissSearchProgramThenContext) {
  Instance s = Sphere("closest_hit_ray");
  RTprogram rg = Program(kModule, "raygen_value");
  RTvariable vc = nullptr, vp = nullptr;
  Ok(rtContextDeclareVariable(ctx_, "value", &vc));
  Ok(rtVariableSet1f(vc, 5.f));
  Ok(rtProgramDeclareVariable(rg, "value", &vp));
  Ok(rtVariableSet1f(vp, 6.f));
  Ok(rtContextSetRayGenerationProgram(ctx_, 0, rg));
  Ok(rtVariableSetObject(ContextVar("top_object"), s.group));
  Ok(rtContextLaunch2D(ctx_, 0, kW, 1));
  EXPECT_EQ(Read(result_)[0][0], 6.f);
  Ok(rtProgramRemoveVariable(rg, vp));
  Ok(rtContextLaunch2D(ctx_, 0, kW, 1));
  EXPECT_EQ(Read(result_)[0][0], 5.f);

  RTprogram miss = Program(kModule, "miss_value");
  RTvariable vm = nullptr;
  Ok(rtProgramDeclareVariable(miss, "value", &vm));
  Ok(rtVariableSet1f(vm, 7.f));
  Ok(rtContextSetRayGenerationProgram(ctx_, 0, Program(kModule, "trace_camera")));
  Ok(rtContextSetMissProgram(ctx_, 0, miss));
  Ok(rtContextLaunch2D(ctx_, 0, kW, 1));
  EXPECT_EQ(Read(result_)[1], (Float4{7.f, 1.f, 0.f, 0.f}));
  Ok(rtProgramRemoveVariable(miss, vm));
  Ok(rtContextLaunch2D(ctx_, 0, kW, 1));
  EXPECT_EQ(Read(result_)[1][0], 5.f);
}

// ---- Table 6 -------------------------------------------------------------------------------

TEST_F(TablesTest, Table6ObjectSpaceInIntersectionAndAnyHitWorldSpaceInClosestHitAndMiss) {
  Instance s = Sphere("closest_hit_ray", "any_hit_ray");
  RTtransform t = nullptr;
  Ok(rtTransformCreate(ctx_, &t));
  const float m[16] = {1, 0, 0, 5, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};  // translate x by 5
  Ok(rtTransformSetMatrix(t, 0, m, nullptr));
  Ok(rtTransformSetChild(t, s.group));
  RTgroup top = nullptr;
  Ok(rtGroupCreate(ctx_, &top));
  Ok(rtGroupSetAcceleration(top, Accel()));
  Ok(rtGroupSetChildCount(top, 1));
  Ok(rtGroupSetChild(top, 0, t));
  Ok(rtVariableSet3f(ContextVar("ray_origin"), 5.f, 0.f, -10.f));
  Launch(top);
  EXPECT_EQ(Read(is_log_)[0][0], 0.f);  // intersection: object space
  EXPECT_EQ(Read(ah_log_)[0][0], 0.f);  // any hit: object space
  EXPECT_EQ(Read(result_)[0][0], 5.f);  // closest hit: world space
  EXPECT_NEAR(Read(result_)[0][3], 9.f, 1e-4f);
  EXPECT_EQ(Read(result_)[1][0], 6.f);  // miss (x = 6 grazes): world space
}

TEST_F(TablesTest, AttributesFromIntersectionReachClosestHit) {
  Instance s = Sphere("closest_hit_attributes");
  Launch(s.group);
  std::vector<Float4> r = Read(result_);
  EXPECT_EQ(r[0], (Float4{0.f, 0.f, -10.f, 0.f}));  // hit_origin, hit_id
}

TEST_F(TablesTest, TransformsWithoutATransformNodeReturnTheirInput) {
  Instance s = Sphere("closest_hit_transform_specials");
  Launch(s.group);
  const Float4 r = Read(result_)[0];
  EXPECT_EQ(r[0], 0.f);
  EXPECT_TRUE(std::signbit(r[0])) << "-0 became +0";
  EXPECT_EQ(r[1], std::numeric_limits<float>::infinity());
  EXPECT_TRUE(std::signbit(r[2])) << "-0 became +0";
  EXPECT_EQ(r[3], -std::numeric_limits<float>::infinity());
}

// ---- Any hit: ignore restores t and attributes, terminate ends traversal -----------------------

class AnyHitTest : public TablesTest {
 protected:
  // Two slabs at z = 1 (primitive 0) and z = 2 (primitive 1); rays start at z = -10.
  void Run(const char* any_hit) {
    Instance s = MakeInstance(Program(kModule, "slabs_intersect"), Program(kModule, "slabs_bounds"),
                              2, Program(kModule, "closest_hit_count"),
                              any_hit ? Program(kModule, any_hit) : nullptr);
    Launch(s.group);
  }
};

TEST_F(AnyHitTest, WithoutAnyHitTheNearestPrimitiveWins) {
  Run(nullptr);
  Float4 r = Read(result_)[0];
  EXPECT_NEAR(r[1], 11.f, 1e-4f);
  EXPECT_EQ(r[2], 0.f);
}

TEST_F(AnyHitTest, IgnoreRestoresDistanceAndAttributes) {
  Run("any_hit_ignore_first");
  Float4 r = Read(result_)[0];
  EXPECT_NEAR(r[1], 12.f, 1e-4f);  // the far slab
  EXPECT_EQ(r[2], 1.f);            // its attribute, not the ignored one's
}

TEST_F(AnyHitTest, IgnoreEndsTheAnyHitProgram) {
  Run("any_hit_ignore_first_then_count");
  Float4 r = Read(result_)[0];
  EXPECT_EQ(r[0], 1.f);  // the far slab's count; nothing after the near slab's ignore ran
  EXPECT_NEAR(r[1], 12.f, 1e-4f);
  EXPECT_EQ(r[2], 1.f);
}

TEST_F(AnyHitTest, TerminateEndsTheAnyHitProgram) {
  Run("any_hit_terminate_then_count");
  EXPECT_EQ(Read(result_)[0][0], 1.f);  // one call, and nothing after rtTerminateRay ran
}

TEST_F(AnyHitTest, IgnoringEverythingIsAMiss) {
  Run("any_hit_ignore");
  Float4 r = Read(result_)[0];
  EXPECT_GT(r[3], 1e26f);  // miss_ray reports tmax in w
}

TEST_F(AnyHitTest, TerminateEndsTraversalAndRunsClosestHit) {
  Run("any_hit_terminate");
  Float4 r = Read(result_)[0];
  EXPECT_EQ(r[0], 1.f);  // one any-hit call, then traversal stopped
  EXPECT_TRUE(r[2] == 0.f || r[2] == 1.f);
}

// Variables declared inside namespaces bind by their qualified names, as the OptiX guide says
// ("references from the host ... need to include the full namespace"); they all bound by the
// bare name before, so 'outer::ns_probe' set on the host reached nothing.
TEST_F(TablesTest, NamespacedVariablesBindByQualifiedName) {
  RTbuffer out = Float4Buffer("outer::ns_result", RT_BUFFER_OUTPUT, kW, 1);
  Ok(rtContextSetRayGenerationProgram(ctx_, 0, Program(kModule, "write_namespaced")));
  Ok(rtContextLaunch2D(ctx_, 0, kW, 1));
  EXPECT_EQ(Read(out)[0], (Float4{1.f, 2.f, 3.f, 4.f}));  // the static initializers
  Ok(rtVariableSet1f(ContextVar("ns_probe"), 10.f));
  Ok(rtVariableSet1f(ContextVar("outer::ns_probe"), 20.f));
  Ok(rtVariableSet1f(ContextVar("outer::inner::ns_probe"), 30.f));
  Ok(rtVariableSet1f(ContextVar("ns_hidden"), 40.f));
  Ok(rtContextLaunch2D(ctx_, 0, kW, 1));
  EXPECT_EQ(Read(out)[1], (Float4{10.f, 20.f, 30.f, 40.f}));
}

}  // namespace
}  // namespace tessera::testing

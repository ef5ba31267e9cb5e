// Graph nodes: shared children, transforms over several levels, groups of groups, and when
// accelerations are rebuilt.
#include <cmath>
#include <cstring>
#include <vector>

#include "rt_fixture.h"

namespace tessera::testing {
namespace {

constexpr char kModule[] = "semantics_programs";

class GraphTest : public RtFixture {
 protected:
  static constexpr size_t kW = 16;
  void SetUp() override {
    RtFixture::SetUp();
    Ok(rtContextSetEntryPointCount(ctx_, 1));
    Ok(rtContextSetRayTypeCount(ctx_, 1));
    result_ = Float4Buffer("result", RT_BUFFER_OUTPUT, kW, 1);
    Float4Buffer("is_log", RT_BUFFER_OUTPUT, kW, 1);
    Float4Buffer("ah_log", RT_BUFFER_OUTPUT, kW, 1);
    // Rays start at (x, 0, -10), x = 0..15, and go toward +z.
    Ok(rtVariableSet3f(ContextVar("ray_origin"), 0.f, 0.f, -10.f));
    Ok(rtVariableSet3f(ContextVar("ray_dir"), 0.f, 0.f, 1.f));
    Ok(rtContextSetRayGenerationProgram(ctx_, 0, Program(kModule, "trace_camera")));
    Ok(rtContextSetMissProgram(ctx_, 0, Program(kModule, "miss_ray")));
  }
  // A sphere of radius 0.4 at the object-space origin; closest hit reports the world hit origin.
  Instance SmallSphere(const char* bounds = "sphere_bounds") {
    Instance i = MakeInstance(Program(kModule, "sphere_intersect"), Program(kModule, bounds), 1,
                              Program(kModule, "closest_hit_ray"));
    RTvariable s = nullptr;
    EXPECT_EQ(rtGeometryDeclareVariable(i.geometry, "sphere", &s), RT_SUCCESS);
    EXPECT_EQ(rtVariableSet4f(s, 0.f, 0.f, 0.f, 0.4f), RT_SUCCESS);
    return i;
  }
  RTtransform Translate(RTobject child, float x) {
    RTtransform t = nullptr;
    EXPECT_EQ(rtTransformCreate(ctx_, &t), RT_SUCCESS);
    const float m[16] = {1, 0, 0, x, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    EXPECT_EQ(rtTransformSetMatrix(t, 0, m, nullptr), RT_SUCCESS);
    EXPECT_EQ(rtTransformSetChild(t, child), RT_SUCCESS);
    return t;
  }
  RTgroup Group(std::vector<RTobject> children) {
    RTgroup g = nullptr;
    EXPECT_EQ(rtGroupCreate(ctx_, &g), RT_SUCCESS);
    EXPECT_EQ(rtGroupSetAcceleration(g, Accel()), RT_SUCCESS);
    EXPECT_EQ(rtGroupSetChildCount(g, static_cast<unsigned>(children.size())), RT_SUCCESS);
    for (unsigned i = 0; i < children.size(); ++i) {
      EXPECT_EQ(rtGroupSetChild(g, i, children[i]), RT_SUCCESS);
    }
    return g;
  }
  // Which of the kW rays hit something (closest_hit_ray writes t < 1e26 in w).
  std::vector<bool> Hits(RTobject top) {
    EXPECT_EQ(rtVariableSetObject(ContextVar("top_object"), top), RT_SUCCESS);
    RTresult r = rtContextLaunch2D(ctx_, 0, kW, 1);
    EXPECT_EQ(r, RT_SUCCESS) << Error(r);
    std::vector<bool> hits;
    for (const Float4& p : Read(result_)) hits.push_back(p[3] < 1e26f);
    return hits;
  }
  static std::vector<bool> Only(std::initializer_list<int> xs) {
    std::vector<bool> v(kW, false);
    for (int x : xs) v[x] = true;
    return v;
  }
  RTbuffer result_ = nullptr;
};

TEST_F(GraphTest, GeometryGroupAlone) {
  Instance s = SmallSphere();
  EXPECT_EQ(Hits(s.group), Only({0}));
}

TEST_F(GraphTest, SharedChildUnderTwoTransforms) {
  Instance s = SmallSphere();
  RTgroup top = Group({Translate(s.group, 3.f), Translate(s.group, 7.f)});
  EXPECT_EQ(Hits(top), Only({3, 7}));
}

TEST_F(GraphTest, TransformsComposeOverSeveralLevels) {
  Instance s = SmallSphere();
  // Group → T(+1) → Group → T(+2) → T(+4) → GeometryGroup: the sphere lands at x = 7.
  RTtransform inner = Translate(Translate(s.group, 4.f), 2.f);
  RTgroup top = Group({Translate(Group({inner}), 1.f)});
  EXPECT_EQ(Hits(top), Only({7}));
  // The closest hit sees the world-space ray (origin x = 7), not the object-space one.
  EXPECT_EQ(Read(result_)[7][0], 7.f);
}

TEST_F(GraphTest, TransformAtTheTopAndGroupsOfGroups) {
  Instance s = SmallSphere();
  EXPECT_EQ(Hits(Translate(s.group, 5.f)), Only({5}));
  RTgroup top = Group({Group({s.group}), Group({Translate(s.group, 9.f)})});
  EXPECT_EQ(Hits(top), Only({0, 9}));
}

// Each level holds the level below twice, once moved out of the rays' way: 2^30 paths through
// 61 nodes. Building the accelerations visits each node once (a visit per path never ends).
TEST_F(GraphTest, SubgraphsSharedAtEveryLevelAreBuiltOnce) {
  Instance s = SmallSphere();
  RTobject level = s.group;
  for (int i = 0; i < 4; ++i) level = Group({level, Translate(level, float(1 << i))});
  for (int i = 0; i < 26; ++i) {  // moved along -y: rays at y = 0 pass them by
    RTtransform away = nullptr;
    ASSERT_EQ(rtTransformCreate(ctx_, &away), RT_SUCCESS);
    const float m[16] = {1, 0, 0, 0, 0, 1, 0, -10.f * float(1 << i), 0, 0, 1, 0, 0, 0, 0, 1};
    ASSERT_EQ(rtTransformSetMatrix(away, 0, m, nullptr), RT_SUCCESS);
    ASSERT_EQ(rtTransformSetChild(away, level), RT_SUCCESS);
    level = Group({level, away});
  }
  EXPECT_EQ(Hits(level), std::vector<bool>(kW, true));
  // The depth limit holds for a shared subgraph reached again deeper down: this one is 61 levels
  // high, so under four more levels it is too deep, though its first visit was fine. Validation
  // says so before any device sees the graph.
  RTobject deeper = level;
  for (int i = 0; i < 4; ++i) deeper = Group({deeper});
  EXPECT_EQ(rtVariableSetObject(ContextVar("top_object"), Group({level, deeper})), RT_SUCCESS);
  for (RTresult r : {rtContextValidate(ctx_), rtContextLaunch2D(ctx_, 0, kW, 1)}) {
    EXPECT_NE(r, RT_SUCCESS);
    EXPECT_NE(Error(r).find("the graph below it is 65 levels deep; devices traverse at most 64"),
              std::string::npos)
        << Error(r);
  }
}

TEST_F(GraphTest, ChangingATransformMovesTheChild) {
  Instance s = SmallSphere();
  RTtransform t = Translate(s.group, 2.f);
  RTgroup top = Group({t});
  EXPECT_EQ(Hits(top), Only({2}));
  const float m[16] = {1, 0, 0, 11, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  Ok(rtTransformSetMatrix(t, 0, m, nullptr));
  RTacceleration a = nullptr;
  Ok(rtGroupGetAcceleration(top, &a));
  Ok(rtAccelerationMarkDirty(a));
  EXPECT_EQ(Hits(top), Only({11}));
}

// Bounds are only required to be conservative: a box of +-FLT_MAX (past what Embree builds)
// still gets the primitive hit, alone, in a group, and scaled up by a transform.
TEST_F(GraphTest, UnboundedBoxesAreStillHit) {
  Instance s = SmallSphere("unbounded_bounds");
  EXPECT_EQ(Hits(s.group), Only({0}));
  EXPECT_EQ(Hits(Group({Translate(s.group, 4.f)})), Only({4}));
  RTtransform grow = nullptr;
  Ok(rtTransformCreate(ctx_, &grow));
  const float m[16] = {4, 0, 0, 8, 0, 4, 0, 0, 0, 0, 4, 0, 0, 0, 0, 1};  // radius 1.6 at x = 8
  Ok(rtTransformSetMatrix(grow, 0, m, nullptr));
  Ok(rtTransformSetChild(grow, s.group));
  EXPECT_EQ(Hits(Group({grow})), Only({7, 8, 9}));
}

// Whether a matrix is singular does not depend on its units: squeezing x by 1e-12 is exactly
// invertible, and only the ray through the sphere's center still hits it.
TEST_F(GraphTest, AnisotropicTransformsAreInvertible) {
  Instance s = SmallSphere();
  RTtransform squeeze = nullptr;
  Ok(rtTransformCreate(ctx_, &squeeze));
  const float m[16] = {1e-12f, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  Ok(rtTransformSetMatrix(squeeze, 0, m, nullptr));
  Ok(rtTransformSetChild(squeeze, s.group));
  EXPECT_EQ(Hits(Group({squeeze})), Only({0}));
  const float far[16] = {1, 0, 0, 2e12f, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  EXPECT_EQ(rtTransformSetMatrix(squeeze, 0, far, nullptr), RT_SUCCESS);
}

// rtTransform* in an intersection program gives the transforms above the primitive, also when
// the acceleration takes the mesh as native triangles and the program runs after traversal.
TEST_F(GraphTest, IntersectionProgramsSeeTheirTransformWithEveryBuilder) {
  RTbuffer vertices = nullptr, indices = nullptr;
  Ok(rtBufferCreate(ctx_, RT_BUFFER_INPUT, &vertices));
  Ok(rtBufferSetFormat(vertices, RT_FORMAT_FLOAT3));
  Ok(rtBufferSetSize1D(vertices, 4));
  Ok(rtBufferCreate(ctx_, RT_BUFFER_INPUT, &indices));
  Ok(rtBufferSetFormat(indices, RT_FORMAT_INT3));
  Ok(rtBufferSetSize1D(indices, 2));
  const float quad[12] = {-0.5f, -0.5f, 0, 0.5f, -0.5f, 0, 0.5f, 0.5f, 0, -0.5f, 0.5f, 0};
  const int triangles[6] = {0, 1, 2, 0, 2, 3};
  void* p = nullptr;
  Ok(rtBufferMap(vertices, &p));
  std::memcpy(p, quad, sizeof(quad));
  Ok(rtBufferUnmap(vertices));
  Ok(rtBufferMap(indices, &p));
  std::memcpy(p, triangles, sizeof(triangles));
  Ok(rtBufferUnmap(indices));
  for (const char* builder : {"Bvh", "Trbvh"}) {
    SCOPED_TRACE(builder);
    Instance mesh =
        MakeInstance(Program(kModule, "mesh_intersect"), Program(kModule, "mesh_bounds"), 2,
                     Program(kModule, "closest_hit_attributes"));
    RTvariable v = nullptr;
    Ok(rtGeometryDeclareVariable(mesh.geometry, "vertex_buffer", &v));
    Ok(rtVariableSetObject(v, vertices));
    Ok(rtGeometryDeclareVariable(mesh.geometry, "index_buffer", &v));
    Ok(rtVariableSetObject(v, indices));
    Ok(rtGeometryGroupSetAcceleration(mesh.group, Accel(builder)));
    EXPECT_EQ(Hits(Group({Translate(mesh.group, 6.f)})), Only({6}));
    EXPECT_EQ(Read(result_)[6][0], 6.f);  // the object-space origin, in world space
  }
}

// A graph node binds only to an rtObject, and an rtObject only to a node: a float2 has the same
// 8 bytes but would read the node's id as its value.
TEST_F(GraphTest, NodesBindOnlyToRtObject) {
  Instance s = SmallSphere();
  Ok(rtVariableSetObject(ContextVar("pair"), s.group));
  Ok(rtVariableSetObject(ContextVar("top_object"), s.group));
  RTresult r = rtContextLaunch2D(ctx_, 0, kW, 1);
  EXPECT_NE(r, RT_SUCCESS);
  EXPECT_NE(Error(r).find("'pair' is declared as float2 but is bound to a graph node"),
            std::string::npos)
      << Error(r);
  // A variable keeps its type once set: declare both again.
  Ok(rtContextRemoveVariable(ctx_, ContextVar("pair")));
  Ok(rtContextRemoveVariable(ctx_, ContextVar("top_object")));
  Ok(rtVariableSet2ui(ContextVar("top_object"), 9u, 0u));
  r = rtContextLaunch2D(ctx_, 0, kW, 1);
  EXPECT_NE(r, RT_SUCCESS);
  EXPECT_NE(Error(r).find("'top_object' is declared as rtObject but was set as uint2"),
            std::string::npos)
      << Error(r);
  Ok(rtContextRemoveVariable(ctx_, ContextVar("top_object")));
  EXPECT_EQ(Hits(s.group), Only({0}));
}

// Tracing an rtObject nobody set says so, instead of naming object #0.
TEST_F(GraphTest, TracingAnUnsetRtObjectSaysSo) {
  Instance s = SmallSphere();
  EXPECT_EQ(Hits(s.group), Only({0}));
  Ok(rtContextRemoveVariable(ctx_, ContextVar("top_object")));
  RTresult r = rtContextLaunch2D(ctx_, 0, kW, 1);
  EXPECT_NE(r, RT_SUCCESS);
  EXPECT_NE(Error(r).find("rtTrace on an rtObject that no scope sets"), std::string::npos)
      << Error(r);
}

// A node that only an unattached program's variable names (still on the devices until it is
// destroyed) cannot fail launches, even when its scene cannot be built.
TEST_F(GraphTest, NodesOnlyUnattachedProgramsNameDoNotFailLaunches) {
  Instance s = SmallSphere();
  Instance orphan = SmallSphere();
  RTprogram detached = Program(kModule, "miss_ray");
  RTvariable v = nullptr;
  Ok(rtProgramDeclareVariable(detached, "top_object", &v));
  Ok(rtVariableSetObject(v, orphan.group));
  Ok(rtContextSetMissProgram(ctx_, 0, detached));
  EXPECT_EQ(Hits(s.group), Only({0}));
  Ok(rtContextSetMissProgram(ctx_, 0, Program(kModule, "miss_ray")));
  RTacceleration accel = nullptr;
  Ok(rtGeometryGroupGetAcceleration(orphan.group, &accel));
  Ok(rtAccelerationDestroy(accel));  // the orphan's scene can no longer be built
  Ok(rtContextValidate(ctx_));
  EXPECT_EQ(Hits(s.group), Only({0}));
}

TEST_F(GraphTest, AccelerationsRebuildOnlyWhenDirty) {
  RTbuffer calls = nullptr;
  Ok(rtBufferCreate(ctx_, RT_BUFFER_INPUT_OUTPUT, &calls));
  Ok(rtBufferSetFormat(calls, RT_FORMAT_UNSIGNED_INT));
  Ok(rtBufferSetSize1D(calls, 1));
  Ok(rtVariableSetObject(ContextVar("bounds_calls"), calls));
  Instance s = SmallSphere("counted_sphere_bounds");
  auto count = [&] {
    void* p = nullptr;
    EXPECT_EQ(rtBufferMap(calls, &p), RT_SUCCESS);
    unsigned n = *static_cast<unsigned*>(p);
    EXPECT_EQ(rtBufferUnmap(calls), RT_SUCCESS);
    return n;
  };
  Ok(rtVariableSetObject(ContextVar("top_object"), s.group));
  Ok(rtContextLaunch2D(ctx_, 0, 0, 0));  // builds accelerations only
  EXPECT_EQ(count(), 1u);
  EXPECT_EQ(Hits(s.group), Only({0}));
  EXPECT_EQ(count(), 1u);  // unchanged scene: no rebuild
  RTacceleration a = nullptr;
  Ok(rtGeometryGroupGetAcceleration(s.group, &a));
  Ok(rtAccelerationMarkDirty(a));
  EXPECT_EQ(Hits(s.group), Only({0}));
  EXPECT_EQ(count(), 2u);
}

// Two geometry groups, each counting its bounding-box runs in its own element of a context
// buffer: marking one acceleration dirty rebuilds that one alone, in the engine and in a worker
// process; an unchanged launch rebuilds nothing.
TEST_F(GraphTest, OnlyTheAccelerationThatChangedIsRebuilt) {
  for (const char* spec : {"inproc", "local:1"}) {
    SCOPED_TRACE(spec);
    Ok(tesseraContextSetDeviceSpec(ctx_, spec));
    RTbuffer calls = nullptr;
    Ok(rtBufferCreate(ctx_, RT_BUFFER_INPUT_OUTPUT, &calls));
    Ok(rtBufferSetFormat(calls, RT_FORMAT_UNSIGNED_INT));
    Ok(rtBufferSetSize1D(calls, 2));
    Ok(rtVariableSetObject(ContextVar("bounds_calls"), calls));
    auto counts = [&] {
      void* p = nullptr;
      EXPECT_EQ(rtBufferMap(calls, &p), RT_SUCCESS);
      std::vector<unsigned> n(static_cast<unsigned*>(p), static_cast<unsigned*>(p) + 2);
      EXPECT_EQ(rtBufferUnmap(calls), RT_SUCCESS);
      return n;
    };
    Instance a = SmallSphere("slot_counted_sphere_bounds");
    Instance b = SmallSphere("slot_counted_sphere_bounds");
    unsigned slot = 0;
    for (RTgeometry g : {a.geometry, b.geometry}) {
      RTvariable v = nullptr;
      Ok(rtGeometryDeclareVariable(g, "bounds_slot", &v));
      Ok(rtVariableSet1ui(v, slot++));
    }
    RTgroup top = Group({Translate(a.group, 3.f), Translate(b.group, 7.f)});
    EXPECT_EQ(Hits(top), Only({3, 7}));
    EXPECT_EQ(counts(), (std::vector<unsigned>{1, 1}));
    EXPECT_EQ(Hits(top), Only({3, 7}));
    EXPECT_EQ(counts(), (std::vector<unsigned>{1, 1}));  // unchanged: no rebuild
    RTacceleration accel = nullptr;
    Ok(rtGeometryGroupGetAcceleration(b.group, &accel));
    Ok(rtAccelerationMarkDirty(accel));
    EXPECT_EQ(Hits(top), Only({3, 7}));
    EXPECT_EQ(counts(), (std::vector<unsigned>{1, 2}));  // b's alone
  }
}

}  // namespace
}  // namespace tessera::testing

// Flattened groups (worker/core/scene.cc): a Group's chains of Groups and Transforms down to
// GeometryGroups become one level of Embree instances. Programs must see what the per-level path
// gives them (acceleration property "flatten" "0"): the same hit, distance and primitive, the
// same transforms in intersection and closest-hit programs, the same any-hit candidates, on an
// in-process device and on worker processes. Matrices are exact in float (translations by
// halves, scales by two, quarter turns), so that composing a chain at once or level by level
// rounds alike.
#include <cstring>
#include <string>
#include <vector>

#include "rt_fixture.h"
#include "triangles_fixture.h"

namespace tessera::testing {
namespace {

constexpr char kModule[] = "flattened_graph_programs";

class FlattenedGraphTest : public OnDevicesFixture {
 protected:
  static constexpr size_t kW = 32, kH = 8;
  void SetUp() override {
    OnDevicesFixture::SetUp();
    Ok(rtContextSetRayTypeCount(ctx_, 2));
    for (const char* name : {"out_hit", "out_point", "out_matrix", "out_intersect"}) {
      outputs_.push_back(Float4Buffer(name, RT_BUFFER_OUTPUT, kW, kH));
    }
    Ok(rtContextSetRayGenerationProgram(ctx_, 0, Program(kModule, "camera")));
    for (unsigned t = 0; t < 2; ++t) Ok(rtContextSetMissProgram(ctx_, t, Program(kModule, "miss")));
    closest_hit_ = Program(kModule, "closest_hit");
    count_any_hit_ = Program(kModule, "count_any_hit");
  }

  RTgeometrygroup Leaf(RTgeometry geometry, float tag, const char* builder) {
    RTmaterial m = nullptr;
    Ok(rtMaterialCreate(ctx_, &m));
    Ok(rtMaterialSetClosestHitProgram(m, 0, closest_hit_));
    Ok(rtMaterialSetAnyHitProgram(m, 1, count_any_hit_));
    RTgeometryinstance gi = nullptr;
    Ok(rtGeometryInstanceCreate(ctx_, &gi));
    Ok(rtGeometryInstanceSetGeometry(gi, geometry));
    Ok(rtGeometryInstanceSetMaterialCount(gi, 1));
    Ok(rtGeometryInstanceSetMaterial(gi, 0, m));
    RTvariable v = nullptr;
    Ok(rtGeometryInstanceDeclareVariable(gi, "tag", &v));
    Ok(rtVariableSet1f(v, tag));
    RTgeometrygroup g = nullptr;
    Ok(rtGeometryGroupCreate(ctx_, &g));
    Ok(rtGeometryGroupSetAcceleration(g, Accel(builder)));
    Ok(rtGeometryGroupSetChildCount(g, 1));
    Ok(rtGeometryGroupSetChild(g, 0, gi));
    return g;
  }
  // A sphere (user geometry) of radius `r` at (x, y, 0).
  RTgeometrygroup Sphere(float x, float y, float r, float tag) {
    RTgeometry g = nullptr;
    Ok(rtGeometryCreate(ctx_, &g));
    Ok(rtGeometrySetPrimitiveCount(g, 1));
    Ok(rtGeometrySetIntersectionProgram(g, Program(kModule, "sphere_intersect")));
    Ok(rtGeometrySetBoundingBoxProgram(g, Program(kModule, "sphere_bounds")));
    RTvariable v = nullptr;
    Ok(rtGeometryDeclareVariable(g, "sphere", &v));
    Ok(rtVariableSet4f(v, x, y, 0.f, r));
    return Leaf(g, tag, "Bvh");
  }
  // A square of side 2 at z = 0 around (x, y) as two native triangles (Trbvh).
  RTgeometrygroup Square(float x, float y, float tag, const char* intersect = "mesh_intersect") {
    RTbuffer vertices = nullptr, indices = nullptr;
    Ok(rtBufferCreate(ctx_, RT_BUFFER_INPUT, &vertices));
    Ok(rtBufferSetFormat(vertices, RT_FORMAT_FLOAT3));
    Ok(rtBufferSetSize1D(vertices, 4));
    Ok(rtBufferCreate(ctx_, RT_BUFFER_INPUT, &indices));
    Ok(rtBufferSetFormat(indices, RT_FORMAT_INT3));
    Ok(rtBufferSetSize1D(indices, 2));
    // Corners off the rays' grid (0.5 apart, at quarters), so that no ray meets an edge, the
    // diagonal the two triangles share included.
    const float quad[12] = {x - 1.1f, y - 1.05f, 0, x + 0.9f, y - 1.05f, 0,
                            x + 0.9f, y + 0.95f, 0, x - 1.1f, y + 0.95f, 0};
    const int triangles[6] = {0, 1, 2, 0, 2, 3};
    void* p = nullptr;
    Ok(rtBufferMap(vertices, &p));
    std::memcpy(p, quad, sizeof(quad));
    Ok(rtBufferUnmap(vertices));
    Ok(rtBufferMap(indices, &p));
    std::memcpy(p, triangles, sizeof(triangles));
    Ok(rtBufferUnmap(indices));
    RTgeometry g = nullptr;
    Ok(rtGeometryCreate(ctx_, &g));
    Ok(rtGeometrySetPrimitiveCount(g, 2));
    Ok(rtGeometrySetIntersectionProgram(g, Program(kModule, intersect)));
    Ok(rtGeometrySetBoundingBoxProgram(g, Program(kModule, "mesh_bounds")));
    RTvariable v = nullptr;
    Ok(rtGeometryDeclareVariable(g, "vertex_buffer", &v));
    Ok(rtVariableSetObject(v, vertices));
    Ok(rtGeometryDeclareVariable(g, "index_buffer", &v));
    Ok(rtVariableSetObject(v, indices));
    return Leaf(g, tag, "Trbvh");
  }
  RTtransform Transform(RTobject child, const std::vector<float>& m) {
    RTtransform t = nullptr;
    Ok(rtTransformCreate(ctx_, &t));
    Ok(rtTransformSetMatrix(t, 0, m.data(), nullptr));
    Ok(rtTransformSetChild(t, child));
    return t;
  }
  RTtransform Move(RTobject child, float x, float y, float z) {
    return Transform(child, {1, 0, 0, x, 0, 1, 0, y, 0, 0, 1, z, 0, 0, 0, 1});
  }
  RTgroup Group(const std::vector<RTobject>& children) {
    RTacceleration a = Accel();
    group_accels_.push_back(a);
    RTgroup g = nullptr;
    Ok(rtGroupCreate(ctx_, &g));
    Ok(rtGroupSetAcceleration(g, a));
    Ok(rtGroupSetChildCount(g, static_cast<unsigned>(children.size())));
    for (unsigned i = 0; i < children.size(); ++i) Ok(rtGroupSetChild(g, i, children[i]));
    return g;
  }

  // Every output of a launch on `top`, with every Group flattened or not.
  std::vector<float> Render(RTobject top, bool flatten) {
    for (RTacceleration a : group_accels_) {
      EXPECT_EQ(rtAccelerationSetProperty(a, "flatten", flatten ? "1" : "0"), RT_SUCCESS);
      EXPECT_EQ(rtAccelerationMarkDirty(a), RT_SUCCESS);
    }
    EXPECT_EQ(rtVariableSetObject(ContextVar("top_object"), top), RT_SUCCESS);
    const RTresult r = rtContextLaunch2D(ctx_, 0, kW, kH);
    EXPECT_EQ(r, RT_SUCCESS) << Error(r);
    std::vector<float> all;
    for (RTbuffer b : outputs_) {
      for (const Float4& f : Read(b)) all.insert(all.end(), f.begin(), f.end());
    }
    return all;
  }
  // Renders `top` flattened and not, expects the same bits, and returns the flattened outputs.
  std::vector<float> Same(RTobject top) {
    const std::vector<float> nested = Render(top, false);
    const std::vector<float> flat = Render(top, true);
    EXPECT_EQ(nested.size(), flat.size());
    for (size_t i = 0; i < nested.size() && i < flat.size(); ++i) {
      if (std::memcmp(&nested[i], &flat[i], sizeof(float)) != 0) {
        ADD_FAILURE() << "output " << i / (kW * kH * 4) << ", launch index " << (i / 4) % (kW * kH)
                      << ", component " << i % 4 << ": " << nested[i] << " per level, " << flat[i]
                      << " flattened";
        break;
      }
    }
    return flat;
  }
  // out_hit of launch index (x, y) in `all`.
  static Float4 HitAt(const std::vector<float>& all, size_t x, size_t y) {
    const float* p = &all[(y * kW + x) * 4];
    return {p[0], p[1], p[2], p[3]};
  }
  static Float4 PointAt(const std::vector<float>& all, size_t x, size_t y) {
    const float* p = &all[(kW * kH + y * kW + x) * 4];
    return {p[0], p[1], p[2], p[3]};
  }
  // Launch index x of the ray through world x (rays start at -7.75, 0.5 apart: x is a quarter).
  static size_t Column(float x) { return static_cast<size_t>((x + 7.75f) / 0.5f); }

  std::vector<RTbuffer> outputs_;
  std::vector<RTacceleration> group_accels_;
  RTprogram closest_hit_ = nullptr, count_any_hit_ = nullptr;
};

// Group -> Transform -> Group -> Transform -> Group -> Transform -> GeometryGroup, with siblings
// at every level: a sphere and a square, scaled, turned and moved.
TEST_P(FlattenedGraphTest, NestedGroupsWithSeveralChildren) {
  RTgeometrygroup ball = Sphere(0.f, 0.f, 0.75f, 1.f);
  RTgeometrygroup square = Square(0.f, 0.f, 2.f);
  // A quarter turn about z, doubled, moved to x = 4.
  RTtransform turned = Transform(ball, {0, -2, 0, 4, 2, 0, 0, 0, 0, 0, 2, 1, 0, 0, 0, 1});
  RTgroup inner = Group({turned, Move(square, -2.f, 0.f, 3.f)});
  RTgroup middle = Group({Move(inner, 0.5f, 0.f, 0.f), Move(ball, -5.f, 0.f, 0.f), square});
  RTgroup top =
      Group({Move(middle, 0.f, 0.5f, -1.f), Move(Move(ball, 2.f, 0.f, 0.f), 0.f, -1.f, 0.f)});
  const std::vector<float> out = Same(top);
  // The doubled sphere sits at x = 4.5, y = 0.5: its closest hit sees the whole chain.
  const Float4 hit = HitAt(out, Column(4.25f), 4);
  EXPECT_EQ(hit[1], 1.f);
  const Float4 origin = PointAt(out, Column(4.25f), 4);
  EXPECT_EQ(origin[0], 4.5f);
  EXPECT_EQ(origin[1], 0.5f);
  EXPECT_EQ(origin[2], 0.f);  // moved +1 inside, -1 above
  EXPECT_EQ(origin[3], 0.f);  // m[0] of a quarter turn
  size_t hits = 0, candidates = 0;
  for (size_t i = 0; i < kW * kH; ++i) {
    hits += out[i * 4 + 1] >= 0.f;
    candidates += static_cast<size_t>(out[i * 4 + 3]);
  }
  EXPECT_GT(hits, 20u);
  EXPECT_GT(candidates, hits);  // spheres give two candidates a ray
}

// One GeometryGroup reached through several paths at several depths, and a subgraph shared by
// two parents.
TEST_P(FlattenedGraphTest, SharedSubgraphs) {
  RTgeometrygroup ball = Sphere(0.f, 0.f, 0.5f, 3.f);
  RTgroup pair = Group({Move(ball, -1.f, 0.f, 0.f), Move(ball, 1.f, 0.f, 0.f)});
  RTgroup top = Group({Move(pair, -4.f, 0.f, 0.f), Move(pair, 4.f, 0.f, 2.f), ball,
                       Group({Move(Group({pair}), 0.f, 1.f, 0.f)})});
  const std::vector<float> out = Same(top);
  EXPECT_EQ(HitAt(out, Column(-5.25f), 3)[1], 3.f);
  EXPECT_EQ(PointAt(out, Column(-5.25f), 3)[0], -5.f);
  EXPECT_EQ(PointAt(out, Column(5.25f), 3)[2], 2.f);
  EXPECT_EQ(PointAt(out, Column(1.25f), 5)[1], 1.f);
}

// rtTransformSetMatrix between launches moves what is below, flattened or not.
TEST_P(FlattenedGraphTest, TransformsChangedBetweenLaunches) {
  RTgeometrygroup square = Square(0.f, 0.f, 4.f);
  RTtransform inner = Move(square, -4.f, 0.f, 0.f);
  RTgroup top = Group({Move(Group({inner}), 0.f, 0.f, 1.f)});
  const std::vector<float> before = Same(top);
  EXPECT_EQ(HitAt(before, Column(-4.25f), 4)[1], 4.f);
  EXPECT_EQ(HitAt(before, Column(4.25f), 4)[1], -1.f);
  const float moved[16] = {1, 0, 0, 4, 0, 1, 0, 0, 0, 0, 1, 2, 0, 0, 0, 1};
  Ok(rtTransformSetMatrix(inner, 0, moved, nullptr));
  const std::vector<float> after = Same(top);
  EXPECT_EQ(HitAt(after, Column(-4.25f), 4)[1], -1.f);
  EXPECT_EQ(HitAt(after, Column(4.25f), 4)[1], 4.f);
  EXPECT_EQ(PointAt(after, Column(4.25f), 4)[2], 3.f);
  EXPECT_EQ(HitAt(after, Column(4.25f), 4)[0], 23.f);  // from z = -20 to z = 3
}

// A Transform above a flattened Group composes with the instances' transforms; a Selector in a
// chain keeps that chain on the per-level path while its siblings are flattened.
TEST_P(FlattenedGraphTest, TransformAboveAndSelectorInTheChain) {
  RTgeometrygroup ball = Sphere(0.f, 0.f, 0.75f, 5.f);
  RTgeometrygroup square = Square(0.f, 0.f, 6.f);
  RTselector selector = nullptr;
  Ok(rtSelectorCreate(ctx_, &selector));
  Ok(rtSelectorSetVisitProgram(selector, Program(kModule, "visit_first")));
  Ok(rtSelectorSetChildCount(selector, 1));
  Ok(rtSelectorSetChild(selector, 0, Move(ball, 0.f, 0.f, 1.f)));
  RTgroup group = Group({Move(selector, -3.f, 0.f, 0.f), Move(square, 3.f, 0.f, 0.f),
                         Move(Group({ball}), 0.f, 1.f, 0.f)});
  RTtransform top = Transform(group, {2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 1});
  const std::vector<float> out = Same(top);
  EXPECT_EQ(HitAt(out, Column(-6.25f), 4)[1], 5.f);  // through the selector
  EXPECT_EQ(PointAt(out, Column(-6.25f), 4)[2], 2.f);
  EXPECT_EQ(HitAt(out, Column(6.25f), 4)[1], 6.f);
  EXPECT_EQ(PointAt(out, Column(6.25f), 4)[3], 2.f);  // the scale above
  EXPECT_EQ(HitAt(out, Column(0.25f), 7)[1], 5.f);
  EXPECT_EQ(PointAt(out, Column(0.25f), 7)[1], 2.f);
}

// Transforms that come to the identity (one identity matrix; a move and its inverse on two levels)
// are dropped when the Group is flattened: programs see what the same leaves give without any
// Transform, and what the per-level path gives through them.
TEST_P(FlattenedGraphTest, IdentityTransformsChangeNothing) {
  const std::vector<float> kIdentity = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  RTgeometrygroup ball = Sphere(-3.f, 0.f, 0.75f, 9.f);
  RTgeometrygroup square = Square(3.f, 0.f, 10.f);
  const std::vector<float> plain = Render(Group({ball, square}), true);
  RTgroup moved_back = Group({Move(Group({Move(square, 2.f, 0.f, 0.f)}), -2.f, 0.f, 0.f)});
  const std::vector<float> through = Same(Group({Transform(ball, kIdentity), moved_back}));
  ASSERT_EQ(plain.size(), through.size());
  EXPECT_EQ(std::memcmp(plain.data(), through.data(), plain.size() * sizeof(float)), 0);
  EXPECT_EQ(HitAt(through, Column(-3.25f), 4)[1], 9.f);
  EXPECT_EQ(HitAt(through, Column(3.25f), 4)[1], 10.f);
  EXPECT_EQ(PointAt(through, Column(3.25f), 4)[3], 1.f);  // the object-to-world m[0]
}

// Native triangles whose intersection program rejects what Embree found: the ray is traced again
// with a context filter, which reaches the triangles inside the instances, in their space.
TEST_P(FlattenedGraphTest, IntersectionProgramsRejectingNativeTriangles) {
  RTgeometrygroup cut = Square(0.f, 0.f, 7.f, "cutout_intersect");
  RTgeometrygroup behind = Square(0.f, 0.f, 8.f);
  RTgroup top = Group(
      {Move(Group({Move(cut, 0.5f, 0.f, 0.f)}), 2.f, 0.f, 0.f), Move(behind, 2.5f, 0.f, 1.f)});
  const std::vector<float> out = Same(top);
  EXPECT_EQ(HitAt(out, Column(1.75f), 4)[1], 8.f);  // object x = -0.75: cut out
  EXPECT_EQ(HitAt(out, Column(3.25f), 4)[1], 7.f);
  EXPECT_EQ(PointAt(out, Column(3.25f), 4)[0], 2.5f);
  // Any-hit programs meet only what the intersection program reports.
  EXPECT_EQ(HitAt(out, Column(1.75f), 4)[3], 1.f);
  EXPECT_EQ(HitAt(out, Column(3.25f), 4)[3], 2.f);
}

INSTANTIATE_TEST_SUITE_P(Devices, FlattenedGraphTest, ::testing::Values("inproc", "local:2"),
                         [](const ::testing::TestParamInfo<const char*>& info) {
                           std::string name = info.param;
                           for (char& c : name) {
                             if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                           }
                           return name;
                         });

// Built-in triangles below flattened transforms: Embree's hit gives the face from its geometric
// normal in the instance's space, which must be judged against the ray in that space. A half turn
// about x turns the square's back to the rays.
class FlattenedTrianglesTest : public TrianglesFixture {
 protected:
  RTtransform Transform(RTobject child, const std::vector<float>& m) {
    RTtransform t = nullptr;
    EXPECT_EQ(rtTransformCreate(ctx_, &t), RT_SUCCESS);
    EXPECT_EQ(rtTransformSetMatrix(t, 0, m.data(), nullptr), RT_SUCCESS);
    EXPECT_EQ(rtTransformSetChild(t, child), RT_SUCCESS);
    return t;
  }
  RTgroup Top(const std::vector<RTobject>& children) {
    RTacceleration a = Accel();
    accels_.push_back(a);
    RTgroup g = nullptr;
    EXPECT_EQ(rtGroupCreate(ctx_, &g), RT_SUCCESS);
    EXPECT_EQ(rtGroupSetAcceleration(g, a), RT_SUCCESS);
    EXPECT_EQ(rtGroupSetChildCount(g, static_cast<unsigned>(children.size())), RT_SUCCESS);
    for (unsigned i = 0; i < children.size(); ++i) {
      EXPECT_EQ(rtGroupSetChild(g, i, children[i]), RT_SUCCESS);
    }
    return g;
  }
  std::vector<Float4> Render(RTobject top, bool flatten) {
    for (RTacceleration a : accels_) {
      EXPECT_EQ(rtAccelerationSetProperty(a, "flatten", flatten ? "1" : "0"), RT_SUCCESS);
      EXPECT_EQ(rtAccelerationMarkDirty(a), RT_SUCCESS);
    }
    EXPECT_EQ(rtVariableSetObject(ContextVar("top_object"), top), RT_SUCCESS);
    return Launch();
  }
  std::vector<RTacceleration> accels_;
};

TEST_P(FlattenedTrianglesTest, FacesAndBarycentricsBelowTransforms) {
  Scene({Material("closest_barycentrics")});
  // y -> 1.05 - y, z -> -z: the square seen from behind, the rays off its diagonal.
  const std::vector<float> flip = {1, 0, 0, 0, 0, -1, 0, 1.05f, 0, 0, -1, 0, 0, 0, 0, 1};
  const std::vector<float> away = {1, 0, 0, 5, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  // One instance (traced without Embree's instance level), and several (with it).
  for (RTgroup top : {Top({Transform(group_, flip)}),
                      Top({Transform(Top({group_}), flip), Transform(group_, away)})}) {
    const std::vector<Float4> nested = Render(top, false);
    const std::vector<Float4> flat = Render(top, true);
    ASSERT_EQ(nested.size(), flat.size());
    EXPECT_EQ(std::memcmp(nested.data(), flat.data(), nested.size() * sizeof(Float4)), 0);
    size_t seen[2] = {0, 0};
    for (size_t i = 0; i < flat.size(); ++i) {
      // Triangle 0 faces the rays unturned (TrianglesFixture), so turned it shows its back.
      ASSERT_TRUE(flat[i][0] == 0.f || flat[i][0] == 1.f) << "launch index " << i;
      ++seen[static_cast<size_t>(flat[i][0])];
      EXPECT_EQ(flat[i][1], flat[i][0] == 0.f ? 2.f : 1.f) << "launch index " << i;
    }
    EXPECT_GT(seen[0], 0u);
    EXPECT_GT(seen[1], 0u);
  }
}

INSTANTIATE_TEST_SUITE_P(Devices, FlattenedTrianglesTest, ::testing::Values("inproc", "local:2"),
                         [](const ::testing::TestParamInfo<const char*>& info) {
                           std::string name = info.param;
                           for (char& c : name) {
                             if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                           }
                           return name;
                         });

}  // namespace
}  // namespace tessera::testing

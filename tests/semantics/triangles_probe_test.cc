// Built-in triangles (OptiX 6 GeometryTriangles) misused: buffers changed or destroyed after they
// are set, counts that do not fit, material indices out of range, forbidden calls in attribute
// programs; and combined with transforms, groups, nested traces and any-hit programs. Each bad
// input fails with an error naming the object, never a crash or a silently wrong image.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "triangles_fixture.h"

namespace tessera::testing {
namespace {

class TrianglesProbeTest : public TrianglesFixture {
 protected:
  // A second square below the first (z = -1), as two more triangles of the same mesh.
  void AddSquareBelow() {
    const float vertices[] = {0, 0, 0,  1, 0, 0,  0, 1, 0,  1, 1, 0,
                              0, 0, -1, 1, 0, -1, 0, 1, -1, 1, 1, -1};
    const unsigned indices[] = {0, 1, 2, 1, 2, 3, 4, 5, 6, 5, 6, 7};
    RTbuffer v = InputBuffer(RT_FORMAT_FLOAT3, 8, vertices, sizeof(vertices));
    RTbuffer i = InputBuffer(RT_FORMAT_UNSIGNED_INT3, 4, indices, sizeof(indices));
    Ok(rtGeometryTrianglesSetPrimitiveCount(triangles_, 4));
    Ok(rtGeometryTrianglesSetVertices(triangles_, 8, v, 0, 0, RT_FORMAT_FLOAT3));
    Ok(rtGeometryTrianglesSetTriangleIndices(triangles_, i, 0, 0, RT_FORMAT_UNSIGNED_INT3));
  }
};

TEST_P(TrianglesProbeTest, DestroyedVertexBufferFailsByName) {
  Scene({Material("closest_tag")});
  Launch();
  Ok(rtBufferDestroy(vertices_));
  LaunchFails({"vertex buffer", "destroyed"});
}

TEST_P(TrianglesProbeTest, ShrunkVertexBufferFails) {
  Scene({Material("closest_tag")});
  Launch();
  Ok(rtBufferSetSize1D(vertices_, 2));
  LaunchFails({"geometry triangles", "do not fit"});
}

TEST_P(TrianglesProbeTest, ReformattedIndexBufferFails) {
  Scene({Material("closest_tag")});
  Launch();
  Ok(rtBufferSetFormat(indices_, RT_FORMAT_UNSIGNED_BYTE));
  LaunchFails({"geometry triangles", "do not fit"});
}

TEST_P(TrianglesProbeTest, ZeroTrianglesAndVerticesMiss) {
  Ok(rtGeometryTrianglesSetPrimitiveCount(triangles_, 0));
  Ok(rtGeometryTrianglesSetVertices(triangles_, 0, vertices_, 0, 0, RT_FORMAT_FLOAT3));
  Scene({Material("closest_tag")});
  for (const Float4& v : Launch()) EXPECT_EQ(v[0], -1.f);
}

TEST_P(TrianglesProbeTest, ZeroSizedBuffersMiss) {
  RTbuffer empty = nullptr;
  Ok(rtBufferCreate(ctx_, RT_BUFFER_INPUT, &empty));
  Ok(rtBufferSetFormat(empty, RT_FORMAT_FLOAT3));
  Ok(rtBufferSetSize1D(empty, 0));
  Ok(rtGeometryTrianglesSetPrimitiveCount(triangles_, 0));
  Ok(rtGeometryTrianglesSetVertices(triangles_, 0, empty, 0, 0, RT_FORMAT_FLOAT3));
  Ok(rtGeometryTrianglesSetTriangleIndices(triangles_, empty, 0, 0, RT_FORMAT_UNSIGNED_INT3));
  Scene({Material("closest_tag")});
  for (const Float4& v : Launch()) EXPECT_EQ(v[0], -1.f);
}

TEST_P(TrianglesProbeTest, HugeOffsetsAndStridesFail) {
  Scene({Material("closest_tag")});
  const RTsize big = ~RTsize{0} - 4;
  Ok(rtGeometryTrianglesSetVertices(triangles_, 4, vertices_, big, 12, RT_FORMAT_FLOAT3));
  LaunchFails({"geometry triangles", "do not fit"});
  Ok(rtGeometryTrianglesSetVertices(triangles_, 4, vertices_, 0, big, RT_FORMAT_FLOAT3));
  LaunchFails({"geometry triangles", "do not fit"});
  Ok(rtGeometryTrianglesSetVertices(triangles_, 4, vertices_, 12, RTsize{1} << 62,
                                    RT_FORMAT_FLOAT3));
  LaunchFails({"geometry triangles", "do not fit"});
  Ok(rtGeometryTrianglesSetVertices(triangles_, 4, vertices_, 0, 12, RT_FORMAT_FLOAT3));
  Ok(rtGeometryTrianglesSetTriangleIndices(triangles_, indices_, big, 12, RT_FORMAT_UNSIGNED_INT3));
  LaunchFails({"geometry triangles", "do not fit"});
  Ok(rtGeometryTrianglesSetTriangleIndices(triangles_, indices_, 0, big, RT_FORMAT_UNSIGNED_INT3));
  LaunchFails({"geometry triangles", "do not fit"});
  Ok(rtGeometryTrianglesSetVertices(triangles_, 0xFFFFFFFFu, vertices_, 0, 12, RT_FORMAT_FLOAT3));
  LaunchFails({"geometry triangles", "do not fit"});
}

TEST_P(TrianglesProbeTest, IndexPastTheVerticesFails) {
  const unsigned indices[] = {0, 1, 2, 1, 2, 4};
  Fill(indices_, indices, sizeof(indices));
  Scene({Material("closest_tag")});
  LaunchFails({"geometry triangles", "vertex 4"});
}

TEST_P(TrianglesProbeTest, MaterialIndexOutOfRangeFails) {
  Ok(rtGeometryTrianglesSetMaterialCount(triangles_, 2));
  const unsigned short material_of[] = {1, 2};
  RTbuffer m = InputBuffer(RT_FORMAT_UNSIGNED_SHORT, 2, material_of, sizeof(material_of));
  Ok(rtGeometryTrianglesSetMaterialIndices(triangles_, m, 0, 0, RT_FORMAT_UNSIGNED_SHORT));
  Scene({Material("closest_tag", 1), Material("closest_tag", 2)});
  LaunchFails({"geometry triangles", "material index 2"});
}

TEST_P(TrianglesProbeTest, MaterialIndicesWrittenOnTheHostCountAtTheNextLaunch) {
  Ok(rtGeometryTrianglesSetMaterialCount(triangles_, 2));
  const unsigned char material_of[] = {0, 1};
  RTbuffer m = InputBuffer(RT_FORMAT_UNSIGNED_BYTE, 2, material_of, sizeof(material_of));
  Ok(rtGeometryTrianglesSetMaterialIndices(triangles_, m, 0, 0, RT_FORMAT_UNSIGNED_BYTE));
  Scene({Material("closest_tag", 10), Material("closest_tag", 20)});
  std::vector<Float4> out = Launch();
  for (unsigned i = 0; i < out.size(); ++i) {
    EXPECT_EQ(out[i][2], OnFirst(i % kSize, i / kSize) ? 10.f : 20.f) << i;
  }
  const unsigned char swapped[] = {1, 0};
  Fill(m, swapped, sizeof(swapped));
  out = Launch();
  for (unsigned i = 0; i < out.size(); ++i) {
    EXPECT_EQ(out[i][2], OnFirst(i % kSize, i / kSize) ? 20.f : 10.f) << i;
  }
  const unsigned char bad[] = {1, 9};
  Fill(m, bad, sizeof(bad));
  LaunchFails({"material index 9"});
}

// A program writes material index 5 into the material index buffer in one launch; the next
// launch must not shade with a material the instance lacks, silently.
TEST_P(TrianglesProbeTest, MaterialIndicesWrittenByAProgramAreChecked) {
  Ok(rtContextSetEntryPointCount(ctx_, 2));
  Ok(rtContextSetRayGenerationProgram(ctx_, 1, Prog("write_material_indices")));
  Ok(rtGeometryTrianglesSetMaterialCount(triangles_, 2));
  const unsigned char material_of[] = {0, 1};
  RTbuffer m = InputBuffer(RT_FORMAT_UNSIGNED_BYTE, 2, material_of, sizeof(material_of),
                           RT_BUFFER_INPUT_OUTPUT);
  Ok(rtVariableSetObject(ContextVar("material_of"), m));
  Ok(rtGeometryTrianglesSetMaterialIndices(triangles_, m, 0, 0, RT_FORMAT_UNSIGNED_BYTE));
  Scene({Material("closest_tag", 10), Material("closest_tag", 20)});
  Launch();
  Ok(rtContextLaunch1D(ctx_, 1, 2));
  LaunchFails({"material index 5"});
}

// Vertices a launch computes into an OUTPUT buffer (an animated mesh): each device builds its
// triangles from the merged vertices, not from the ones its own tiles wrote.
TEST_P(TrianglesProbeTest, VerticesAnimatedByALaunchIntoAnOutputBuffer) {
  Ok(rtContextSetEntryPointCount(ctx_, 2));
  Ok(rtContextSetRayGenerationProgram(ctx_, 1, Prog("animate_vertices")));
  const RTsize one = 1;
  Ok(tesseraContextSetTileSize(ctx_, 1, &one));  // vertices written by different devices
  RTbuffer animated = nullptr;
  Ok(rtBufferCreate(ctx_, RT_BUFFER_OUTPUT, &animated));
  Ok(rtBufferSetFormat(animated, RT_FORMAT_FLOAT3));
  Ok(rtBufferSetSize1D(animated, 4));
  Ok(rtVariableSetObject(ContextVar("animated"), animated));
  Ok(rtGeometryTrianglesSetVertices(triangles_, 4, animated, 0, 12, RT_FORMAT_FLOAT3));
  Scene({Material("closest_barycentrics")});
  RTacceleration accel = nullptr;
  Ok(rtGeometryGroupGetAcceleration(group_, &accel));
  for (float shift : {0.f, 0.5f, 0.25f}) {
    SCOPED_TRACE(shift);
    Ok(rtVariableSet1f(ContextVar("shift"), shift));
    Ok(rtContextLaunch1D(ctx_, 1, 4));
    Ok(rtAccelerationMarkDirty(accel));
    std::vector<Float4> out = Launch();
    for (unsigned i = 0; i < out.size(); ++i) {
      const float x = Coord(i % kSize) - shift, y = Coord(i / kSize);
      const float expected = x < 0.f ? -1.f : (x + y < 1.f ? 0.f : 1.f);  // miss, or primitive
      EXPECT_EQ(out[i][0], expected) << "ray " << i;
    }
  }
}

// Embree leaves a triangle with a vertex beyond +-1.844e18 out of its build: never hit, without a
// word. The launch fails naming the vertex instead.
TEST_P(TrianglesProbeTest, VertexBeyondEmbreesRangeFails) {
  const float vertices[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1e19f, 1, 0};
  Fill(vertices_, vertices, sizeof(vertices));
  Scene({Material("closest_barycentrics")});
  LaunchFails({"geometry triangles", "vertex 3", "beyond"});
}

TEST_P(TrianglesProbeTest, MaterialCountMismatchFails) {
  Ok(rtGeometryTrianglesSetMaterialCount(triangles_, 2));
  const unsigned material_of[] = {0, 1};
  RTbuffer m = InputBuffer(RT_FORMAT_UNSIGNED_INT, 2, material_of, sizeof(material_of));
  Ok(rtGeometryTrianglesSetMaterialIndices(triangles_, m, 0, 0, RT_FORMAT_UNSIGNED_INT));
  Scene({Material("closest_tag", 1), Material("closest_tag", 2), Material("closest_tag", 3)});
  LaunchFails({"material count is 3", "2 materials"});
}

TEST_P(TrianglesProbeTest, SwitchingGeometryKindsBetweenLaunches) {
  Scene({Material("closest_tag", 3)});
  std::vector<Float4> out = Launch();
  EXPECT_EQ(out[0][2], 3.f);
  // The same instance now holds a geometry with programs that finds nothing.
  RTgeometry g = nullptr;
  Ok(rtGeometryCreate(ctx_, &g));
  Ok(rtGeometrySetPrimitiveCount(g, 0));
  Ok(rtGeometrySetIntersectionProgram(g, Prog("attribute_potential")));
  Ok(rtGeometrySetBoundingBoxProgram(g, Prog("attribute_like_bounds")));
  Ok(rtGeometryInstanceSetGeometry(instance_, g));
  for (const Float4& v : Launch()) EXPECT_EQ(v[0], -1.f);
  Ok(rtGeometryInstanceSetGeometryTriangles(instance_, triangles_));
  out = Launch();
  EXPECT_EQ(out[0][2], 3.f);
}

TEST_P(TrianglesProbeTest, UnderTransformAndGroup) {
  Scene({Material("closest_barycentrics")});
  const std::vector<Float4> plain = Launch();
  // Translate the square by 0 in x, y and -2 in z, under a Transform under a Group.
  RTtransform t = nullptr;
  Ok(rtTransformCreate(ctx_, &t));
  const float m[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, -2, 0, 0, 0, 1};
  Ok(rtTransformSetMatrix(t, 0, m, nullptr));
  Ok(rtTransformSetChild(t, group_));
  RTgroup g = nullptr;
  Ok(rtGroupCreate(ctx_, &g));
  Ok(rtGroupSetAcceleration(g, Accel("Bvh")));
  Ok(rtGroupSetChildCount(g, 1));
  Ok(rtGroupSetChild(g, 0, t));
  Ok(rtVariableSetObject(ContextVar("top_object"), g));
  const std::vector<Float4> moved = Launch();
  for (unsigned i = 0; i < plain.size(); ++i) {
    for (int k = 0; k < 4; ++k) EXPECT_NEAR(moved[i][k], plain[i][k], 1e-5) << i;
  }
}

TEST_P(TrianglesProbeTest, NestedTraceKeepsTheOuterHit) {
  AddSquareBelow();
  Scene({Material("closest_nested")});
  std::vector<Float4> out = Launch();
  for (unsigned y = 0; y < kSize; ++y) {
    for (unsigned x = 0; x < kSize; ++x) {
      const Float4& o = out[y * kSize + x];
      const bool first = OnFirst(x, y);
      // Outer hit on triangle 0 or 1; the inner ray hits 2 or 3 whose own nested trace misses.
      const float inner = first ? 2.f * 10.f + 0.f : 3.f * 10.f + 0.f;
      EXPECT_EQ(o[0], (first ? 0.f : 10.f) + inner + 1.f) << x << "," << y;
      EXPECT_EQ(o[1], first ? 1.f : 2.f);
    }
  }
}

// Shadow rays (terminate on first hit, no closest hit) through built-in triangles: Embree's
// occlusion query answers them unless an any-hit program of their ray type must see the
// candidates. Blocked or open, whichever the flags, ray type and any-hit program make it, and the
// caller's hit intact after.
TEST_P(TrianglesProbeTest, ShadowRaysAskOnlyWhetherSomethingIsInTheWay) {
  AddSquareBelow();
  Ok(rtContextSetRayTypeCount(ctx_, 2));
  Ok(rtContextSetMissProgram(ctx_, 1, Prog("miss")));
  RTmaterial m = Material("closest_shadow");
  Ok(rtMaterialSetAnyHitProgram(m, 1, Prog("any_hit_ignore_all")));  // ray type 1 sees nothing
  Scene({m});
  constexpr unsigned kDisableAnyHit = 1u << 0, kTerminate = 1u << 2, kDisableClosest = 1u << 3;
  constexpr unsigned kShadow = kTerminate | kDisableClosest;
  struct Case {
    float dz;
    unsigned type, flags;
    float blocked;
  };
  const Case cases[] = {
      {-1.f, 0, kShadow, 1.f},                   // the square below is in the way
      {1.f, 0, kShadow, 0.f},                    // nothing above
      {-1.f, 1, kShadow, 0.f},                   // ray type 1's any-hit ignores every candidate
      {-1.f, 1, kShadow | kDisableAnyHit, 1.f},  // unless disabled
      {-1.f, 0, kDisableClosest, 1.f},           // the closest hit found in full, not shaded
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(::testing::Message()
                 << "dz " << c.dz << ", type " << c.type << ", flags " << c.flags);
    Ok(rtVariableSet1f(ContextVar("shadow_dz"), c.dz));
    Ok(rtVariableSet1ui(ContextVar("shadow_type"), c.type));
    Ok(rtVariableSet1ui(ContextVar("shadow_flags"), c.flags));
    const std::vector<Float4> out = Launch();
    for (unsigned y = 0; y < kSize; ++y) {
      for (unsigned x = 0; x < kSize; ++x) {
        const Float4& o = out[y * kSize + x];
        EXPECT_EQ(o[0], c.blocked) << x << "," << y;
        EXPECT_EQ(o[1], OnFirst(x, y) ? 0.f : 1.f) << x << "," << y;
      }
    }
  }
}

TEST_P(TrianglesProbeTest, AnyHitTerminateAndIgnore) {
  RTmaterial m = Material("closest_tag", 4);
  Ok(rtMaterialSetAnyHitProgram(m, 0, Prog("any_hit_terminate")));
  Scene({m});
  std::vector<Float4> out = Launch();
  for (const Float4& v : out) EXPECT_EQ(v[2], 4.f);
  Ok(rtMaterialSetAnyHitProgram(m, 0, Prog("any_hit_ignore_all")));
  for (const Float4& v : Launch()) EXPECT_EQ(v[0], -1.f);
}

TEST_P(TrianglesProbeTest, AttributeProgramThatTracesFails) {
  Ok(rtGeometryTrianglesSetAttributeProgram(triangles_, Prog("attribute_traces")));
  Scene({Material("closest_info_raw")});
  LaunchFails({"rtTrace", "attribute program"});
}

TEST_P(TrianglesProbeTest, AttributeProgramWithPotentialIntersectionFails) {
  Ok(rtGeometryTrianglesSetAttributeProgram(triangles_, Prog("attribute_potential")));
  Scene({Material("closest_info_raw")});
  LaunchFails({"rtPotentialIntersection", "attribute program"});
}

TEST_P(TrianglesProbeTest, AttributeProgramThatIgnoresFails) {
  Ok(rtGeometryTrianglesSetAttributeProgram(triangles_, Prog("attribute_ignores")));
  Scene({Material("closest_info_raw")});
  LaunchFails({"rtIgnoreIntersection", "attribute program"});
}

TEST_P(TrianglesProbeTest, AttributeProgramThatTerminatesFails) {
  Ok(rtGeometryTrianglesSetAttributeProgram(triangles_, Prog("attribute_terminates")));
  Scene({Material("closest_info_raw")});
  LaunchFails({"rtTerminateRay", "attribute program"});
}

TEST_P(TrianglesProbeTest, AttributeProgramWithBoundsArgumentsFails) {
  Ok(rtGeometryTrianglesSetAttributeProgram(triangles_, Prog("attribute_like_bounds")));
  Scene({Material("closest_info_raw")});
  LaunchFails({"attribute_like_bounds", "bounding box"});
}

TEST_P(TrianglesProbeTest, AttributeProgramUnderAnyHit) {
  Ok(rtGeometryTrianglesSetAttributeProgram(triangles_, Prog("attribute_info")));
  RTmaterial m = Material("closest_info_raw");
  Ok(rtMaterialSetAnyHitProgram(m, 0, Prog("any_hit_terminate")));
  Scene({m});
  std::vector<Float4> out = Launch();
  for (unsigned i = 0; i < out.size(); ++i) {
    EXPECT_EQ(out[i][0], OnFirst(i % kSize, i / kSize) ? 0.f : 1.f);
    EXPECT_EQ(out[i][3], 7.f);
  }
}

// An attribute program and a closest-hit program of one module: the closest-hit program reads
// the attributes where the attribute program left them (the engine copies nothing between
// them), so what that program leaves unwritten must still read zeros.
TEST_P(TrianglesProbeTest, AttributesLeftUnwrittenReadZerosInTheSameModule) {
  Ok(rtGeometryTrianglesSetAttributeProgram(triangles_, Prog("attribute_first_only")));
  Scene({Material("closest_info_raw")});
  std::vector<Float4> out = Launch();
  for (unsigned i = 0; i < out.size(); ++i) {
    const bool first = OnFirst(i % kSize, i / kSize);
    SCOPED_TRACE(::testing::Message() << "launch index " << i % kSize << "," << i / kSize);
    EXPECT_EQ(out[i][0], first ? 1.f : 0.f);
    EXPECT_EQ(out[i][1], first ? 2.f : 0.f);
    EXPECT_EQ(out[i][2], first ? 3.f : 0.f);
    EXPECT_EQ(out[i][3], first ? 4.f : 0.f);
  }
}

// The same module's attribute program runs again for a nested trace's hit (triangles 2 and 3,
// where it writes nothing), in the variables the outer closest-hit program reads its attributes
// from: the inner hit reads zeros, not the outer hit's attributes, and the outer program gets its
// own back after the trace.
TEST_P(TrianglesProbeTest, NestedTraceKeepsTheOuterAttributes) {
  AddSquareBelow();
  Ok(rtGeometryTrianglesSetAttributeProgram(triangles_, Prog("attribute_first_only")));
  Scene({Material("closest_info_nested")});
  std::vector<Float4> out = Launch();
  for (unsigned i = 0; i < out.size(); ++i) {
    const bool first = OnFirst(i % kSize, i / kSize);
    SCOPED_TRACE(::testing::Message() << "launch index " << i % kSize << "," << i / kSize);
    EXPECT_EQ(out[i][0], first ? 1.f : 0.f) << "outer attributes, after the nested trace";
    EXPECT_EQ(out[i][1], first ? 4.f : 0.f) << "outer attributes, after the nested trace";
    EXPECT_EQ(out[i][2], 0.f) << "the inner hit's attributes: zeros";
    EXPECT_EQ(out[i][3], -1.f) << "the inner hit's nested trace is not made";
  }
}

TEST_P(TrianglesProbeTest, PrimitiveIndexInRayGenerationFails) {
  Ok(rtContextSetRayGenerationProgram(ctx_, 0, Prog("raygen_primitive_index")));
  Scene({Material("closest_tag")});
  LaunchFails({"rtGetPrimitiveIndex", "ray generation"});
}

TEST_P(TrianglesProbeTest, TriangleHitInMissFails) {
  Ok(rtContextSetMissProgram(ctx_, 0, Prog("miss_triangle_hit")));
  Ok(rtGeometryTrianglesSetPrimitiveCount(triangles_, 0));
  Scene({Material("closest_tag")});
  LaunchFails({"rtIsTriangleHit", "miss"});
}

TEST_P(TrianglesProbeTest, NonFiniteVerticesAreNeverHit) {
  const float inf = INFINITY, nan = NAN;
  const float vertices[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, inf, nan, 1e30f};
  Fill(vertices_, vertices, sizeof(vertices));
  Scene({Material("closest_tag")});
  std::vector<Float4> out = Launch();
  for (unsigned i = 0; i < out.size(); ++i) {
    EXPECT_EQ(out[i][0], OnFirst(i % kSize, i / kSize) ? 0.f : -1.f) << i;
  }
}

TEST_P(TrianglesProbeTest, ShortIndicesFloat2VerticesStrides) {
  // Vertices as float2 every 20 bytes from byte 4; indices as ushort3 every 8 bytes from byte 2.
  std::vector<float> v(1 + 5 * 4, 99.f);
  const float xy[4][2] = {{0, 0}, {1, 0}, {0, 1}, {1, 1}};
  for (int i = 0; i < 4; ++i) {
    v[1 + 5 * i] = xy[i][0];
    v[2 + 5 * i] = xy[i][1];
  }
  RTbuffer vb = InputBuffer(RT_FORMAT_FLOAT, v.size(), v.data(), v.size() * 4);
  const uint16_t idx[] = {0xFFFF, 0, 1, 2, 0xFFFF, 1, 2, 3, 0xFFFF};
  RTbuffer ib = InputBuffer(RT_FORMAT_UNSIGNED_SHORT, 9, idx, sizeof(idx));
  Ok(rtGeometryTrianglesSetVertices(triangles_, 4, vb, 4, 20, RT_FORMAT_FLOAT2));
  Ok(rtGeometryTrianglesSetTriangleIndices(triangles_, ib, 2, 8, RT_FORMAT_UNSIGNED_SHORT3));
  Scene({Material("closest_barycentrics")});
  std::vector<Float4> out = Launch();
  for (unsigned i = 0; i < out.size(); ++i) {
    EXPECT_EQ(out[i][0], OnFirst(i % kSize, i / kSize) ? 0.f : 1.f) << i;
  }
}

// An instance no longer in the graph keeps its last state on the devices; it must not fail
// launches of the graph it left.
TEST_P(TrianglesProbeTest, DetachedInstanceDoesNotFailLaunches) {
  Ok(rtGeometryTrianglesSetMaterialCount(triangles_, 2));
  const unsigned char material_of[] = {0, 1};
  RTbuffer m = InputBuffer(RT_FORMAT_UNSIGNED_BYTE, 2, material_of, sizeof(material_of));
  Ok(rtGeometryTrianglesSetMaterialIndices(triangles_, m, 0, 0, RT_FORMAT_UNSIGNED_BYTE));
  Scene({Material("closest_tag", 10), Material("closest_tag", 20)});
  Launch();
  // A new mesh of one material replaces the instance; the old buffer is reused as its
  // material index buffer with other contents.
  RTgeometrytriangles other = nullptr;
  Ok(rtGeometryTrianglesCreate(ctx_, &other));
  Ok(rtGeometryTrianglesSetPrimitiveCount(other, 1));
  Ok(rtGeometryTrianglesSetVertices(other, 4, vertices_, 0, 12, RT_FORMAT_FLOAT3));
  Ok(rtGeometryTrianglesSetTriangleIndices(other, indices_, 0, 12, RT_FORMAT_UNSIGNED_INT3));
  const unsigned char zero[] = {0, 7};
  Fill(m, zero, sizeof(zero));
  Ok(rtGeometryTrianglesSetMaterialIndices(other, m, 0, 0, RT_FORMAT_UNSIGNED_BYTE));
  RTgeometryinstance gi = Instance(other, {Material("closest_tag", 30)});
  Ok(rtGeometryGroupSetChild(group_, 0, gi));
  std::vector<Float4> out = Launch();
  for (unsigned i = 0; i < out.size(); ++i) {
    EXPECT_EQ(out[i][2], OnFirst(i % kSize, i / kSize) ? 30.f : -1.f) << i;
  }
}

// The same for a program that no longer binds: a detached instance whose material sets
// `material_tag` (a float) as an int fails no launch once a healthy instance replaced it.
TEST_P(TrianglesProbeTest, DetachedInstanceWithAnUnbindableProgramDoesNotFailLaunches) {
  RTmaterial bad = nullptr;
  Ok(rtMaterialCreate(ctx_, &bad));
  Ok(rtMaterialSetClosestHitProgram(bad, 0, Prog("closest_tag")));
  RTvariable tag = nullptr;
  Ok(rtMaterialDeclareVariable(bad, "material_tag", &tag));
  Ok(rtVariableSet1i(tag, 3));
  Scene({bad});
  LaunchFails({"material_tag", "type mismatch"});
  Ok(rtGeometryGroupSetChild(group_, 0, Instance(triangles_, {Material("closest_tag", 40)})));
  std::vector<Float4> out = Launch();
  for (unsigned i = 0; i < out.size(); ++i) EXPECT_EQ(out[i][2], 40.f) << i;
}

TEST_P(TrianglesProbeTest, DestroyedTrianglesFailByName) {
  Scene({Material("closest_tag")});
  Launch();
  Ok(rtGeometryTrianglesDestroy(triangles_));
  LaunchFails({"geometry triangles", "destroyed"});
}

TEST_P(TrianglesProbeTest, AttributeProgramReadsTheTrianglesVariables) {
  RTvariable v = nullptr;
  Ok(rtGeometryTrianglesDeclareVariable(triangles_, "mesh_tag", &v));
  Ok(rtVariableSet1f(v, 6.f));
  Ok(rtGeometryTrianglesSetAttributeProgram(triangles_, Prog("attribute_mesh_tag")));
  Scene({Material("closest_info_raw")});
  for (const Float4& o : Launch()) EXPECT_EQ(o[0], 6.f);
  Ok(rtVariableSet1f(v, 8.f));
  for (const Float4& o : Launch()) EXPECT_EQ(o[0], 8.f);
}

INSTANTIATE_TEST_SUITE_P(Devices, TrianglesProbeTest, ::testing::Values("inproc", "local:2"),
                         DeviceName);

}  // namespace
}  // namespace tessera::testing

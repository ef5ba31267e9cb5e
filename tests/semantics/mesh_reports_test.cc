// OptiX 3 meshes traced as native Embree triangles (builder Trbvh with vertex_buffer and
// index_buffer) give what the same programs give as user geometry (builder Bvh) when an
// intersection program reports more than once per call, and attributes a program leaves
// unwritten read zero (mesh_reports_programs.cu). On an in-process device and on workers.
#include <gtest/gtest.h>

#include <array>
#include <cstring>
#include <string>
#include <vector>

#include "rt_fixture.h"
#include "tessera/rt_ext.h"

namespace tessera::testing {
namespace {

constexpr char kModule[] = "mesh_reports_programs";
constexpr unsigned kSide = 8;
using Uint4 = std::array<unsigned, 4>;

class MeshReportsTest : public RtFixture, public ::testing::WithParamInterface<const char*> {
 protected:
  // Two squares of two triangles each, at z = 1 (triangles 0, 1) and z = 4 (2, 3), one
  // GeometryGroup with acceleration `builder`, traced straight along +z.
  std::vector<Uint4> Render(const char* builder, const char* intersection, bool any_hit,
                            float second_z = 4.f) {
    RTbuffer output = Build(builder, intersection, any_hit, second_z);
    Ok(rtContextLaunch2D(ctx_, 0, kSide, kSide));
    return ReadAs<Uint4>(output);
  }

  // The scene of Render, on a new context; returns its output buffer. With `bad_index`, the last
  // triangle names a vertex past the buffer (the device cannot build the mesh); with `root`, that
  // node (a Transform or a Selector) holds the geometry group instead of top_object itself.
  RTbuffer Build(const char* builder, const char* intersection, bool any_hit, float second_z = 4.f,
                 bool bad_index = false, const char* root = nullptr) {
    if (ctx_ != nullptr) rtContextDestroy(ctx_);
    EXPECT_EQ(rtContextCreate(&ctx_), RT_SUCCESS);
    Ok(tesseraContextSetDeviceSpec(ctx_, GetParam()));
    Ok(rtContextSetEntryPointCount(ctx_, 1));
    Ok(rtContextSetRayTypeCount(ctx_, 2));
    Ok(rtContextSetRayGenerationProgram(ctx_, 0, Program(kModule, "ray_gen")));

    const float z[2] = {1.f, second_z};
    std::vector<float> vertices;
    std::vector<int> indices;
    for (int q = 0; q < 2; ++q) {
      for (const auto& [x, y] :
           {std::pair{-10.f, -10.f}, {10.f, -10.f}, {10.f, 10.f}, {-10.f, 10.f}}) {
        vertices.insert(vertices.end(), {x, y, z[q]});
      }
      const int b = 4 * q;
      indices.insert(indices.end(), {b, b + 1, b + 2, b, b + 2, b + 3});
    }
    if (bad_index) indices.back() = 8;
    RTgeometry geometry = nullptr;
    Ok(rtGeometryCreate(ctx_, &geometry));
    Ok(rtGeometrySetPrimitiveCount(geometry, 4));
    Ok(rtGeometrySetIntersectionProgram(geometry, Program(kModule, intersection)));
    Ok(rtGeometrySetBoundingBoxProgram(geometry, Program("semantics_programs", "mesh_bounds")));
    BindBuffer(geometry, "vertex_buffer", RT_FORMAT_FLOAT3, vertices.data(), 8);
    BindBuffer(geometry, "index_buffer", RT_FORMAT_INT3, indices.data(), 4);

    RTmaterial material = nullptr;
    Ok(rtMaterialCreate(ctx_, &material));
    Ok(rtMaterialSetClosestHitProgram(material, 0, Program(kModule, "closest_hit")));
    if (any_hit) Ok(rtMaterialSetAnyHitProgram(material, 0, Program(kModule, "count_any_hit")));
    Ok(rtMaterialSetAnyHitProgram(material, 1, Program(kModule, "shadow_any_hit")));
    RTgeometryinstance instance = nullptr;
    Ok(rtGeometryInstanceCreate(ctx_, &instance));
    Ok(rtGeometryInstanceSetGeometry(instance, geometry));
    Ok(rtGeometryInstanceSetMaterialCount(instance, 1));
    Ok(rtGeometryInstanceSetMaterial(instance, 0, material));
    RTgeometrygroup group = nullptr;
    Ok(rtGeometryGroupCreate(ctx_, &group));
    Ok(rtGeometryGroupSetAcceleration(group, Accel(builder)));
    Ok(rtGeometryGroupSetChildCount(group, 1));
    Ok(rtGeometryGroupSetChild(group, 0, instance));
    RTobject top = group;
    if (root != nullptr && std::string(root) == "transform") {
      RTtransform transform = nullptr;
      Ok(rtTransformCreate(ctx_, &transform));
      Ok(rtTransformSetChild(transform, group));
      top = transform;
    } else if (root != nullptr) {
      RTselector selector = nullptr;
      Ok(rtSelectorCreate(ctx_, &selector));
      Ok(rtSelectorSetVisitProgram(selector, Program(kModule, "visit_first")));
      Ok(rtSelectorSetChildCount(selector, 1));
      Ok(rtSelectorSetChild(selector, 0, group));
      top = selector;
    }
    Ok(rtVariableSetObject(ContextVar("top_object"), top));
    return Buffer2D("output", RT_BUFFER_OUTPUT, RT_FORMAT_UNSIGNED_INT4, kSide, kSide);
  }

  void BindBuffer(RTgeometry g, const char* name, RTformat format, const void* data, size_t n) {
    RTbuffer b = nullptr;
    Ok(rtBufferCreate(ctx_, RT_BUFFER_INPUT, &b));
    Ok(rtBufferSetFormat(b, format));
    Ok(rtBufferSetSize1D(b, n));
    void* p = nullptr;
    Ok(rtBufferMap(b, &p));
    std::memcpy(p, data, n * 12);
    Ok(rtBufferUnmap(b));
    RTvariable v = nullptr;
    Ok(rtGeometryDeclareVariable(g, name, &v));
    Ok(rtVariableSetObject(v, b));
  }
};

// Word 0: radiance any-hit runs | shadow any-hit runs << 8; 1: attribute a_id; 2: t; 3: b_id.
TEST_P(MeshReportsTest, SeveralReportsPerCallGiveWhatUserGeometryGives) {
  struct Case {
    const char* intersection;
    bool any_hit;
  };
  // Testing every triangle in one call with an any-hit program is not among them: during
  // traversal the first report of a call stands for Embree's candidate (docs/programs.md).
  for (const Case& c : {Case{"intersect_all", false}, Case{"intersect_twice", false},
                        Case{"intersect_twice", true}}) {
    SCOPED_TRACE(std::string(c.intersection) + (c.any_hit ? " with any-hit" : ""));
    const std::vector<Uint4> mesh = Render("Trbvh", c.intersection, c.any_hit);
    const std::vector<Uint4> user = Render("Bvh", c.intersection, c.any_hit);
    EXPECT_EQ(mesh, user);
    for (const Uint4& p : mesh) {
      EXPECT_LT(p[1], 2u) << "the near square's triangle, reported first";
      float t;
      std::memcpy(&t, &p[2], sizeof(t));
      EXPECT_FLOAT_EQ(t, 1.f);
      EXPECT_EQ(p[0], (c.any_hit ? 1u : 0u) | (1u << 8)) << "any-hit programs run once";
    }
  }
}

TEST_P(MeshReportsTest, AnAttributeTheProgramDidNotWriteReadsZero) {
  for (const char* builder : {"Trbvh", "Bvh"}) {
    SCOPED_TRACE(builder);
    const std::vector<Uint4> pixels = Render(builder, "intersect_partial", false);
    for (unsigned y = 0; y < kSide; ++y) {
      for (unsigned x = 0; x < kSide; ++x) {
        EXPECT_EQ(pixels[y * kSide + x][3], x == 1 ? 1000 + y : 0u) << "(" << x << ", " << y << ")";
      }
    }
  }
}

// Both squares at z = 1: every ray hits two triangles at exactly the same t. Which one wins is
// up to the acceleration, but it must be the same in every run and on every device (Embree's
// LOW-quality build, once used for Lbvh, MedianBvh and NoAccel, varied from run to run).
TEST_P(MeshReportsTest, ExactTiesResolveTheSameWayEveryTime) {
  for (const char* builder : {"NoAccel", "Lbvh", "MedianBvh", "Bvh", "Trbvh"}) {
    SCOPED_TRACE(builder);
    const std::vector<Uint4> first = Render(builder, "intersect_twice", false, 1.f);
    for (int run = 0; run < 4; ++run) {
      EXPECT_EQ(Render(builder, "intersect_twice", false, 1.f), first) << "run " << run;
    }
  }
}

// A mesh the device cannot build says why, whatever node top_object names above it.
TEST_P(MeshReportsTest, AMeshThatCannotBeBuiltSaysWhyBelowAnyRoot) {
  for (const char* root : {"group", "transform", "selector"}) {
    SCOPED_TRACE(root);
    Build("Trbvh", "intersect_all", false, 4.f, /*bad_index=*/true,
          std::string(root) == "group" ? nullptr : root);
    const RTresult code = rtContextLaunch2D(ctx_, 0, kSide, kSide);
    EXPECT_NE(code, RT_SUCCESS);
    EXPECT_NE(Error(code).find("uses vertex 8 but the vertex buffer holds 8"), std::string::npos)
        << Error(code);
  }
}

INSTANTIATE_TEST_SUITE_P(Devices, MeshReportsTest, ::testing::Values("inproc", "local:2"),
                         DeviceName);

}  // namespace
}  // namespace tessera::testing

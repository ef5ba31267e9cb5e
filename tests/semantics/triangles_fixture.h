// The fixture of triangles_test.cc and triangles_probe_test.cc: built-in triangles (OptiX 6
// GeometryTriangles) under top_object, rays from a grid above them, programs from
// triangles_programs.cu.
#ifndef TESSERA_TESTS_SEMANTICS_TRIANGLES_FIXTURE_H_
#define TESSERA_TESTS_SEMANTICS_TRIANGLES_FIXTURE_H_

#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

#include "rt_fixture.h"
#include "tessera/rt_ext.h"

namespace tessera::testing {

inline constexpr unsigned kSize = 4;  // rays per side of the unit square

// A context on the device set GetParam() names, tracing a 4x4 grid of rays along -z at the unit
// square z = 0, made of two built-in triangles.
class TrianglesFixture : public OnDevicesFixture {
 protected:
  void SetUp() override {
    OnDevicesFixture::SetUp();
    Ok(rtContextSetRayGenerationProgram(ctx_, 0, Prog("ortho")));
    Ok(rtContextSetMissProgram(ctx_, 0, Prog("miss")));
    output_ = Float4Buffer("output", RT_BUFFER_OUTPUT, kSize, kSize);
    // The unit square at z = 0 as two triangles, 0 front-facing the rays, 1 back-facing.
    const float vertices[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0};
    const unsigned indices[] = {0, 1, 2, 1, 2, 3};
    vertices_ = InputBuffer(RT_FORMAT_FLOAT3, 4, vertices, sizeof(vertices));
    indices_ = InputBuffer(RT_FORMAT_UNSIGNED_INT3, 2, indices, sizeof(indices));
    Ok(rtGeometryTrianglesCreate(ctx_, &triangles_));
    Ok(rtGeometryTrianglesSetPrimitiveCount(triangles_, 2));
    Ok(rtGeometryTrianglesSetVertices(triangles_, 4, vertices_, 0, 12, RT_FORMAT_FLOAT3));
    Ok(rtGeometryTrianglesSetTriangleIndices(triangles_, indices_, 0, 12, RT_FORMAT_UNSIGNED_INT3));
  }

  RTprogram Prog(const char* function) { return Program("triangles_programs", function); }

  RTbuffer InputBuffer(RTformat format, size_t n, const void* data, size_t bytes,
                       unsigned type = RT_BUFFER_INPUT) {
    RTbuffer b = nullptr;
    EXPECT_EQ(rtBufferCreate(ctx_, type, &b), RT_SUCCESS);
    EXPECT_EQ(rtBufferSetFormat(b, format), RT_SUCCESS);
    EXPECT_EQ(rtBufferSetSize1D(b, n), RT_SUCCESS);
    Fill(b, data, bytes);
    return b;
  }
  void Fill(RTbuffer b, const void* data, size_t bytes) {
    void* p = nullptr;
    EXPECT_EQ(rtBufferMap(b, &p), RT_SUCCESS);
    if (bytes != 0) std::memcpy(p, data, bytes);
    EXPECT_EQ(rtBufferUnmap(b), RT_SUCCESS);
  }

  RTmaterial Material(const char* closest_hit, float tag = 0.f) {
    RTmaterial m = nullptr;
    EXPECT_EQ(rtMaterialCreate(ctx_, &m), RT_SUCCESS);
    EXPECT_EQ(rtMaterialSetClosestHitProgram(m, 0, Prog(closest_hit)), RT_SUCCESS);
    RTvariable v = nullptr;
    EXPECT_EQ(rtMaterialDeclareVariable(m, "material_tag", &v), RT_SUCCESS);
    EXPECT_EQ(rtVariableSet1f(v, tag), RT_SUCCESS);
    return m;
  }

  RTgeometryinstance Instance(RTgeometrytriangles t, const std::vector<RTmaterial>& materials) {
    RTgeometryinstance gi = nullptr;
    EXPECT_EQ(rtGeometryInstanceCreate(ctx_, &gi), RT_SUCCESS);
    EXPECT_EQ(rtGeometryInstanceSetGeometryTriangles(gi, t), RT_SUCCESS);
    EXPECT_EQ(rtGeometryInstanceSetMaterialCount(gi, static_cast<unsigned>(materials.size())),
              RT_SUCCESS);
    for (unsigned i = 0; i < materials.size(); ++i) {
      EXPECT_EQ(rtGeometryInstanceSetMaterial(gi, i, materials[i]), RT_SUCCESS);
    }
    return gi;
  }

  RTgeometrygroup Group(const std::vector<RTgeometryinstance>& children) {
    RTgeometrygroup g = nullptr;
    EXPECT_EQ(rtGeometryGroupCreate(ctx_, &g), RT_SUCCESS);
    EXPECT_EQ(rtGeometryGroupSetAcceleration(g, Accel("Trbvh")), RT_SUCCESS);
    EXPECT_EQ(rtGeometryGroupSetChildCount(g, static_cast<unsigned>(children.size())), RT_SUCCESS);
    for (unsigned i = 0; i < children.size(); ++i) {
      EXPECT_EQ(rtGeometryGroupSetChild(g, i, children[i]), RT_SUCCESS);
    }
    return g;
  }

  // Puts the triangles with `materials` under top_object.
  void Scene(const std::vector<RTmaterial>& materials) {
    instance_ = Instance(triangles_, materials);
    group_ = Group({instance_});
    Ok(rtVariableSetObject(ContextVar("top_object"), group_));
  }

  std::vector<Float4> Launch() {
    RTresult r = rtContextLaunch2D(ctx_, 0, kSize, kSize);
    EXPECT_EQ(r, RT_SUCCESS) << Error(r);
    return Read(output_);
  }
  // A launch that must fail with a message holding every one of `words`.
  void LaunchFails(const std::vector<std::string>& words) {
    RTresult r = rtContextLaunch2D(ctx_, 0, kSize, kSize);
    EXPECT_NE(r, RT_SUCCESS);
    const std::string e = Error(r);
    for (const std::string& w : words) EXPECT_NE(e.find(w), std::string::npos) << w << ": " << e;
  }

  static float Coord(unsigned i) { return (i + 0.3f) / kSize; }
  static bool OnFirst(unsigned x, unsigned y) { return Coord(x) + Coord(y) < 1.f; }

  RTbuffer output_ = nullptr, vertices_ = nullptr, indices_ = nullptr;
  RTgeometrytriangles triangles_ = nullptr;
  RTgeometryinstance instance_ = nullptr;
  RTgeometrygroup group_ = nullptr;
};

}  // namespace tessera::testing

#endif  // TESSERA_TESTS_SEMANTICS_TRIANGLES_FIXTURE_H_

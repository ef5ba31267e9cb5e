// Built-in triangles (OptiX 6 GeometryTriangles): Embree's hit reaches the programs as the
// primitive index, barycentrics and face, through the built-in attribute or an attribute program,
// with per-triangle materials and any-hit programs; bad arguments fail by name. Each case runs
// on the in-process device and on two worker processes.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "triangles_fixture.h"

namespace tessera::testing {
namespace {

class TrianglesTest : public TrianglesFixture {};

TEST_P(TrianglesTest, BuiltInAttributeGivesPrimitiveFaceAndBarycentrics) {
  Scene({Material("closest_barycentrics")});
  std::vector<Float4> out = Launch();
  for (unsigned y = 0; y < kSize; ++y) {
    for (unsigned x = 0; x < kSize; ++x) {
      const Float4& v = out[y * kSize + x];
      const float px = Coord(x), py = Coord(y);
      SCOPED_TRACE(::testing::Message() << "launch index " << x << "," << y);
      if (OnFirst(x, y)) {  // p = v0 + u (v1 - v0) + v (v2 - v0)
        EXPECT_EQ(v[0], 0.f);
        EXPECT_EQ(v[1], 1.f) << "front face";
        EXPECT_NEAR(v[2], px, 1e-5);
        EXPECT_NEAR(v[3], py, 1e-5);
      } else {  // p = v1 + u (v2 - v1) + v (v3 - v1)
        EXPECT_EQ(v[0], 1.f);
        EXPECT_EQ(v[1], 2.f) << "back face";
        EXPECT_NEAR(v[2], 1.f - px, 1e-5);
        EXPECT_NEAR(v[3], px + py - 1.f, 1e-5);
      }
    }
  }
}

TEST_P(TrianglesTest, AttributeProgramPerTriangleMaterialsAndIndexOffset) {
  Ok(rtGeometryTrianglesSetAttributeProgram(triangles_, Prog("attributes")));
  Ok(rtGeometryTrianglesSetPrimitiveIndexOffset(triangles_, 10));
  Ok(rtGeometryTrianglesSetMaterialCount(triangles_, 2));
  const unsigned char material_of[] = {1, 0};
  RTbuffer m = InputBuffer(RT_FORMAT_UNSIGNED_BYTE, 2, material_of, sizeof(material_of));
  Ok(rtGeometryTrianglesSetMaterialIndices(triangles_, m, 0, 1, RT_FORMAT_UNSIGNED_BYTE));
  Scene({Material("closest_info", 100.f), Material("closest_info", 200.f)});
  std::vector<Float4> out = Launch();
  for (unsigned y = 0; y < kSize; ++y) {
    for (unsigned x = 0; x < kSize; ++x) {
      const Float4& v = out[y * kSize + x];
      SCOPED_TRACE(::testing::Message() << "launch index " << x << "," << y);
      const bool first = OnFirst(x, y);
      EXPECT_EQ(v[0], first ? 10.f : 11.f) << "primitive index with the offset";
      EXPECT_EQ(v[1], first ? 201.f : 102.f) << "face code plus the triangle's material tag";
      EXPECT_NEAR(v[2], first ? Coord(x) + Coord(y) : Coord(y), 1e-5) << "u + v";
      EXPECT_FLOAT_EQ(v[3], 1.f) << "distance";
    }
  }
}

TEST_P(TrianglesTest, AnyHitSeesTheCandidateAndCanIgnoreIt) {
  RTmaterial m = Material("closest_barycentrics");
  Ok(rtMaterialSetAnyHitProgram(m, 0, Prog("any_hit_skip_first")));
  Scene({m});
  std::vector<Float4> out = Launch();
  for (unsigned y = 0; y < kSize; ++y) {
    for (unsigned x = 0; x < kSize; ++x) {
      EXPECT_EQ(out[y * kSize + x][0], OnFirst(x, y) ? -1.f : 1.f) << x << "," << y;
    }
  }
}

TEST_P(TrianglesTest, BarycentricsOutsideAnAttributeProgramFailTheLaunch) {
  Scene({Material("closest_wrong_call")});
  RTresult r = rtContextLaunch2D(ctx_, 0, kSize, kSize);
  EXPECT_NE(r, RT_SUCCESS);
  EXPECT_NE(Error(r).find("rtGetTriangleBarycentrics"), std::string::npos) << Error(r);
}

TEST_P(TrianglesTest, ValidationNamesWhatIsMissingOrTooSmall) {
  Scene({Material("closest_barycentrics")});
  // Three triangles' indices do not fit a buffer of two.
  Ok(rtGeometryTrianglesSetPrimitiveCount(triangles_, 3));
  RTresult r = rtContextValidate(ctx_);
  EXPECT_EQ(r, RT_ERROR_INVALID_CONTEXT);
  EXPECT_NE(Error(r).find("geometry triangles"), std::string::npos) << Error(r);
  EXPECT_NE(Error(r).find("do not fit"), std::string::npos) << Error(r);
  Ok(rtGeometryTrianglesSetPrimitiveCount(triangles_, 2));
  // Two materials on the triangles, one on the instance.
  Ok(rtGeometryTrianglesSetMaterialCount(triangles_, 2));
  r = rtContextValidate(ctx_);
  EXPECT_NE(r, RT_SUCCESS);
  EXPECT_NE(Error(r).find("materials"), std::string::npos) << Error(r);
}

INSTANTIATE_TEST_SUITE_P(Devices, TrianglesTest, ::testing::Values("inproc", "local:2"),
                         DeviceName);

// Arguments: formats, strides, handles and counts.
class TrianglesApiTest : public RtFixture {};

TEST_F(TrianglesApiTest, BadArgumentsFailWithTheirCode) {
  RTgeometrytriangles t = nullptr;
  Ok(rtGeometryTrianglesCreate(ctx_, &t));
  RTbuffer b = nullptr;
  Ok(rtBufferCreate(ctx_, RT_BUFFER_INPUT, &b));
  Ok(rtBufferSetFormat(b, RT_FORMAT_FLOAT3));
  Ok(rtBufferSetSize1D(b, 3));
  EXPECT_EQ(rtGeometryTrianglesSetVertices(t, 3, b, 0, 0, RT_FORMAT_INT3), RT_ERROR_INVALID_VALUE);
  EXPECT_NE(Error(RT_ERROR_INVALID_VALUE).find("vertex format"), std::string::npos);
  EXPECT_EQ(rtGeometryTrianglesSetVertices(t, 3, b, 0, 8, RT_FORMAT_FLOAT3),
            RT_ERROR_INVALID_VALUE);  // stride below an element
  EXPECT_EQ(rtGeometryTrianglesSetVertices(t, 3, nullptr, 0, 0, RT_FORMAT_FLOAT3),
            RT_ERROR_INVALID_VALUE);
  EXPECT_EQ(rtGeometryTrianglesSetTriangleIndices(t, b, 0, 0, RT_FORMAT_FLOAT3),
            RT_ERROR_INVALID_VALUE);
  EXPECT_EQ(rtGeometryTrianglesSetMaterialCount(t, 0), RT_ERROR_INVALID_VALUE);
  EXPECT_EQ(rtGeometryTrianglesGetPrimitiveCount(t, nullptr), RT_ERROR_INVALID_VALUE);
  // Not a geometry, and not a geometry triangles.
  RTgeometryinstance gi = nullptr;
  Ok(rtGeometryInstanceCreate(ctx_, &gi));
  EXPECT_NE(rtGeometryInstanceSetGeometry(gi, reinterpret_cast<RTgeometry>(t)), RT_SUCCESS);
  EXPECT_NE(rtGeometrySetPrimitiveCount(reinterpret_cast<RTgeometry>(t), 1), RT_SUCCESS);
  EXPECT_NE(rtGeometryTrianglesSetPrimitiveCount(reinterpret_cast<RTgeometrytriangles>(gi), 1),
            RT_SUCCESS);
  Ok(rtGeometryInstanceSetGeometryTriangles(gi, t));
  RTgeometry g = reinterpret_cast<RTgeometry>(1);
  Ok(rtGeometryInstanceGetGeometry(gi, &g));
  EXPECT_EQ(g, nullptr);
  RTgeometrytriangles back = nullptr;
  Ok(rtGeometryInstanceGetGeometryTriangles(gi, &back));
  EXPECT_EQ(back, t);
  // Vertices missing.
  Ok(rtGeometryTrianglesSetPrimitiveCount(t, 1));
  RTresult r = rtGeometryTrianglesValidate(t);
  EXPECT_NE(r, RT_SUCCESS);
  EXPECT_NE(Error(r).find("vertices are not set"), std::string::npos) << Error(r);
  Ok(rtGeometryTrianglesSetVertices(t, 3, b, 0, 0, RT_FORMAT_FLOAT3));
  Ok(rtGeometryTrianglesValidate(t));
  Ok(rtGeometryTrianglesDestroy(t));
  EXPECT_NE(rtGeometryTrianglesDestroy(t), RT_SUCCESS);
}

}  // namespace
}  // namespace tessera::testing

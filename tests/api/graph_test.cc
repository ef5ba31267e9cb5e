// The node graph through the C API: building it, child rules, transforms, accelerations, and
// validation messages that name what is wrong.
#include <cmath>
#include <cstring>
#include <string>

#include "api_test_util.h"
#include "gtest/gtest.h"
#include "tessera/rt.h"

namespace tessera::test {
namespace {

class HostGraphTest : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_EQ(rtContextCreate(&ctx), RT_SUCCESS);
    ASSERT_EQ(rtContextSetRayTypeCount(ctx, 2), RT_SUCCESS);
  }
  void TearDown() override { EXPECT_EQ(rtContextDestroy(ctx), RT_SUCCESS); }

  RTprogram Program(const char* function) {
    RTprogram p = nullptr;
    EXPECT_EQ(rtProgramCreateFromPTXFile(ctx, kTestModule, function, &p), RT_SUCCESS);
    return p;
  }

  RTacceleration Accel(const char* builder = "Sbvh", const char* traverser = "Bvh") {
    RTacceleration a = nullptr;
    EXPECT_EQ(rtAccelerationCreate(ctx, &a), RT_SUCCESS);
    EXPECT_EQ(rtAccelerationSetBuilder(a, builder), RT_SUCCESS);
    EXPECT_EQ(rtAccelerationSetTraverser(a, traverser), RT_SUCCESS);
    return a;
  }

  // A complete geometry group with one instance.
  RTgeometrygroup CompleteGeometryGroup() {
    RTgeometry g;
    EXPECT_EQ(rtGeometryCreate(ctx, &g), RT_SUCCESS);
    EXPECT_EQ(rtGeometrySetPrimitiveCount(g, 12), RT_SUCCESS);
    EXPECT_EQ(rtGeometrySetIntersectionProgram(g, Program("intersect")), RT_SUCCESS);
    EXPECT_EQ(rtGeometrySetBoundingBoxProgram(g, Program("bounds")), RT_SUCCESS);
    RTmaterial m;
    EXPECT_EQ(rtMaterialCreate(ctx, &m), RT_SUCCESS);
    RTgeometryinstance gi;
    EXPECT_EQ(rtGeometryInstanceCreate(ctx, &gi), RT_SUCCESS);
    EXPECT_EQ(rtGeometryInstanceSetGeometry(gi, g), RT_SUCCESS);
    EXPECT_EQ(rtGeometryInstanceSetMaterialCount(gi, 1), RT_SUCCESS);
    EXPECT_EQ(rtGeometryInstanceSetMaterial(gi, 0, m), RT_SUCCESS);
    RTgeometrygroup gg;
    EXPECT_EQ(rtGeometryGroupCreate(ctx, &gg), RT_SUCCESS);
    EXPECT_EQ(rtGeometryGroupSetChildCount(gg, 1), RT_SUCCESS);
    EXPECT_EQ(rtGeometryGroupSetChild(gg, 0, gi), RT_SUCCESS);
    EXPECT_EQ(rtGeometryGroupSetAcceleration(gg, Accel()), RT_SUCCESS);
    return gg;
  }

  // Validates and expects failure with `code` and a message containing every fragment.
  void ExpectInvalid(RTresult got, RTresult code, std::initializer_list<const char*> fragments) {
    EXPECT_EQ(got, code);
    std::string message = ErrorString(ctx, code);
    for (const char* f : fragments) {
      EXPECT_NE(message.find(f), std::string::npos) << "'" << f << "' not in: " << message;
    }
  }

  RTcontext ctx = nullptr;
};

TEST_F(HostGraphTest, BuildsAndValidatesAScene) {
  RTgeometrygroup gg = CompleteGeometryGroup();
  EXPECT_EQ(rtGeometryGroupValidate(gg), RT_SUCCESS);
  RTtransform t;
  ASSERT_EQ(rtTransformCreate(ctx, &t), RT_SUCCESS);
  ASSERT_EQ(rtTransformSetChild(t, gg), RT_SUCCESS);
  RTselector s;
  ASSERT_EQ(rtSelectorCreate(ctx, &s), RT_SUCCESS);
  ASSERT_EQ(rtSelectorSetVisitProgram(s, Program("visit")), RT_SUCCESS);
  ASSERT_EQ(rtSelectorSetChildCount(s, 2), RT_SUCCESS);
  ASSERT_EQ(rtSelectorSetChild(s, 0, gg), RT_SUCCESS);  // sharing children is allowed
  ASSERT_EQ(rtSelectorSetChild(s, 1, t), RT_SUCCESS);
  RTgroup root;
  ASSERT_EQ(rtGroupCreate(ctx, &root), RT_SUCCESS);
  ASSERT_EQ(rtGroupSetAcceleration(root, Accel("Bvh", "BvhCompact")), RT_SUCCESS);
  ASSERT_EQ(rtGroupSetChildCount(root, 3), RT_SUCCESS);
  ASSERT_EQ(rtGroupSetChild(root, 0, t), RT_SUCCESS);
  ASSERT_EQ(rtGroupSetChild(root, 1, s), RT_SUCCESS);
  ASSERT_EQ(rtGroupSetChild(root, 2, gg), RT_SUCCESS);
  EXPECT_EQ(rtGroupValidate(root), RT_SUCCESS);

  RTobjecttype type;
  ASSERT_EQ(rtGroupGetChildType(root, 0, &type), RT_SUCCESS);
  EXPECT_EQ(type, RT_OBJECTTYPE_TRANSFORM);
  ASSERT_EQ(rtGroupGetChildType(root, 1, &type), RT_SUCCESS);
  EXPECT_EQ(type, RT_OBJECTTYPE_SELECTOR);
  ASSERT_EQ(rtSelectorGetChildType(s, 0, &type), RT_SUCCESS);
  EXPECT_EQ(type, RT_OBJECTTYPE_GEOMETRY_GROUP);
  ASSERT_EQ(rtTransformGetChildType(t, &type), RT_SUCCESS);
  EXPECT_EQ(type, RT_OBJECTTYPE_GEOMETRY_GROUP);
  RTobject child;
  ASSERT_EQ(rtGroupGetChild(root, 2, &child), RT_SUCCESS);
  EXPECT_EQ(child, gg);
  unsigned count;
  ASSERT_EQ(rtGroupGetChildCount(root, &count), RT_SUCCESS);
  EXPECT_EQ(count, 3u);

  // A context with an entry point and this scene validates and compiles.
  ASSERT_EQ(rtContextSetEntryPointCount(ctx, 1), RT_SUCCESS);
  ASSERT_EQ(rtContextSetRayGenerationProgram(ctx, 0, Program("ray_gen")), RT_SUCCESS);
  RTvariable top;
  ASSERT_EQ(rtContextDeclareVariable(ctx, "top_object", &top), RT_SUCCESS);
  ASSERT_EQ(rtVariableSetObject(top, root), RT_SUCCESS);
  EXPECT_EQ(rtContextValidate(ctx), RT_SUCCESS);
  EXPECT_EQ(rtContextCompile(ctx), RT_SUCCESS);
}

TEST_F(HostGraphTest, ValidationNamesWhatIsMissing) {
  RTgeometry g;
  ASSERT_EQ(rtGeometryCreate(ctx, &g), RT_SUCCESS);
  ExpectInvalid(rtGeometryValidate(g), RT_ERROR_INVALID_VALUE,
                {"rtGeometryValidate(geometry #", "intersection program is not set"});
  ASSERT_EQ(rtGeometrySetIntersectionProgram(g, Program("intersect")), RT_SUCCESS);
  ExpectInvalid(rtGeometryValidate(g), RT_ERROR_INVALID_VALUE, {"bounding box program"});
  ASSERT_EQ(rtGeometrySetBoundingBoxProgram(g, Program("bounds")), RT_SUCCESS);
  ExpectInvalid(rtGeometryValidate(g), RT_ERROR_INVALID_VALUE, {"primitive count"});
  ASSERT_EQ(rtGeometrySetPrimitiveCount(g, 0), RT_SUCCESS);
  EXPECT_EQ(rtGeometryValidate(g), RT_SUCCESS);

  RTgeometryinstance gi;
  ASSERT_EQ(rtGeometryInstanceCreate(ctx, &gi), RT_SUCCESS);
  ExpectInvalid(rtGeometryInstanceValidate(gi), RT_ERROR_INVALID_VALUE, {"geometry is not set"});
  ASSERT_EQ(rtGeometryInstanceSetGeometry(gi, g), RT_SUCCESS);
  ExpectInvalid(rtGeometryInstanceValidate(gi), RT_ERROR_INVALID_VALUE, {"material count is 0"});
  ASSERT_EQ(rtGeometryInstanceSetMaterialCount(gi, 2), RT_SUCCESS);
  ExpectInvalid(rtGeometryInstanceValidate(gi), RT_ERROR_INVALID_VALUE,
                {"geometry instance #", "material 0 is not set"});

  RTgeometrygroup gg;
  ASSERT_EQ(rtGeometryGroupCreate(ctx, &gg), RT_SUCCESS);
  ExpectInvalid(rtGeometryGroupValidate(gg), RT_ERROR_INVALID_VALUE, {"acceleration is not set"});
  RTacceleration a;
  ASSERT_EQ(rtAccelerationCreate(ctx, &a), RT_SUCCESS);
  ASSERT_EQ(rtGeometryGroupSetAcceleration(gg, a), RT_SUCCESS);
  ExpectInvalid(rtGeometryGroupValidate(gg), RT_ERROR_INVALID_VALUE,
                {"acceleration #", "no builder set"});
  ASSERT_EQ(rtAccelerationSetBuilder(a, "TriangleKdTree"), RT_SUCCESS);
  ASSERT_EQ(rtAccelerationSetTraverser(a, "Bvh"), RT_SUCCESS);
  ExpectInvalid(rtAccelerationValidate(a), RT_ERROR_INVALID_VALUE,
                {"'TriangleKdTree' cannot be used with traverser 'Bvh'"});
  ASSERT_EQ(rtAccelerationSetTraverser(a, "KdTree"), RT_SUCCESS);
  ASSERT_EQ(rtGeometryGroupSetChildCount(gg, 1), RT_SUCCESS);
  ExpectInvalid(rtGeometryGroupValidate(gg), RT_ERROR_INVALID_VALUE, {"child 0 is not set"});
  ASSERT_EQ(rtGeometryGroupSetChild(gg, 0, gi), RT_SUCCESS);
  ExpectInvalid(rtGeometryGroupValidate(gg), RT_ERROR_INVALID_VALUE, {"material 0 is not set"});

  RTselector s;
  ASSERT_EQ(rtSelectorCreate(ctx, &s), RT_SUCCESS);
  ExpectInvalid(rtSelectorValidate(s), RT_ERROR_INVALID_VALUE, {"visit program is not set"});
  RTtransform t;
  ASSERT_EQ(rtTransformCreate(ctx, &t), RT_SUCCESS);
  ExpectInvalid(rtTransformValidate(t), RT_ERROR_INVALID_VALUE,
                {"transform #", "child is not set"});
  RTgroup group;
  ASSERT_EQ(rtGroupCreate(ctx, &group), RT_SUCCESS);
  ExpectInvalid(rtGroupValidate(group), RT_ERROR_INVALID_VALUE, {"group #", "acceleration"});
}

TEST_F(HostGraphTest, ContextValidationCoversEntryPointsAndReferences) {
  ASSERT_EQ(rtContextSetEntryPointCount(ctx, 2), RT_SUCCESS);
  ExpectInvalid(rtContextValidate(ctx), RT_ERROR_INVALID_CONTEXT,
                {"rtContextValidate(context)", "entry point 0 has no ray generation program"});
  RTprogram rg = Program("ray_gen");
  ASSERT_EQ(rtContextSetRayGenerationProgram(ctx, 0, rg), RT_SUCCESS);
  ASSERT_EQ(rtContextSetRayGenerationProgram(ctx, 1, rg), RT_SUCCESS);
  EXPECT_EQ(rtContextValidate(ctx), RT_SUCCESS);

  // Buffers a variable refers to must be complete.
  RTbuffer b;
  ASSERT_EQ(rtBufferCreate(ctx, RT_BUFFER_INPUT, &b), RT_SUCCESS);
  RTvariable v;
  ASSERT_EQ(rtProgramDeclareVariable(rg, "data", &v), RT_SUCCESS);
  ASSERT_EQ(rtVariableSetObject(v, b), RT_SUCCESS);
  ExpectInvalid(rtContextValidate(ctx), RT_ERROR_INVALID_CONTEXT,
                {"buffer #", "format is not set"});
  ASSERT_EQ(rtBufferSetFormat(b, RT_FORMAT_FLOAT), RT_SUCCESS);
  ExpectInvalid(rtContextCompile(ctx), RT_ERROR_INVALID_CONTEXT, {"size is not set"});
  ASSERT_EQ(rtBufferSetSize1D(b, 4), RT_SUCCESS);
  EXPECT_EQ(rtContextValidate(ctx), RT_SUCCESS);

  // A destroyed object that is still referenced is reported where it is used.
  ASSERT_EQ(rtBufferDestroy(b), RT_SUCCESS);
  ExpectInvalid(rtContextValidate(ctx), RT_ERROR_INVALID_CONTEXT,
                {"program #", "variable 'data' refers to destroyed buffer #"});
  RTobject still = nullptr;
  ASSERT_EQ(rtVariableGetObject(v, &still), RT_SUCCESS);  // memory-safe: the link holds it
  EXPECT_EQ(still, b);
  ASSERT_EQ(rtProgramRemoveVariable(rg, v), RT_SUCCESS);
  EXPECT_EQ(rtContextValidate(ctx), RT_SUCCESS);

  // Destroying a program that is an entry point's ray generation program.
  ASSERT_EQ(rtProgramDestroy(rg), RT_SUCCESS);
  ExpectInvalid(rtContextValidate(ctx), RT_ERROR_INVALID_CONTEXT,
                {"ray generation program for entry point 0 refers to destroyed program #"});
  RTprogram dangling = nullptr;
  ASSERT_EQ(rtContextGetRayGenerationProgram(ctx, 0, &dangling), RT_SUCCESS);
  EXPECT_EQ(dangling, rg);
}

TEST_F(HostGraphTest, CyclesAreReported) {
  RTgroup a, b;
  ASSERT_EQ(rtGroupCreate(ctx, &a), RT_SUCCESS);
  ASSERT_EQ(rtGroupCreate(ctx, &b), RT_SUCCESS);
  for (RTgroup g : {a, b}) {
    ASSERT_EQ(rtGroupSetAcceleration(g, Accel("NoAccel", "NoAccel")), RT_SUCCESS);
    ASSERT_EQ(rtGroupSetChildCount(g, 1), RT_SUCCESS);
  }
  RTtransform t;
  ASSERT_EQ(rtTransformCreate(ctx, &t), RT_SUCCESS);
  ASSERT_EQ(rtGroupSetChild(a, 0, t), RT_SUCCESS);
  ASSERT_EQ(rtTransformSetChild(t, b), RT_SUCCESS);
  ASSERT_EQ(rtGroupSetChild(b, 0, a), RT_SUCCESS);
  ExpectInvalid(rtGroupValidate(a), RT_ERROR_INVALID_VALUE, {"cycle"});
}

TEST_F(HostGraphTest, ChildRules) {
  RTgroup group;
  ASSERT_EQ(rtGroupCreate(ctx, &group), RT_SUCCESS);
  ASSERT_EQ(rtGroupSetChildCount(group, 1), RT_SUCCESS);
  RTgeometryinstance gi;
  ASSERT_EQ(rtGeometryInstanceCreate(ctx, &gi), RT_SUCCESS);
  ExpectInvalid(rtGroupSetChild(group, 0, gi), RT_ERROR_TYPE_MISMATCH,
                {"rtGroupSetChild(group #", "child is a geometry instance #"});
  RTgeometrygroup gg;
  ASSERT_EQ(rtGeometryGroupCreate(ctx, &gg), RT_SUCCESS);
  ASSERT_EQ(rtGeometryGroupSetChildCount(gg, 1), RT_SUCCESS);
  // Geometry groups take instances only: a group handle in that slot is a wrong-type handle.
  EXPECT_EQ(rtGeometryGroupSetChild(gg, 0, reinterpret_cast<RTgeometryinstance>(group)),
            RT_ERROR_INVALID_VALUE);
  // Shrinking child counts drops children.
  ASSERT_EQ(rtGroupSetChild(group, 0, gg), RT_SUCCESS);
  ASSERT_EQ(rtGroupSetChildCount(group, 0), RT_SUCCESS);
  RTobject child;
  EXPECT_EQ(rtGroupGetChild(group, 0, &child), RT_ERROR_INVALID_VALUE);
  // A destroyed child is memory-safe and reported.
  ASSERT_EQ(rtGroupSetChildCount(group, 1), RT_SUCCESS);
  ASSERT_EQ(rtGroupGetChild(group, 0, &child), RT_SUCCESS);
  EXPECT_EQ(child, nullptr);
  ASSERT_EQ(rtGroupSetChild(group, 0, gg), RT_SUCCESS);
  ASSERT_EQ(rtGeometryGroupDestroy(gg), RT_SUCCESS);
  ASSERT_EQ(rtGroupSetAcceleration(group, Accel()), RT_SUCCESS);
  ExpectInvalid(rtGroupValidate(group), RT_ERROR_INVALID_VALUE,
                {"child 0 refers to destroyed geometry group #"});
}

TEST_F(HostGraphTest, TransformMatrices) {
  RTtransform t;
  ASSERT_EQ(rtTransformCreate(ctx, &t), RT_SUCCESS);
  float m[16], inv[16];
  ASSERT_EQ(rtTransformGetMatrix(t, 0, m, inv), RT_SUCCESS);
  EXPECT_EQ(m[0], 1.0f);  // identity by default
  EXPECT_EQ(m[1], 0.0f);
  const float translate[16] = {1, 0, 0, 3, 0, 1, 0, 4, 0, 0, 1, 5, 0, 0, 0, 1};
  ASSERT_EQ(rtTransformSetMatrix(t, 0, translate, nullptr), RT_SUCCESS);
  ASSERT_EQ(rtTransformGetMatrix(t, 0, m, inv), RT_SUCCESS);
  EXPECT_EQ(m[3], 3.0f);
  EXPECT_EQ(inv[3], -3.0f);
  EXPECT_EQ(inv[7], -4.0f);
  ASSERT_EQ(rtTransformGetMatrix(t, 1, m, nullptr), RT_SUCCESS);
  EXPECT_EQ(m[12], 3.0f);  // transposed: column-major
  // Transposed input means the same matrix.
  float column_major[16];
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) column_major[c * 4 + r] = translate[r * 4 + c];
  }
  ASSERT_EQ(rtTransformSetMatrix(t, 1, column_major, nullptr), RT_SUCCESS);
  ASSERT_EQ(rtTransformGetMatrix(t, 0, m, nullptr), RT_SUCCESS);
  EXPECT_EQ(std::memcmp(m, translate, sizeof(m)), 0);
  // A given inverse is kept as given.
  const float scale[16] = {2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 1};
  const float given[16] = {0.5f, 0, 0, 0, 0, 0.5f, 0, 0, 0, 0, 0.5f, 0, 0, 0, 0, 1};
  ASSERT_EQ(rtTransformSetMatrix(t, 0, scale, given), RT_SUCCESS);
  ASSERT_EQ(rtTransformGetMatrix(t, 0, nullptr, inv), RT_SUCCESS);
  EXPECT_EQ(inv[0], 0.5f);
  // Singular without an inverse is refused; the old matrix stays.
  const float flat[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1};
  ExpectInvalid(rtTransformSetMatrix(t, 0, flat, nullptr), RT_ERROR_INVALID_VALUE,
                {"rtTransformSetMatrix(transform #", "singular"});
  ASSERT_EQ(rtTransformGetMatrix(t, 0, m, nullptr), RT_SUCCESS);
  EXPECT_EQ(m[0], 2.0f);
  ASSERT_EQ(rtTransformSetMatrix(t, 0, flat, given), RT_SUCCESS);  // with an inverse: accepted
}

// Properties travel to workers in a protobuf map<string, string>, which must be UTF-8.
TEST_F(HostGraphTest, AccelerationPropertiesMustBeUtf8) {
  RTacceleration a;
  ASSERT_EQ(rtAccelerationCreate(ctx, &a), RT_SUCCESS);
  ExpectInvalid(rtAccelerationSetProperty(a, "refit", "\xff"), RT_ERROR_INVALID_VALUE,
                {"rtAccelerationSetProperty(acceleration #", "property value is not valid UTF-8"});
  ExpectInvalid(rtAccelerationSetProperty(a, "\xc3\x28", "1"), RT_ERROR_INVALID_VALUE,
                {"property name is not valid UTF-8"});
  ExpectInvalid(rtAccelerationSetProperty(a, "x", "\xed\xa0\x80"), RT_ERROR_INVALID_VALUE,
                {"not valid UTF-8"});  // a surrogate
  EXPECT_EQ(rtAccelerationSetProperty(a, "vertex_buffer_name", "v\xc3\xa9rtices"), RT_SUCCESS);
  const char* s = nullptr;
  ASSERT_EQ(rtAccelerationGetProperty(a, "refit", &s), RT_SUCCESS);
  EXPECT_STREQ(s, "");
}

// Devices move rays with the top three rows only: a projective bottom row, or a matrix or given
// inverse that is not finite, is refused instead of tracing a scene other than the one set.
TEST_F(HostGraphTest, TransformMatricesMustBeAffineAndFinite) {
  RTtransform t;
  ASSERT_EQ(rtTransformCreate(ctx, &t), RT_SUCCESS);
  const float translate[16] = {1, 0, 0, 3, 0, 1, 0, 4, 0, 0, 1, 5, 0, 0, 0, 1};
  ASSERT_EQ(rtTransformSetMatrix(t, 0, translate, nullptr), RT_SUCCESS);
  const float projective[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0.5f, 1};
  ExpectInvalid(rtTransformSetMatrix(t, 0, projective, nullptr), RT_ERROR_INVALID_VALUE,
                {"rtTransformSetMatrix(transform #", "bottom row", "affine"});
  // A column-major matrix passed without transpose puts the translation in the bottom row.
  ExpectInvalid(rtTransformSetMatrix(t, 1, translate, nullptr), RT_ERROR_INVALID_VALUE,
                {"bottom row is (3, 4, 5, 1)"});
  const float nan[16] = {1, 0, 0, NAN, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  const float identity[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  ExpectInvalid(rtTransformSetMatrix(t, 0, nan, identity), RT_ERROR_INVALID_VALUE,
                {"matrix has an entry that is not finite"});
  ExpectInvalid(rtTransformSetMatrix(t, 0, identity, nan), RT_ERROR_INVALID_VALUE,
                {"inverse matrix has an entry that is not finite"});
  // An inverse with rounding in its bottom row is kept.
  const float rounded[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 1e-9f, 0, 0, 0.99999994f};
  EXPECT_EQ(rtTransformSetMatrix(t, 0, identity, rounded), RT_SUCCESS);
  float m[16];
  ASSERT_EQ(rtTransformGetMatrix(t, 0, m, nullptr), RT_SUCCESS);
  EXPECT_EQ(m[3], 0.0f);
}

TEST_F(HostGraphTest, AccelerationSettings) {
  RTacceleration a;
  ASSERT_EQ(rtAccelerationCreate(ctx, &a), RT_SUCCESS);
  const char* s = nullptr;
  ASSERT_EQ(rtAccelerationGetBuilder(a, &s), RT_SUCCESS);
  EXPECT_STREQ(s, "");
  for (const char* builder : {"Sbvh", "Bvh", "BvhCompact" /* not a builder */, "MedianBvh", "Lbvh",
                              "TriangleKdTree", "NoAccel", "Trbvh"}) {
    RTresult expected = std::string(builder) == "BvhCompact" ? RT_ERROR_INVALID_VALUE : RT_SUCCESS;
    EXPECT_EQ(rtAccelerationSetBuilder(a, builder), expected) << builder;
  }
  ASSERT_EQ(rtAccelerationGetBuilder(a, &s), RT_SUCCESS);
  EXPECT_STREQ(s, "Trbvh");
  ExpectInvalid(rtAccelerationSetBuilder(a, "Octree"), RT_ERROR_INVALID_VALUE,
                {"unknown builder 'Octree'"});
  for (const char* traverser : {"Bvh", "BvhCompact", "KdTree", "NoAccel"}) {
    EXPECT_EQ(rtAccelerationSetTraverser(a, traverser), RT_SUCCESS) << traverser;
  }
  EXPECT_EQ(rtAccelerationSetTraverser(a, "Sbvh"), RT_ERROR_INVALID_VALUE);
  ASSERT_EQ(rtAccelerationGetTraverser(a, &s), RT_SUCCESS);
  EXPECT_STREQ(s, "NoAccel");

  ASSERT_EQ(rtAccelerationSetProperty(a, "vertex_buffer_name", "verts"), RT_SUCCESS);
  ASSERT_EQ(rtAccelerationGetProperty(a, "vertex_buffer_name", &s), RT_SUCCESS);
  EXPECT_STREQ(s, "verts");
  ASSERT_EQ(rtAccelerationGetProperty(a, "refit", &s), RT_SUCCESS);
  EXPECT_STREQ(s, "");

  // A new acceleration is dirty: it has no data yet, and data that is not Tessera's is refused
  // without changing it (tests/semantics/acceleration_data_test.cc has the round trips).
  RTsize size = 99;
  EXPECT_EQ(rtAccelerationGetDataSize(a, &size), RT_ERROR_INVALID_VALUE);
  EXPECT_EQ(size, 99u);
  char out[4] = {};
  EXPECT_EQ(rtAccelerationGetData(a, out), RT_ERROR_INVALID_VALUE);
  const char blob[4] = {1, 2, 3, 4};
  EXPECT_EQ(rtAccelerationSetData(a, blob, sizeof(blob)), RT_ERROR_INVALID_VALUE);
  EXPECT_EQ(rtAccelerationSetData(a, nullptr, 0), RT_ERROR_INVALID_VALUE);
  int dirty = 0;
  ASSERT_EQ(rtAccelerationIsDirty(a, &dirty), RT_SUCCESS);
  EXPECT_EQ(dirty, 1);
  ASSERT_EQ(rtAccelerationGetBuilder(a, &s), RT_SUCCESS);
  EXPECT_STREQ(s, "Trbvh");
  ASSERT_EQ(rtAccelerationMarkDirty(a), RT_SUCCESS);
}

TEST_F(HostGraphTest, MaterialProgramsPerRayType) {
  RTmaterial m;
  ASSERT_EQ(rtMaterialCreate(ctx, &m), RT_SUCCESS);
  RTprogram ch = Program("closest_hit");
  RTprogram ah = Program("any_hit");
  ASSERT_EQ(rtMaterialSetClosestHitProgram(m, 0, ch), RT_SUCCESS);
  ASSERT_EQ(rtMaterialSetAnyHitProgram(m, 1, ah), RT_SUCCESS);
  RTprogram got;
  ASSERT_EQ(rtMaterialGetClosestHitProgram(m, 0, &got), RT_SUCCESS);
  EXPECT_EQ(got, ch);
  ASSERT_EQ(rtMaterialGetClosestHitProgram(m, 1, &got), RT_SUCCESS);
  EXPECT_EQ(got, nullptr);
  ASSERT_EQ(rtMaterialGetAnyHitProgram(m, 1, &got), RT_SUCCESS);
  EXPECT_EQ(got, ah);
  ExpectInvalid(rtMaterialSetAnyHitProgram(m, 2, ah), RT_ERROR_INVALID_VALUE,
                {"rtMaterialSetAnyHitProgram(material #", "ray type 2 is out of range"});
  EXPECT_EQ(rtMaterialValidate(m), RT_SUCCESS);
}

TEST_F(HostGraphTest, GettersReturnWhatWasSet) {
  RTgeometry g;
  ASSERT_EQ(rtGeometryCreate(ctx, &g), RT_SUCCESS);
  RTprogram is = Program("intersect");
  ASSERT_EQ(rtGeometrySetIntersectionProgram(g, is), RT_SUCCESS);
  RTprogram got;
  ASSERT_EQ(rtGeometryGetIntersectionProgram(g, &got), RT_SUCCESS);
  EXPECT_EQ(got, is);
  ASSERT_EQ(rtGeometryGetBoundingBoxProgram(g, &got), RT_SUCCESS);
  EXPECT_EQ(got, nullptr);
  ASSERT_EQ(rtGeometrySetPrimitiveCount(g, 42), RT_SUCCESS);
  unsigned n = 0;
  ASSERT_EQ(rtGeometryGetPrimitiveCount(g, &n), RT_SUCCESS);
  EXPECT_EQ(n, 42u);
  RTgeometryinstance gi;
  ASSERT_EQ(rtGeometryInstanceCreate(ctx, &gi), RT_SUCCESS);
  ASSERT_EQ(rtGeometryInstanceSetGeometry(gi, g), RT_SUCCESS);
  RTgeometry gg;
  ASSERT_EQ(rtGeometryInstanceGetGeometry(gi, &gg), RT_SUCCESS);
  EXPECT_EQ(gg, g);
  RTselector s;
  ASSERT_EQ(rtSelectorCreate(ctx, &s), RT_SUCCESS);
  RTprogram visit = Program("visit");
  ASSERT_EQ(rtSelectorSetVisitProgram(s, visit), RT_SUCCESS);
  ASSERT_EQ(rtSelectorGetVisitProgram(s, &got), RT_SUCCESS);
  EXPECT_EQ(got, visit);
  RTgroup group;
  ASSERT_EQ(rtGroupCreate(ctx, &group), RT_SUCCESS);
  RTacceleration a = Accel();
  ASSERT_EQ(rtGroupSetAcceleration(group, a), RT_SUCCESS);
  RTacceleration ga;
  ASSERT_EQ(rtGroupGetAcceleration(group, &ga), RT_SUCCESS);
  EXPECT_EQ(ga, a);
  RTcontext owner;
  ASSERT_EQ(rtGroupGetContext(group, &owner), RT_SUCCESS);
  EXPECT_EQ(owner, ctx);
}

}  // namespace
}  // namespace tessera::test

// Variables through the C API: declare/query/remove on every scope, set/get round trips of every
// type, names and the first-set-fixes-the-type rule.
#include <cstring>
#include <functional>
#include <vector>

#include "api_test_util.h"
#include "gtest/gtest.h"
#include "tessera/rt.h"

namespace tessera::test {
namespace {

class HostVariableTest : public ::testing::Test {
 protected:
  void SetUp() override { ASSERT_EQ(rtContextCreate(&ctx), RT_SUCCESS); }
  void TearDown() override { EXPECT_EQ(rtContextDestroy(ctx), RT_SUCCESS); }

  RTvariable Declare(const char* name) {
    RTvariable v = nullptr;
    EXPECT_EQ(rtContextDeclareVariable(ctx, name, &v), RT_SUCCESS);
    return v;
  }

  RTobjecttype TypeOf(RTvariable v) {
    RTobjecttype t = RT_OBJECTTYPE_UNKNOWN;
    EXPECT_EQ(rtVariableGetType(v, &t), RT_SUCCESS);
    return t;
  }

  RTsize SizeOf(RTvariable v) {
    RTsize s = 0;
    EXPECT_EQ(rtVariableGetSize(v, &s), RT_SUCCESS);
    return s;
  }

  RTcontext ctx = nullptr;
};

TEST_F(HostVariableTest, FloatIntUintRoundTrips) {
  RTvariable f1 = Declare("f1"), f2 = Declare("f2"), f3 = Declare("f3"), f4 = Declare("f4");
  ASSERT_EQ(rtVariableSet1f(f1, 1.5f), RT_SUCCESS);
  ASSERT_EQ(rtVariableSet2f(f2, 1, 2), RT_SUCCESS);
  ASSERT_EQ(rtVariableSet3f(f3, 1, 2, 3), RT_SUCCESS);
  ASSERT_EQ(rtVariableSet4f(f4, 1, 2, 3, 4), RT_SUCCESS);
  float a = 0, b = 0, c = 0, d = 0;
  ASSERT_EQ(rtVariableGet1f(f1, &a), RT_SUCCESS);
  EXPECT_EQ(a, 1.5f);
  ASSERT_EQ(rtVariableGet2f(f2, &a, &b), RT_SUCCESS);
  EXPECT_EQ(b, 2.0f);
  ASSERT_EQ(rtVariableGet3f(f3, &a, &b, &c), RT_SUCCESS);
  EXPECT_EQ(c, 3.0f);
  ASSERT_EQ(rtVariableGet4f(f4, &a, &b, &c, &d), RT_SUCCESS);
  EXPECT_EQ(d, 4.0f);
  float v4[4] = {};
  ASSERT_EQ(rtVariableGet4fv(f4, v4), RT_SUCCESS);
  EXPECT_EQ(v4[0], 1.0f);
  EXPECT_EQ(TypeOf(f3), RT_OBJECTTYPE_FLOAT3);
  EXPECT_EQ(SizeOf(f3), 12u);

  const int iv[4] = {-1, -2, -3, -4};
  RTvariable i[4] = {Declare("i1"), Declare("i2"), Declare("i3"), Declare("i4")};
  ASSERT_EQ(rtVariableSet1iv(i[0], iv), RT_SUCCESS);
  ASSERT_EQ(rtVariableSet2iv(i[1], iv), RT_SUCCESS);
  ASSERT_EQ(rtVariableSet3i(i[2], -1, -2, -3), RT_SUCCESS);
  ASSERT_EQ(rtVariableSet4iv(i[3], iv), RT_SUCCESS);
  int ia = 0, ib = 0, ic = 0, id = 0;
  ASSERT_EQ(rtVariableGet3i(i[2], &ia, &ib, &ic), RT_SUCCESS);
  EXPECT_EQ(ic, -3);
  ASSERT_EQ(rtVariableGet4i(i[3], &ia, &ib, &ic, &id), RT_SUCCESS);
  EXPECT_EQ(id, -4);
  int out[4] = {};
  ASSERT_EQ(rtVariableGet2iv(i[1], out), RT_SUCCESS);
  EXPECT_EQ(out[1], -2);
  ASSERT_EQ(rtVariableGet1i(i[0], &ia), RT_SUCCESS);
  EXPECT_EQ(ia, -1);
  EXPECT_EQ(TypeOf(i[3]), RT_OBJECTTYPE_INT4);

  const unsigned uv[4] = {7, 8, 9, 10};
  RTvariable u[4] = {Declare("u1"), Declare("u2"), Declare("u3"), Declare("u4")};
  ASSERT_EQ(rtVariableSet1ui(u[0], 7), RT_SUCCESS);
  ASSERT_EQ(rtVariableSet2ui(u[1], 7, 8), RT_SUCCESS);
  ASSERT_EQ(rtVariableSet3uiv(u[2], uv), RT_SUCCESS);
  ASSERT_EQ(rtVariableSet4ui(u[3], 7, 8, 9, 10), RT_SUCCESS);
  unsigned ua = 0, ub = 0, uc = 0, ud = 0;
  ASSERT_EQ(rtVariableGet4ui(u[3], &ua, &ub, &uc, &ud), RT_SUCCESS);
  EXPECT_EQ(ud, 10u);
  ASSERT_EQ(rtVariableGet2ui(u[1], &ua, &ub), RT_SUCCESS);
  EXPECT_EQ(ub, 8u);
  unsigned uout[4] = {};
  ASSERT_EQ(rtVariableGet3uiv(u[2], uout), RT_SUCCESS);
  EXPECT_EQ(uout[2], 9u);
  ASSERT_EQ(rtVariableGet1uiv(u[0], uout), RT_SUCCESS);
  EXPECT_EQ(uout[0], 7u);
  EXPECT_EQ(TypeOf(u[1]), RT_OBJECTTYPE_UNSIGNED_INT2);

  // The first Set fixed the type; the same type may be set again.
  ASSERT_EQ(rtVariableSet1f(f1, 2.5f), RT_SUCCESS);
  EXPECT_EQ(rtVariableSet1i(f1, 2), RT_ERROR_TYPE_MISMATCH);
}

TEST_F(HostVariableTest, AllMatrixShapesWithTranspose) {
  using SetFn = RTresult (*)(RTvariable, int, const float*);
  using GetFn = RTresult (*)(RTvariable, int, float*);
  struct Shape {
    int rows, cols;
    SetFn set;
    GetFn get;
    RTobjecttype type;
  };
  const Shape shapes[] = {
      {2, 2, rtVariableSetMatrix2x2fv, rtVariableGetMatrix2x2fv, RT_OBJECTTYPE_MATRIX_FLOAT2x2},
      {2, 3, rtVariableSetMatrix2x3fv, rtVariableGetMatrix2x3fv, RT_OBJECTTYPE_MATRIX_FLOAT2x3},
      {2, 4, rtVariableSetMatrix2x4fv, rtVariableGetMatrix2x4fv, RT_OBJECTTYPE_MATRIX_FLOAT2x4},
      {3, 2, rtVariableSetMatrix3x2fv, rtVariableGetMatrix3x2fv, RT_OBJECTTYPE_MATRIX_FLOAT3x2},
      {3, 3, rtVariableSetMatrix3x3fv, rtVariableGetMatrix3x3fv, RT_OBJECTTYPE_MATRIX_FLOAT3x3},
      {3, 4, rtVariableSetMatrix3x4fv, rtVariableGetMatrix3x4fv, RT_OBJECTTYPE_MATRIX_FLOAT3x4},
      {4, 2, rtVariableSetMatrix4x2fv, rtVariableGetMatrix4x2fv, RT_OBJECTTYPE_MATRIX_FLOAT4x2},
      {4, 3, rtVariableSetMatrix4x3fv, rtVariableGetMatrix4x3fv, RT_OBJECTTYPE_MATRIX_FLOAT4x3},
      {4, 4, rtVariableSetMatrix4x4fv, rtVariableGetMatrix4x4fv, RT_OBJECTTYPE_MATRIX_FLOAT4x4},
  };
  int n = 0;
  for (const Shape& s : shapes) {
    std::string name = "m" + std::to_string(n++);
    RTvariable v = Declare(name.c_str());
    std::vector<float> rows(s.rows * s.cols);
    for (size_t i = 0; i < rows.size(); ++i) rows[i] = static_cast<float>(i + 1);
    ASSERT_EQ(s.set(v, 0, rows.data()), RT_SUCCESS);
    EXPECT_EQ(TypeOf(v), s.type);
    EXPECT_EQ(SizeOf(v), rows.size() * sizeof(float));
    std::vector<float> got(rows.size()), transposed(rows.size());
    ASSERT_EQ(s.get(v, 0, got.data()), RT_SUCCESS);
    EXPECT_EQ(got, rows);
    ASSERT_EQ(s.get(v, 1, transposed.data()), RT_SUCCESS);
    for (int r = 0; r < s.rows; ++r) {
      for (int c = 0; c < s.cols; ++c) {
        EXPECT_EQ(transposed[c * s.rows + r], rows[r * s.cols + c]);
      }
    }
    // Setting the transposed form stores the same matrix.
    ASSERT_EQ(s.set(v, 1, transposed.data()), RT_SUCCESS);
    ASSERT_EQ(s.get(v, 0, got.data()), RT_SUCCESS);
    EXPECT_EQ(got, rows);
  }
  // Shapes are distinct types.
  RTvariable m22 = Declare("square");
  const float m[16] = {};
  ASSERT_EQ(rtVariableSetMatrix2x2fv(m22, 0, m), RT_SUCCESS);
  EXPECT_EQ(rtVariableSetMatrix4x4fv(m22, 0, m), RT_ERROR_TYPE_MISMATCH);
}

TEST_F(HostVariableTest, ObjectsAndUserData) {
  RTbuffer buffer;
  ASSERT_EQ(rtBufferCreate(ctx, RT_BUFFER_INPUT, &buffer), RT_SUCCESS);
  RTgroup group;
  ASSERT_EQ(rtGroupCreate(ctx, &group), RT_SUCCESS);
  RTtransform transform;
  ASSERT_EQ(rtTransformCreate(ctx, &transform), RT_SUCCESS);
  RTprogram program;
  ASSERT_EQ(rtProgramCreateFromPTXFile(ctx, kTestModule, "miss", &program), RT_SUCCESS);

  RTvariable b = Declare("b");
  ASSERT_EQ(rtVariableSetObject(b, buffer), RT_SUCCESS);
  RTobject got = nullptr;
  ASSERT_EQ(rtVariableGetObject(b, &got), RT_SUCCESS);
  EXPECT_EQ(got, buffer);
  EXPECT_EQ(TypeOf(b), RT_OBJECTTYPE_BUFFER);

  // Node variables may switch between node kinds (top_object = group or transform …).
  RTvariable top = Declare("top_object");
  ASSERT_EQ(rtVariableSetObject(top, group), RT_SUCCESS);
  EXPECT_EQ(TypeOf(top), RT_OBJECTTYPE_GROUP);
  ASSERT_EQ(rtVariableSetObject(top, transform), RT_SUCCESS);
  EXPECT_EQ(TypeOf(top), RT_OBJECTTYPE_TRANSFORM);
  ASSERT_EQ(rtVariableGetObject(top, &got), RT_SUCCESS);
  EXPECT_EQ(got, transform);

  RTvariable p = Declare("callable");
  ASSERT_EQ(rtVariableSetObject(p, program), RT_SUCCESS);
  EXPECT_EQ(TypeOf(p), RT_OBJECTTYPE_PROGRAM);

  struct Light {
    float pos[3];
    int kind;
    double power;
  } light = {{1, 2, 3}, 4, 5.5};
  RTvariable u = Declare("light");
  ASSERT_EQ(rtVariableSetUserData(u, sizeof(light), &light), RT_SUCCESS);
  EXPECT_EQ(TypeOf(u), RT_OBJECTTYPE_USER);
  EXPECT_EQ(SizeOf(u), sizeof(light));
  Light back{};
  ASSERT_EQ(rtVariableGetUserData(u, sizeof(back), &back), RT_SUCCESS);
  EXPECT_EQ(back.kind, 4);
  EXPECT_EQ(back.power, 5.5);
  EXPECT_EQ(rtVariableGetUserData(u, 3, &back), RT_ERROR_INVALID_VALUE);
  std::vector<unsigned char> big(1 << 16, 0x5A);
  ASSERT_EQ(rtVariableSetUserData(u, big.size(), big.data()), RT_SUCCESS);  // any size
  EXPECT_EQ(SizeOf(u), big.size());
}

TEST_F(HostVariableTest, DeclareQueryRemoveOnEveryScope) {
  RTprogram program;
  ASSERT_EQ(rtProgramCreateFromPTXFile(ctx, kTestModule, "ray_gen", &program), RT_SUCCESS);
  RTgeometry geometry;
  ASSERT_EQ(rtGeometryCreate(ctx, &geometry), RT_SUCCESS);
  RTgeometryinstance instance;
  ASSERT_EQ(rtGeometryInstanceCreate(ctx, &instance), RT_SUCCESS);
  RTmaterial material;
  ASSERT_EQ(rtMaterialCreate(ctx, &material), RT_SUCCESS);
  RTselector selector;
  ASSERT_EQ(rtSelectorCreate(ctx, &selector), RT_SUCCESS);

  struct Scope {
    const char* name;
    std::function<RTresult(const char*, RTvariable*)> declare, query;
    std::function<RTresult(RTvariable)> remove;
    std::function<RTresult(unsigned*)> count;
    std::function<RTresult(unsigned, RTvariable*)> get;
  };
  const std::vector<Scope> scopes = {
      {"context", [&](const char* n, RTvariable* v) { return rtContextDeclareVariable(ctx, n, v); },
       [&](const char* n, RTvariable* v) { return rtContextQueryVariable(ctx, n, v); },
       [&](RTvariable v) { return rtContextRemoveVariable(ctx, v); },
       [&](unsigned* c) { return rtContextGetVariableCount(ctx, c); },
       [&](unsigned i, RTvariable* v) { return rtContextGetVariable(ctx, i, v); }},
      {"program",
       [&](const char* n, RTvariable* v) { return rtProgramDeclareVariable(program, n, v); },
       [&](const char* n, RTvariable* v) { return rtProgramQueryVariable(program, n, v); },
       [&](RTvariable v) { return rtProgramRemoveVariable(program, v); },
       [&](unsigned* c) { return rtProgramGetVariableCount(program, c); },
       [&](unsigned i, RTvariable* v) { return rtProgramGetVariable(program, i, v); }},
      {"geometry",
       [&](const char* n, RTvariable* v) { return rtGeometryDeclareVariable(geometry, n, v); },
       [&](const char* n, RTvariable* v) { return rtGeometryQueryVariable(geometry, n, v); },
       [&](RTvariable v) { return rtGeometryRemoveVariable(geometry, v); },
       [&](unsigned* c) { return rtGeometryGetVariableCount(geometry, c); },
       [&](unsigned i, RTvariable* v) { return rtGeometryGetVariable(geometry, i, v); }},
      {"geometry instance",
       [&](const char* n, RTvariable* v) {
         return rtGeometryInstanceDeclareVariable(instance, n, v);
       },
       [&](const char* n, RTvariable* v) {
         return rtGeometryInstanceQueryVariable(instance, n, v);
       },
       [&](RTvariable v) { return rtGeometryInstanceRemoveVariable(instance, v); },
       [&](unsigned* c) { return rtGeometryInstanceGetVariableCount(instance, c); },
       [&](unsigned i, RTvariable* v) { return rtGeometryInstanceGetVariable(instance, i, v); }},
      {"material",
       [&](const char* n, RTvariable* v) { return rtMaterialDeclareVariable(material, n, v); },
       [&](const char* n, RTvariable* v) { return rtMaterialQueryVariable(material, n, v); },
       [&](RTvariable v) { return rtMaterialRemoveVariable(material, v); },
       [&](unsigned* c) { return rtMaterialGetVariableCount(material, c); },
       [&](unsigned i, RTvariable* v) { return rtMaterialGetVariable(material, i, v); }},
      {"selector",
       [&](const char* n, RTvariable* v) { return rtSelectorDeclareVariable(selector, n, v); },
       [&](const char* n, RTvariable* v) { return rtSelectorQueryVariable(selector, n, v); },
       [&](RTvariable v) { return rtSelectorRemoveVariable(selector, v); },
       [&](unsigned* c) { return rtSelectorGetVariableCount(selector, c); },
       [&](unsigned i, RTvariable* v) { return rtSelectorGetVariable(selector, i, v); }},
  };
  for (const Scope& s : scopes) {
    SCOPED_TRACE(s.name);
    RTvariable a = nullptr, b = nullptr, q = nullptr;
    ASSERT_EQ(s.declare("alpha", &a), RT_SUCCESS);
    ASSERT_EQ(s.declare("ns::beta_2", &b), RT_SUCCESS);
    EXPECT_EQ(s.declare("alpha", &q), RT_ERROR_VARIABLE_REDECLARED);
    EXPECT_NE(ErrorString(ctx, RT_ERROR_VARIABLE_REDECLARED).find("'alpha'"), std::string::npos);
    for (const char* bad : {"", "1x", "a-b", "a b", "a::", "::a", "a:::b"}) {
      EXPECT_EQ(s.declare(bad, &q), RT_ERROR_ILLEGAL_SYMBOL) << "'" << bad << "'";
    }
    unsigned count = 0;
    ASSERT_EQ(s.count(&count), RT_SUCCESS);
    EXPECT_EQ(count, 2u);
    ASSERT_EQ(s.get(1, &q), RT_SUCCESS);
    EXPECT_EQ(q, b);
    ASSERT_EQ(s.query("alpha", &q), RT_SUCCESS);
    EXPECT_EQ(q, a);
    ASSERT_EQ(s.query("missing", &q), RT_SUCCESS);
    EXPECT_EQ(q, nullptr);  // OptiX: unknown names are not an error
    const char* name = nullptr;
    ASSERT_EQ(rtVariableGetName(b, &name), RT_SUCCESS);
    EXPECT_STREQ(name, "ns::beta_2");
    const char* annotation = nullptr;
    ASSERT_EQ(rtVariableGetAnnotation(b, &annotation), RT_SUCCESS);
    EXPECT_STREQ(annotation, "");
    RTcontext owner = nullptr;
    ASSERT_EQ(rtVariableGetContext(b, &owner), RT_SUCCESS);
    EXPECT_EQ(owner, ctx);
    EXPECT_EQ(TypeOf(b), RT_OBJECTTYPE_UNKNOWN);
    EXPECT_EQ(SizeOf(b), 0u);

    ASSERT_EQ(s.remove(a), RT_SUCCESS);
    EXPECT_EQ(s.remove(a), RT_ERROR_INVALID_VALUE);  // the handle is gone
    ASSERT_EQ(s.count(&count), RT_SUCCESS);
    EXPECT_EQ(count, 1u);
    EXPECT_EQ(rtVariableSet1f(a, 1), RT_ERROR_INVALID_VALUE);
    EXPECT_NE(ErrorString(ctx, RT_ERROR_INVALID_VALUE).find("destroyed variable"),
              std::string::npos);
  }
  // A variable of another scope is not found here.
  RTvariable on_material = nullptr;
  ASSERT_EQ(rtMaterialQueryVariable(material, "ns::beta_2", &on_material), RT_SUCCESS);
  EXPECT_EQ(rtGeometryRemoveVariable(geometry, on_material), RT_ERROR_VARIABLE_NOT_FOUND);
  EXPECT_NE(ErrorString(ctx, RT_ERROR_VARIABLE_NOT_FOUND).find("geometry #"), std::string::npos);
}

TEST_F(HostVariableTest, DestroyingTheScopeDestroysItsVariables) {
  RTmaterial material;
  ASSERT_EQ(rtMaterialCreate(ctx, &material), RT_SUCCESS);
  RTvariable v;
  ASSERT_EQ(rtMaterialDeclareVariable(material, "kd", &v), RT_SUCCESS);
  ASSERT_EQ(rtMaterialDestroy(material), RT_SUCCESS);
  float f;
  EXPECT_EQ(rtVariableGet1f(v, &f), RT_ERROR_INVALID_VALUE);
}

}  // namespace
}  // namespace tessera::test

// OptiXpp (optixu/optixpp_namespace.h) over libtessera: handle lifetime, variables through
// operator[], every setter/getter pair, errors as optix::Exception, and a render through OptiXpp
// that must match the same scene built through the C API bit for bit.
#include <optixu/optixpp_namespace.h>
// The rest of what SDK host code includes, after the wrapper, to check that they mix.
#include <optix_world.h>
#include <optixu/optixpp.h>
#include <optixu/optixu_math_namespace.h>

#include <cstring>
#include <string>
#include <vector>

#include "api_test_util.h"
#include "gtest/gtest.h"
#include "tessera/rt.h"
#include "tessera/rt_ext.h"

namespace tessera::test {
namespace {

const std::string kModule = std::string(TESSERA_TEST_MODULE_DIR) + "/optixpp_programs.so";

long LiveWrappers() { return optix::optixpp_detail::LiveObjectCount().load(); }

// Runs `body`, which must throw optix::Exception with `code`; returns the exception's message.
template <class Body>
std::string ExpectThrows(RTresult code, Body body) {
  try {
    body();
  } catch (const optix::Exception& e) {
    EXPECT_EQ(e.getErrorCode(), code) << e.getErrorString();
    EXPECT_STREQ(e.what(), e.getErrorString().c_str());
    return e.getErrorString();
  }
  ADD_FAILURE() << "no optix::Exception thrown";
  return "";
}

class OptixppTest : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_NO_THROW(ctx_ = optix::Context::create());
    ctx_->setRayTypeCount(1);
    ctx_->setEntryPointCount(1);
  }
  void TearDown() override {
    if (ctx_) ctx_->destroy();
  }

  optix::Program Prog(const char* name) { return ctx_->createProgramFromPTXFile(kModule, name); }

  ScopedEnv devices_{"TESSERA_DEVICES", "inproc"};
  optix::Context ctx_;
};

// ---- Handles ----------------------------------------------------------------------------------

TEST_F(OptixppTest, LastHandleDeletesTheWrapperNotTheApiObject) {
  const long before = LiveWrappers();
  RTbuffer raw = nullptr;
  {
    optix::Buffer a = ctx_->createBuffer(RT_BUFFER_INPUT, RT_FORMAT_FLOAT);
    raw = a->get();
    EXPECT_EQ(LiveWrappers(), before + 1);
    optix::Buffer b = a;  // copy: same wrapper, one more reference
    EXPECT_EQ(b.get(), a.get());
    EXPECT_EQ(LiveWrappers(), before + 1);
    optix::Buffer c = std::move(b);
    EXPECT_FALSE(b);  // NOLINT(bugprone-use-after-move): moved-from handles are null
    EXPECT_EQ(c.get(), a.get());
    a = optix::Buffer();
    EXPECT_EQ(LiveWrappers(), before + 1);  // c still holds it
    c = 0;                                  // the OptiX idiom for letting go
    EXPECT_EQ(LiveWrappers(), before);
  }
  EXPECT_EQ(LiveWrappers(), before);
  // The buffer itself lives on until destroyed, as in OptiX.
  RTformat format = RT_FORMAT_UNKNOWN;
  EXPECT_EQ(rtBufferGetFormat(raw, &format), RT_SUCCESS);
  EXPECT_EQ(format, RT_FORMAT_FLOAT);
  optix::Buffer again = optix::Buffer::take(raw);
  again->destroy();
  EXPECT_EQ(rtBufferGetFormat(raw, &format), RT_ERROR_INVALID_VALUE);
}

TEST_F(OptixppTest, SelfAssignmentAndTemporariesKeepCounts) {
  const long before = LiveWrappers();
  optix::Material m = ctx_->createMaterial();
  optix::Material& alias = m;
  m = alias;
  EXPECT_TRUE(m);
  EXPECT_EQ(LiveWrappers(), before + 1);
  // A temporary handle attached to the graph: the instance keeps working after it is gone.
  optix::GeometryGroup gg = ctx_->createGeometryGroup();
  gg->addChild(ctx_->createGeometryInstance());
  EXPECT_EQ(gg->getChildCount(), 1u);
  EXPECT_NO_THROW(gg->getChild(0)->setMaterialCount(1));
  EXPECT_EQ(gg->getChild(0)->getMaterialCount(), 1u);
}

TEST_F(OptixppTest, TakeWrapsCApiObjectsAndGetReturnsThem) {
  RTtransform raw = nullptr;
  ASSERT_EQ(rtTransformCreate(ctx_->get(), &raw), RT_SUCCESS);
  optix::Transform t = optix::Transform::take(raw);
  EXPECT_EQ(t->get(), raw);
  optix::Transform t2 = optix::Transform::take(raw);
  EXPECT_NE(t.get(), t2.get());  // two wrappers ...
  EXPECT_TRUE(t == t2);          // ... of one object compare equal
  EXPECT_EQ(t->getContext(), ctx_);
  EXPECT_EQ(t->getContext()->get(), ctx_->get());
  // The guide's example: destroying through the C API with get().
  EXPECT_EQ(rtTransformDestroy(t->get()), RT_SUCCESS);
  EXPECT_EQ(rtTransformValidate(raw), RT_ERROR_INVALID_VALUE);

  EXPECT_FALSE(optix::Transform::take(static_cast<RTtransform>(nullptr)));
  optix::Transform null_handle;
  EXPECT_FALSE(null_handle);
  EXPECT_TRUE(null_handle == optix::Transform());
  EXPECT_FALSE(null_handle == t);
  ExpectThrows(RT_ERROR_INVALID_VALUE, [&] { null_handle->getChildType(); });
}

TEST_F(OptixppTest, ContextCreateDestroyAndUseAfterDestroy) {
  optix::Context c = optix::Context::create();
  RTcontext raw = c->get();
  unsigned int count = 0;
  EXPECT_EQ(rtContextGetRayTypeCount(raw, &count), RT_SUCCESS);
  EXPECT_EQ(c->getContext(), c);
  c->destroy();
  EXPECT_EQ(rtContextGetRayTypeCount(raw, &count), RT_ERROR_INVALID_CONTEXT);
  const std::string message = ExpectThrows(RT_ERROR_INVALID_CONTEXT, [&] { c->getRayTypeCount(); });
  EXPECT_EQ(message, ErrorString(raw, RT_ERROR_INVALID_CONTEXT));
  EXPECT_NE(message.find("rtContextGetRayTypeCount"), std::string::npos) << message;
}

TEST_F(OptixppTest, OptixuNamespaceNamesTheSameClasses) {
  optixu::Context same = ctx_;
  EXPECT_EQ(same.get(), ctx_.get());
  optixu::Buffer b = ctx_->createBuffer(RT_BUFFER_INPUT);
  optix::Buffer c = b;
  EXPECT_TRUE(b == c);
  static_assert(std::is_same<optixu::Variable, optix::Variable>::value, "one type");
  static_assert(std::is_same<optixu::Exception, optix::Exception>::value, "one type");
}

// ---- Scoped objects and operator[] ------------------------------------------------------------

// operator[], declare/query/remove/count/get on one scoped object.
template <class Scoped>
void CheckScope(Scoped object) {
  const unsigned int start = object->getVariableCount();
  optix::Variable a = object["value"];
  optix::Variable b = object["value"];
  optix::Variable c = object[std::string("value")];
  EXPECT_TRUE(a);
  EXPECT_TRUE(a == b);
  EXPECT_TRUE(a == c);
  EXPECT_EQ(object->getVariableCount(), start + 1);
  EXPECT_EQ(a->getName(), "value");
  EXPECT_EQ(object->queryVariable("value"), a);
  EXPECT_FALSE(object->queryVariable("nothing_here"));
  EXPECT_EQ(object->getVariable(start), a);
  ExpectThrows(RT_ERROR_VARIABLE_REDECLARED, [&] { object->declareVariable("value"); });
  ExpectThrows(RT_ERROR_ILLEGAL_SYMBOL, [&] { object["not a name"]; });
  optix::Variable d = object->declareVariable("other");
  EXPECT_EQ(object->getVariableCount(), start + 2);
  object->removeVariable(a);
  EXPECT_EQ(object->getVariableCount(), start + 1);
  EXPECT_FALSE(object->queryVariable("value"));
  EXPECT_EQ(object->getVariable(start), d);
  ExpectThrows(RT_ERROR_INVALID_VALUE, [&] { object->getVariable(start + 1); });
}

TEST_F(OptixppTest, OperatorBracketDeclaresOnceOnEveryScope) {
  CheckScope(ctx_);
  CheckScope(Prog("miss"));
  CheckScope(ctx_->createGeometry());
  CheckScope(ctx_->createGeometryTriangles());
  CheckScope(ctx_->createGeometryInstance());
  CheckScope(ctx_->createMaterial());
  CheckScope(ctx_->createSelector());
}

TEST_F(OptixppTest, ScopedObjWorksThroughTheBaseClass) {
  optix::Material m = ctx_->createMaterial();
  optix::ScopedObj& scope = *m;
  scope["Kd"]->setFloat(1.f, 2.f, 3.f);
  EXPECT_EQ(scope.getVariableCount(), 1u);
  EXPECT_EQ(m["Kd"]->getFloat3().z, 3.f);
  optix::DestroyableObj& destroyable = *m;
  destroyable.destroy();
  ExpectThrows(RT_ERROR_INVALID_VALUE, [&] { m->getVariableCount(); });
}

// ---- Variables --------------------------------------------------------------------------------

TEST_F(OptixppTest, FloatSettersRoundTrip) {
  ctx_["f1"]->setFloat(1.5f);
  EXPECT_EQ(ctx_["f1"]->getFloat(), 1.5f);
  EXPECT_EQ(ctx_["f1"]->getType(), RT_OBJECTTYPE_FLOAT);
  EXPECT_EQ(ctx_["f1"]->getSize(), sizeof(float));
  ctx_["f2"]->setFloat(1.f, 2.f);
  EXPECT_EQ(ctx_["f2"]->getFloat2().y, 2.f);
  ctx_["f3"]->setFloat(1.f, 2.f, 3.f);
  const optix::float3 f3 = ctx_["f3"]->getFloat3();
  EXPECT_EQ(f3.x, 1.f);
  EXPECT_EQ(f3.y, 2.f);
  EXPECT_EQ(f3.z, 3.f);
  EXPECT_EQ(ctx_["f3"]->getType(), RT_OBJECTTYPE_FLOAT3);
  ctx_["f4"]->setFloat(1.f, 2.f, 3.f, 4.f);
  EXPECT_EQ(ctx_["f4"]->getFloat4().w, 4.f);

  ctx_["v2"]->setFloat(optix::make_float2(5.f, 6.f));
  ctx_["v3"]->setFloat(optix::make_float3(5.f, 6.f, 7.f));
  ctx_["v4"]->setFloat(make_float4(5.f, 6.f, 7.f, 8.f));
  float a = 0, b = 0, c = 0, d = 0;
  ctx_["v2"]->getFloat(a, b);
  EXPECT_EQ(a, 5.f);
  EXPECT_EQ(b, 6.f);
  ctx_["v3"]->getFloat(a, b, c);
  EXPECT_EQ(c, 7.f);
  ctx_["v4"]->getFloat(a, b, c, d);
  EXPECT_EQ(d, 8.f);
  ctx_["f1"]->getFloat(a);
  EXPECT_EQ(a, 1.5f);

  const float in[4] = {9.f, 10.f, 11.f, 12.f};
  float out[4] = {};
  ctx_["fv1"]->set1fv(in);
  ctx_["fv1"]->get1fv(out);
  EXPECT_EQ(out[0], 9.f);
  ctx_["fv2"]->set2fv(in);
  ctx_["fv2"]->get2fv(out);
  EXPECT_EQ(out[1], 10.f);
  ctx_["fv3"]->set3fv(in);
  ctx_["fv3"]->get3fv(out);
  EXPECT_EQ(out[2], 11.f);
  ctx_["fv4"]->set4fv(in);
  std::memset(out, 0, sizeof(out));
  ctx_["fv4"]->get4fv(out);
  EXPECT_EQ(std::vector<float>(out, out + 4), std::vector<float>(in, in + 4));
  EXPECT_EQ(ctx_["fv4"]->getType(), RT_OBJECTTYPE_FLOAT4);
}

TEST_F(OptixppTest, IntAndUintSettersRoundTrip) {
  ctx_["i1"]->setInt(-1);
  EXPECT_EQ(ctx_["i1"]->getInt(), -1);
  ctx_["i2"]->setInt(-1, -2);
  EXPECT_EQ(ctx_["i2"]->getInt2().y, -2);
  ctx_["i3"]->setInt(512, 512, 1024);  // the guide's example
  EXPECT_EQ(ctx_["i3"]->getInt3().z, 1024);
  ctx_["i4"]->setInt(1, 2, 3, -4);
  EXPECT_EQ(ctx_["i4"]->getInt4().w, -4);
  ctx_["iv2"]->setInt(make_int2(7, 8));
  ctx_["iv3"]->setInt(make_int3(7, 8, 9));
  ctx_["iv4"]->setInt(make_int4(7, 8, 9, 10));
  int a = 0, b = 0, c = 0, d = 0;
  ctx_["i1"]->getInt(a);
  EXPECT_EQ(a, -1);
  ctx_["iv2"]->getInt(a, b);
  EXPECT_EQ(b, 8);
  ctx_["iv3"]->getInt(a, b, c);
  EXPECT_EQ(c, 9);
  ctx_["iv4"]->getInt(a, b, c, d);
  EXPECT_EQ(d, 10);
  EXPECT_EQ(ctx_["iv4"]->getType(), RT_OBJECTTYPE_INT4);
  const int iin[4] = {-5, -6, -7, -8};
  int iout[4] = {};
  ctx_["ivv1"]->set1iv(iin);
  ctx_["ivv1"]->get1iv(iout);
  EXPECT_EQ(iout[0], -5);
  ctx_["ivv2"]->set2iv(iin);
  ctx_["ivv2"]->get2iv(iout);
  EXPECT_EQ(iout[1], -6);
  ctx_["ivv3"]->set3iv(iin);
  ctx_["ivv3"]->get3iv(iout);
  EXPECT_EQ(iout[2], -7);
  ctx_["ivv4"]->set4iv(iin);
  ctx_["ivv4"]->get4iv(iout);
  EXPECT_EQ(iout[3], -8);

  ctx_["u1"]->setUint(4000000000u);
  EXPECT_EQ(ctx_["u1"]->getUint(), 4000000000u);
  EXPECT_EQ(ctx_["u1"]->getType(), RT_OBJECTTYPE_UNSIGNED_INT);
  ctx_["u2"]->setUint(1u, 2u);
  EXPECT_EQ(ctx_["u2"]->getUint2().y, 2u);
  ctx_["u3"]->setUint(1u, 2u, 3u);
  EXPECT_EQ(ctx_["u3"]->getUint3().z, 3u);
  ctx_["u4"]->setUint(1u, 2u, 3u, 4u);
  EXPECT_EQ(ctx_["u4"]->getUint4().w, 4u);
  ctx_["uv2"]->setUint(make_uint2(11, 12));
  ctx_["uv3"]->setUint(make_uint3(11, 12, 13));
  ctx_["uv4"]->setUint(make_uint4(11, 12, 13, 14));
  unsigned int ua = 0, ub = 0, uc = 0, ud = 0;
  ctx_["u1"]->getUint(ua);
  EXPECT_EQ(ua, 4000000000u);
  ctx_["uv2"]->getUint(ua, ub);
  EXPECT_EQ(ub, 12u);
  ctx_["uv3"]->getUint(ua, ub, uc);
  EXPECT_EQ(uc, 13u);
  ctx_["uv4"]->getUint(ua, ub, uc, ud);
  EXPECT_EQ(ud, 14u);
  const unsigned int uin[4] = {21, 22, 23, 24};
  unsigned int uout[4] = {};
  ctx_["uvv1"]->set1uiv(uin);
  ctx_["uvv1"]->get1uiv(uout);
  EXPECT_EQ(uout[0], 21u);
  ctx_["uvv2"]->set2uiv(uin);
  ctx_["uvv2"]->get2uiv(uout);
  EXPECT_EQ(uout[1], 22u);
  ctx_["uvv3"]->set3uiv(uin);
  ctx_["uvv3"]->get3uiv(uout);
  EXPECT_EQ(uout[2], 23u);
  ctx_["uvv4"]->set4uiv(uin);
  ctx_["uvv4"]->get4uiv(uout);
  EXPECT_EQ(uout[3], 24u);
}

TEST_F(OptixppTest, MatrixSettersRoundTripWithTranspose) {
  using Setter = void (optix::VariableObj::*)(bool, const float*);
  using Getter = void (optix::VariableObj::*)(bool, float*) const;
  struct Case {
    const char* name;
    int rows, cols;
    Setter set;
    Getter get;
    RTobjecttype type;
  };
  const Case cases[] = {
      {"m22", 2, 2, &optix::VariableObj::setMatrix2x2fv, &optix::VariableObj::getMatrix2x2fv,
       RT_OBJECTTYPE_MATRIX_FLOAT2x2},
      {"m23", 2, 3, &optix::VariableObj::setMatrix2x3fv, &optix::VariableObj::getMatrix2x3fv,
       RT_OBJECTTYPE_MATRIX_FLOAT2x3},
      {"m24", 2, 4, &optix::VariableObj::setMatrix2x4fv, &optix::VariableObj::getMatrix2x4fv,
       RT_OBJECTTYPE_MATRIX_FLOAT2x4},
      {"m32", 3, 2, &optix::VariableObj::setMatrix3x2fv, &optix::VariableObj::getMatrix3x2fv,
       RT_OBJECTTYPE_MATRIX_FLOAT3x2},
      {"m33", 3, 3, &optix::VariableObj::setMatrix3x3fv, &optix::VariableObj::getMatrix3x3fv,
       RT_OBJECTTYPE_MATRIX_FLOAT3x3},
      {"m34", 3, 4, &optix::VariableObj::setMatrix3x4fv, &optix::VariableObj::getMatrix3x4fv,
       RT_OBJECTTYPE_MATRIX_FLOAT3x4},
      {"m42", 4, 2, &optix::VariableObj::setMatrix4x2fv, &optix::VariableObj::getMatrix4x2fv,
       RT_OBJECTTYPE_MATRIX_FLOAT4x2},
      {"m43", 4, 3, &optix::VariableObj::setMatrix4x3fv, &optix::VariableObj::getMatrix4x3fv,
       RT_OBJECTTYPE_MATRIX_FLOAT4x3},
      {"m44", 4, 4, &optix::VariableObj::setMatrix4x4fv, &optix::VariableObj::getMatrix4x4fv,
       RT_OBJECTTYPE_MATRIX_FLOAT4x4},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const int n = c.rows * c.cols;
    std::vector<float> m(n), out(n), transposed(n);
    for (int i = 0; i < n; ++i) m[i] = 1.f + i;
    optix::Variable v = ctx_[c.name];
    ((*v).*c.set)(false, m.data());
    EXPECT_EQ(v->getType(), c.type);
    EXPECT_EQ(v->getSize(), n * sizeof(float));
    ((*v).*c.get)(false, out.data());
    EXPECT_EQ(out, m);
    // Set transposed (the input is cols x rows, row-major), read back untransposed.
    for (int r = 0; r < c.rows; ++r) {
      for (int col = 0; col < c.cols; ++col) transposed[col * c.rows + r] = m[r * c.cols + col];
    }
    ((*v).*c.set)(true, transposed.data());
    ((*v).*c.get)(false, out.data());
    EXPECT_EQ(out, m);
    ((*v).*c.get)(true, out.data());
    EXPECT_EQ(out, transposed);
  }
}

TEST_F(OptixppTest, ObjectAndUserDataVariablesRoundTrip) {
  optix::Buffer buffer = ctx_->createBuffer(RT_BUFFER_INPUT, RT_FORMAT_FLOAT, 4);
  optix::Program program = Prog("miss");
  optix::Group group = ctx_->createGroup();
  optix::GeometryGroup gg = ctx_->createGeometryGroup();
  optix::Transform transform = ctx_->createTransform();
  optix::Selector selector = ctx_->createSelector();

  ctx_["buffer"]->set(buffer);
  EXPECT_EQ(ctx_["buffer"]->getType(), RT_OBJECTTYPE_BUFFER);
  EXPECT_EQ(ctx_["buffer"]->getBuffer(), buffer);
  ctx_["buffer2"]->setBuffer(buffer);
  EXPECT_EQ(ctx_["buffer2"]->getBuffer()->get(), buffer->get());
  ctx_["program"]->set(program);
  EXPECT_EQ(ctx_["program"]->getType(), RT_OBJECTTYPE_PROGRAM);
  EXPECT_EQ(ctx_["program"]->getProgram(), program);

  // Node kinds may replace each other in one variable.
  optix::Variable node = ctx_["top_object"];
  node->set(group);
  EXPECT_EQ(node->getType(), RT_OBJECTTYPE_GROUP);
  EXPECT_EQ(node->getGroup(), group);
  node->set(gg);
  EXPECT_EQ(node->getGeometryGroup(), gg);
  node->set(transform);
  EXPECT_EQ(node->getTransform(), transform);
  node->set(selector);
  EXPECT_EQ(node->getSelector(), selector);
  EXPECT_EQ(node->getSize(), 4u);
  // Asking for another kind than the variable refers to.
  std::string message = ExpectThrows(RT_ERROR_TYPE_MISMATCH, [&] { node->getGroup(); });
  EXPECT_NE(message.find("top_object"), std::string::npos) << message;
  ExpectThrows(RT_ERROR_TYPE_MISMATCH, [&] { node->getBuffer(); });
  ExpectThrows(RT_ERROR_TYPE_MISMATCH, [&] { ctx_["buffer"]->getTextureSampler(); });

  struct Light {
    float direction[3];
    float ambient;
  };
  const Light light = {{0.f, 0.6f, 0.8f}, 0.25f};
  ctx_["light"]->setUserData(sizeof(light), &light);
  EXPECT_EQ(ctx_["light"]->getType(), RT_OBJECTTYPE_USER);
  EXPECT_EQ(ctx_["light"]->getSize(), sizeof(Light));
  Light back = {};
  ctx_["light"]->getUserData(sizeof(back), &back);
  EXPECT_EQ(std::memcmp(&back, &light, sizeof(Light)), 0);
  ExpectThrows(RT_ERROR_INVALID_VALUE, [&] { ctx_["light"]->getUserData(4, &back); });

  EXPECT_EQ(ctx_["light"]->getAnnotation(), "");  // host-declared
  EXPECT_EQ(ctx_["light"]->getContext(), ctx_);
}

// ---- Errors -----------------------------------------------------------------------------------

TEST_F(OptixppTest, ErrorsThrowTheCApiCodeAndMessage) {
  // Wrong type: the first set fixes it.
  optix::Variable v = ctx_["scale"];
  v->setFloat(1.f);
  std::string message = ExpectThrows(RT_ERROR_TYPE_MISMATCH, [&] { v->setInt(1); });
  EXPECT_EQ(message, ctx_->getErrorString(RT_ERROR_TYPE_MISMATCH));
  EXPECT_EQ(message, ErrorString(ctx_->get(), RT_ERROR_TYPE_MISMATCH));
  EXPECT_NE(message.find("rtVariableSet1i"), std::string::npos) << message;
  ExpectThrows(RT_ERROR_TYPE_MISMATCH, [&] { v->getFloat3(); });
  ExpectThrows(RT_ERROR_TYPE_MISMATCH, [&] { ctx_["never_set"]->getFloat(); });

  // Bad indices.
  message = ExpectThrows(RT_ERROR_INVALID_VALUE, [&] { ctx_->getRayGenerationProgram(3); });
  EXPECT_EQ(message, ErrorString(ctx_->get(), RT_ERROR_INVALID_VALUE));
  EXPECT_NE(message.find("rtContextGetRayGenerationProgram"), std::string::npos) << message;
  optix::Material material = ctx_->createMaterial();
  ExpectThrows(RT_ERROR_INVALID_VALUE,
               [&] { material->setClosestHitProgram(5, Prog("closest_hit_diffuse")); });
  optix::GeometryInstance gi = ctx_->createGeometryInstance();
  ExpectThrows(RT_ERROR_INVALID_VALUE, [&] { gi->getMaterial(0); });
  ExpectThrows(RT_ERROR_INVALID_VALUE, [&] { ctx_->createGroup()->removeChild(0u); });

  // Destroyed objects: the C API's message names the call.
  optix::Buffer buffer = ctx_->createBuffer(RT_BUFFER_INPUT, RT_FORMAT_FLOAT, 8);
  buffer->destroy();
  message = ExpectThrows(RT_ERROR_INVALID_VALUE, [&] { buffer->getFormat(); });
  EXPECT_EQ(message, ErrorString(ctx_->get(), RT_ERROR_INVALID_VALUE));
  EXPECT_NE(message.find("rtBufferGetFormat"), std::string::npos) << message;
  ExpectThrows(RT_ERROR_INVALID_VALUE, [&] { buffer->getContext(); });
  ExpectThrows(RT_ERROR_INVALID_VALUE, [&] { buffer->destroy(); });
  ExpectThrows(RT_ERROR_INVALID_VALUE, [&] { ctx_["b"]->set(buffer); });

  // Mapping twice.
  optix::Buffer mapped = ctx_->createBuffer(RT_BUFFER_INPUT, RT_FORMAT_FLOAT, 8);
  mapped->map();
  ExpectThrows(RT_ERROR_ALREADY_MAPPED, [&] { mapped->map(); });
  mapped->unmap();
  ExpectThrows(RT_ERROR_INVALID_VALUE, [&] { mapped->unmap(); });

  // A bad program file.
  ExpectThrows(RT_ERROR_FILE_NOT_FOUND,
               [&] { ctx_->createProgramFromPTXFile("/nonexistent/x.so", "miss"); });
  message = ExpectThrows(RT_ERROR_INVALID_SOURCE,
                         [&] { ctx_->createProgramFromPTXFile(kModule, "nope"); });
  EXPECT_NE(message.find("nope"), std::string::npos) << message;

  // checkError and makeException, for user code.
  EXPECT_NO_THROW(ctx_->checkError(RT_SUCCESS));
  ExpectThrows(RT_ERROR_TYPE_MISMATCH, [&] { ctx_->checkError(RT_ERROR_TYPE_MISMATCH); });
  ExpectThrows(RT_ERROR_UNKNOWN, [&] { material->checkError(RT_ERROR_UNKNOWN, ctx_); });
  optix::Exception e = optix::Exception::makeException(RT_ERROR_TYPE_MISMATCH, ctx_->get());
  EXPECT_EQ(e.getErrorCode(), RT_ERROR_TYPE_MISMATCH);
  EXPECT_EQ(e.getErrorString(), ErrorString(ctx_->get(), RT_ERROR_TYPE_MISMATCH));
  optix::Exception own("mine");
  EXPECT_EQ(own.getErrorCode(), RT_ERROR_UNKNOWN);
  EXPECT_EQ(own.getErrorString(), "mine");

  // Validation of an incomplete context.
  ExpectThrows(RT_ERROR_INVALID_CONTEXT, [&] { ctx_->validate(); });
  ExpectThrows(RT_ERROR_INVALID_CONTEXT, [&] { ctx_->compile(); });
  ExpectThrows(RT_ERROR_INVALID_CONTEXT, [&] { ctx_->launch(0, 4, 4); });
}

TEST_F(OptixppTest, GetChildOfAnotherKindThrows) {
  optix::Group group = ctx_->createGroup();
  optix::Transform transform = ctx_->createTransform();
  group->addChild(transform);
  EXPECT_EQ(group->getChild<optix::Transform>(0), transform);
  ExpectThrows(RT_ERROR_TYPE_MISMATCH, [&] { group->getChild<optix::Group>(0); });
  transform->setChild(ctx_->createGeometryGroup());
  ExpectThrows(RT_ERROR_TYPE_MISMATCH, [&] { transform->getChild<optix::Selector>(); });
  // A geometry instance is not a group child: the C API refuses it, and the count is undone.
  ExpectThrows(RT_ERROR_TYPE_MISMATCH, [&] { group->setChild(0, ctx_->createMaterial()); });
  ExpectThrows(RT_ERROR_TYPE_MISMATCH, [&] { group->addChild(ctx_->createMaterial()); });
  EXPECT_EQ(group->getChildCount(), 1u);
}

TEST_F(OptixppTest, TextureSamplerMembersRoundTrip) {
  optix::TextureSampler s = ctx_->createTextureSampler();
  EXPECT_EQ(s->getContext()->get(), ctx_->get());
  // OptiX's defaults.
  EXPECT_EQ(s->getWrapMode(2), RT_WRAP_REPEAT);
  EXPECT_EQ(s->getReadMode(), RT_TEXTURE_READ_NORMALIZED_FLOAT);
  EXPECT_EQ(s->getIndexingMode(), RT_TEXTURE_INDEX_NORMALIZED_COORDINATES);
  EXPECT_EQ(s->getMaxAnisotropy(), 1.f);
  s->setWrapMode(1, RT_WRAP_MIRROR);
  EXPECT_EQ(s->getWrapMode(1), RT_WRAP_MIRROR);
  s->setFilteringModes(RT_FILTER_NEAREST, RT_FILTER_LINEAR, RT_FILTER_LINEAR);
  RTfiltermode mn, mg, mp;
  s->getFilteringModes(mn, mg, mp);
  EXPECT_EQ(mn, RT_FILTER_NEAREST);
  EXPECT_EQ(mg, RT_FILTER_LINEAR);
  EXPECT_EQ(mp, RT_FILTER_LINEAR);
  s->setMaxAnisotropy(4.f);
  EXPECT_EQ(s->getMaxAnisotropy(), 4.f);
  s->setMipLevelClamp(0.5f, 3.f);
  float lo = 0.f, hi = 0.f;
  s->getMipLevelClamp(lo, hi);
  EXPECT_EQ(lo, 0.5f);
  EXPECT_EQ(hi, 3.f);
  s->setMipLevelBias(-1.f);
  EXPECT_EQ(s->getMipLevelBias(), -1.f);
  s->setReadMode(RT_TEXTURE_READ_ELEMENT_TYPE);
  EXPECT_EQ(s->getReadMode(), RT_TEXTURE_READ_ELEMENT_TYPE);
  s->setIndexingMode(RT_TEXTURE_INDEX_ARRAY_INDEX);
  EXPECT_EQ(s->getIndexingMode(), RT_TEXTURE_INDEX_ARRAY_INDEX);
  s->setMipLevelCount(1);
  EXPECT_EQ(s->getMipLevelCount(), 1u);
  s->setArraySize(1);
  EXPECT_EQ(s->getArraySize(), 1u);
  ExpectThrows(RT_ERROR_INVALID_VALUE, [&] { s->setArraySize(2); });

  optix::Buffer b = ctx_->createBuffer(RT_BUFFER_INPUT, RT_FORMAT_UNSIGNED_BYTE4, 8, 8);
  s->setBuffer(b);
  EXPECT_EQ(s->getBuffer()->get(), b->get());
  EXPECT_EQ(s->getBuffer(0, 0)->get(), b->get());
  ExpectThrows(RT_ERROR_INVALID_VALUE, [&] { s->getBuffer(0, 1); });
  EXPECT_NO_THROW(s->validate());

  const int id = s->getId();
  EXPECT_GT(id, 0);
  EXPECT_EQ(ctx_->getTextureSamplerFromId(id)->get(), s->get());
  ExpectThrows(RT_ERROR_INVALID_VALUE, [&] { ctx_->getTextureSamplerFromId(b->getId()); });

  ctx_["tex"]->setTextureSampler(s);
  EXPECT_EQ(ctx_["tex"]->getType(), RT_OBJECTTYPE_TEXTURE_SAMPLER);
  EXPECT_EQ(ctx_["tex"]->getTextureSampler()->get(), s->get());
  ExpectThrows(RT_ERROR_TYPE_MISMATCH, [&] { ctx_["tex"]->getBuffer(); });

  s->destroy();
  optix::TextureSampler none;
  ExpectThrows(RT_ERROR_INVALID_VALUE, [&] { none->setMipLevelCount(1); });  // null handle
}

TEST_F(OptixppTest, BufferMipLevels) {
  optix::Buffer b = ctx_->createBuffer(RT_BUFFER_INPUT, RT_FORMAT_FLOAT, 8, 4);
  b->setMipLevelCount(4);
  EXPECT_EQ(b->getMipLevelCount(), 4u);
  RTsize w = 0, h = 0;
  b->getMipLevelSize(2, w, h);
  EXPECT_EQ(w, 2u);
  EXPECT_EQ(h, 1u);
  RTsize w1 = 0;
  ExpectThrows(RT_ERROR_INVALID_VALUE, [&] { b->getMipLevelSize(0, w1); });  // the buffer is 2D
  float* level0 = static_cast<float*>(b->map(0, RT_BUFFER_MAP_WRITE_DISCARD));
  float* level1 = static_cast<float*>(b->map(1, RT_BUFFER_MAP_WRITE_DISCARD));
  EXPECT_EQ(level1 - level0, 8 * 4);  // level 1 follows level 0's 32 floats
  level1[7] = 5.f;
  b->unmap(1);
  b->unmap(0);
  EXPECT_EQ(static_cast<const float*>(b->map(1, RT_BUFFER_MAP_READ))[7], 5.f);
  b->unmap(1);
  ExpectThrows(RT_ERROR_INVALID_VALUE, [&] { b->map(4); });
  ExpectThrows(RT_ERROR_INVALID_VALUE, [&] { b->setMipLevelCount(5); });  // 8x4 has 4 levels
}

// Program ids (OptiX 3.6): getId, getProgramFromId, setProgramId, and the host's id types in a
// mapped buffer of RT_FORMAT_PROGRAM_ID elements (bindless_test.cc runs programs that use them).
TEST_F(OptixppTest, ProgramIdsRoundTrip) {
  optix::Program miss = Prog("miss");
  optix::Program hit = Prog("closest_hit_diffuse");
  const int id = miss->getId();
  EXPECT_GT(id, 0);
  EXPECT_EQ(miss->getId(), id);
  EXPECT_NE(hit->getId(), id);
  EXPECT_EQ(ctx_->getProgramFromId(id)->get(), miss->get());
  ctx_["shade"]->setProgramId(hit);
  EXPECT_EQ(ctx_["shade"]->getInt(), hit->getId());

  optix::Buffer ids = ctx_->createBuffer(RT_BUFFER_INPUT, RT_FORMAT_PROGRAM_ID, 2);
  static_assert(sizeof(optix::callableProgramId<int(int)>) == sizeof(int), "an id is an int");
  auto* data = static_cast<optix::callableProgramId<int(int)>*>(ids->map());
  data[0] = optix::callableProgramId<int(int)>(id);
  data[1] = optix::callableProgramId<int(int)>(hit->getId());
  ids->unmap();
  const int* raw = static_cast<const int*>(ids->map());
  EXPECT_EQ(raw[0], id);
  EXPECT_EQ(raw[1], hit->getId());
  ids->unmap();

  std::string message =
      ExpectThrows(RT_ERROR_INVALID_VALUE, [&] { ctx_->getProgramFromId(ids->getId()); });
  EXPECT_NE(message.find("no live program has id"), std::string::npos) << message;
}

// ---- Context ----------------------------------------------------------------------------------

TEST_F(OptixppTest, ContextSettersRoundTrip) {
  ctx_->setEntryPointCount(3);
  EXPECT_EQ(ctx_->getEntryPointCount(), 3u);
  ctx_->setRayTypeCount(2);
  EXPECT_EQ(ctx_->getRayTypeCount(), 2u);
  ctx_->setStackSize(4096);
  EXPECT_EQ(ctx_->getStackSize(), 4096u);
  ctx_->setPrintEnabled(true);
  EXPECT_TRUE(ctx_->getPrintEnabled());
  ctx_->setPrintEnabled(false);
  EXPECT_FALSE(ctx_->getPrintEnabled());
  ctx_->setPrintBufferSize(1 << 20);
  EXPECT_EQ(ctx_->getPrintBufferSize(), RTsize{1} << 20);
  ctx_->setPrintLaunchIndex(3);
  optix::int3 index = ctx_->getPrintLaunchIndex();
  EXPECT_EQ(index.x, 3);
  EXPECT_EQ(index.y, -1);
  EXPECT_EQ(index.z, -1);
  ctx_->setPrintLaunchIndex(1, 2, 3);
  EXPECT_EQ(ctx_->getPrintLaunchIndex().z, 3);
  ExpectThrows(RT_ERROR_INVALID_VALUE, [&] { ctx_->setPrintLaunchIndex(-2); });
  ctx_->setExceptionEnabled(RT_EXCEPTION_BUFFER_INDEX_OUT_OF_BOUNDS, true);
  EXPECT_TRUE(ctx_->getExceptionEnabled(RT_EXCEPTION_BUFFER_INDEX_OUT_OF_BOUNDS));
  ctx_->setExceptionEnabled(RT_EXCEPTION_BUFFER_INDEX_OUT_OF_BOUNDS, false);
  EXPECT_FALSE(ctx_->getExceptionEnabled(RT_EXCEPTION_BUFFER_INDEX_OUT_OF_BOUNDS));

  optix::Program raygen = Prog("pinhole_camera");
  optix::Program exception = Prog("exception");
  optix::Program miss = Prog("miss");
  ctx_->setRayGenerationProgram(2, raygen);
  EXPECT_EQ(ctx_->getRayGenerationProgram(2), raygen);
  EXPECT_FALSE(ctx_->getRayGenerationProgram(0));
  ctx_->setExceptionProgram(1, exception);
  EXPECT_EQ(ctx_->getExceptionProgram(1), exception);
  ctx_->setMissProgram(1, miss);
  EXPECT_EQ(ctx_->getMissProgram(1), miss);
  EXPECT_EQ(ctx_->getMissProgram(1)->getContext(), ctx_);
  EXPECT_EQ(ctx_->getRunningState(), 0);

  ctx_->setTimeoutCallback([]() { return 0; }, 0.5);
  ctx_->setCPUNumThreads(2);
  EXPECT_EQ(ctx_->getCPUNumThreads(), 2);
  EXPECT_GT(ctx_->getMaxTextureCount(), 0);
  EXPECT_EQ(ctx_->getGPUPagingActive(), 0);
  EXPECT_EQ(ctx_->getGPUPagingForcedOff(), 0);
  ExpectThrows(RT_ERROR_NOT_SUPPORTED, [&] { ctx_->setGPUPagingForcedOff(1); });
  const RTsize used = ctx_->getUsedHostMemory();
  optix::Buffer b = ctx_->createBuffer(RT_BUFFER_INPUT, RT_FORMAT_FLOAT4, 256);
  EXPECT_EQ(ctx_->getUsedHostMemory(), used + 256 * 16);
  EXPECT_GT(ctx_->getAvailableDeviceMemory(0), 0u);
  EXPECT_EQ(ctx_->getBufferFromId(b->getId()), b);
  EXPECT_FALSE(ctx_->getErrorString(RT_ERROR_UNKNOWN).empty());
}

TEST_F(OptixppTest, Devices) {
  const unsigned int count = optix::Context::getDeviceCount();
  ASSERT_GE(count, 1u);
  EXPECT_FALSE(optix::ContextObj::getDeviceName(0).empty());
  int threads = 0;
  optix::ContextObj::getDeviceAttribute(0, RT_DEVICE_ATTRIBUTE_MULTIPROCESSOR_COUNT,
                                        sizeof(threads), &threads);
  EXPECT_GE(threads, 1);
  ExpectThrows(RT_ERROR_INVALID_VALUE, [&] { optix::ContextObj::getDeviceName(1000); });

  const std::vector<int> enabled = ctx_->getEnabledDevices();
  EXPECT_EQ(enabled.size(), ctx_->getEnabledDeviceCount());
  ASSERT_FALSE(enabled.empty());
  const int first[] = {0};
  ctx_->setDevices(first, first + 1);
  EXPECT_EQ(ctx_->getEnabledDevices(), std::vector<int>{0});
  ctx_->setDevices(enabled.begin(), enabled.end());
  EXPECT_EQ(ctx_->getEnabledDevices(), enabled);
  const std::vector<int> bad = {static_cast<int>(count)};
  ExpectThrows(RT_ERROR_INVALID_DEVICE, [&] { ctx_->setDevices(bad.begin(), bad.end()); });
}

// ---- Buffers ----------------------------------------------------------------------------------

TEST_F(OptixppTest, BufferSettersRoundTrip) {
  optix::Buffer b = ctx_->createBuffer(RT_BUFFER_INPUT_OUTPUT);
  b->setFormat(RT_FORMAT_UNSIGNED_INT2);
  EXPECT_EQ(b->getFormat(), RT_FORMAT_UNSIGNED_INT2);
  EXPECT_EQ(b->getElementSize(), 8u);
  b->setSize(10);
  RTsize w = 0, h = 0, d = 0;
  b->getSize(w);
  EXPECT_EQ(w, 10u);
  EXPECT_EQ(b->getDimensionality(), 1u);
  b->setSize(3, 4);
  b->getSize(w, h);
  EXPECT_EQ(w, 3u);
  EXPECT_EQ(h, 4u);
  EXPECT_EQ(b->getDimensionality(), 2u);
  b->setSize(2, 3, 5);
  b->getSize(w, h, d);
  EXPECT_EQ(d, 5u);
  EXPECT_EQ(b->getDimensionality(), 3u);
  const RTsize dims[2] = {6, 7};
  b->setSize(2u, dims);
  RTsize back[2] = {};
  b->getSize(2u, back);
  EXPECT_EQ(back[0], 6u);
  EXPECT_EQ(back[1], 7u);

  // Map, write, unmap, map again: the contents stay.
  unsigned int* p = static_cast<unsigned int*>(b->map());
  for (unsigned int i = 0; i < 6 * 7 * 2; ++i) p[i] = i * 3;
  b->unmap();
  p = static_cast<unsigned int*>(b->map());
  EXPECT_EQ(p[41], 41u * 3);
  b->unmap();
  b->markDirty();

  optix::Buffer user = ctx_->createBuffer(RT_BUFFER_INPUT, RT_FORMAT_USER);
  user->setElementSize(24);
  EXPECT_EQ(user->getElementSize(), 24u);
  ExpectThrows(RT_ERROR_INVALID_VALUE, [&] { b->setElementSize(24); });  // USER only

  // Every createBuffer form.
  EXPECT_EQ(ctx_->createBuffer(RT_BUFFER_OUTPUT, RT_FORMAT_BYTE)->getFormat(), RT_FORMAT_BYTE);
  ctx_->createBuffer(RT_BUFFER_OUTPUT, RT_FORMAT_FLOAT, 5)->getSize(w);
  EXPECT_EQ(w, 5u);
  ctx_->createBuffer(RT_BUFFER_OUTPUT, RT_FORMAT_FLOAT, 5, 6)->getSize(w, h);
  EXPECT_EQ(h, 6u);
  ctx_->createBuffer(RT_BUFFER_OUTPUT, RT_FORMAT_FLOAT, 5, 6, 7)->getSize(w, h, d);
  EXPECT_EQ(d, 7u);
  EXPECT_NE(b->getId(), user->getId());
  EXPECT_EQ(b->getContext(), ctx_);
  b->validate();
  ExpectThrows(RT_ERROR_INVALID_VALUE, [&] { ctx_->createBuffer(0x40); });
}

TEST_F(OptixppTest, BufferDevicePointers) {
  optix::Buffer b = ctx_->createBuffer(RT_BUFFER_INPUT, RT_FORMAT_INT, 4);
  const int device = ctx_->getEnabledDevices()[0];
  int* p = static_cast<int*>(b->getDevicePointer(device));
  ASSERT_NE(p, nullptr);
  EXPECT_EQ(b->getDevicePointer(device), p);
  optix::Buffer cuda = ctx_->createBufferForCUDA(RT_BUFFER_INPUT, RT_FORMAT_INT, 4);
  std::vector<int> mine(4, 7);
  cuda->setDevicePointer(device, mine.data());
  EXPECT_EQ(cuda->getDevicePointer(device), mine.data());
  RTsize w = 0, h = 0, d = 0;
  ctx_->createBufferForCUDA(RT_BUFFER_INPUT, RT_FORMAT_INT, 2, 3, 4)->getSize(w, h, d);
  EXPECT_EQ(w * h * d, 24u);
  EXPECT_EQ(ctx_->createBufferForCUDA(RT_BUFFER_INPUT, RT_FORMAT_INT2)->getFormat(),
            RT_FORMAT_INT2);
  ExpectThrows(RT_ERROR_INVALID_VALUE, [&] { b->getDevicePointer(1000); });
}

// ---- Nodes ------------------------------------------------------------------------------------

TEST_F(OptixppTest, GroupChildrenAndAcceleration) {
  optix::Group group = ctx_->createGroup();
  optix::Acceleration accel = ctx_->createAcceleration("Bvh", "Bvh");
  group->setAcceleration(accel);
  EXPECT_EQ(group->getAcceleration(), accel);

  optix::GeometryGroup gg = ctx_->createGeometryGroup();
  optix::Transform transform = ctx_->createTransform();
  optix::Selector selector = ctx_->createSelector();
  optix::Group inner = ctx_->createGroup();
  group->setChildCount(2);
  group->setChild(0, gg);
  group->setChild(1, transform);
  EXPECT_EQ(group->getChildCount(), 2u);
  EXPECT_EQ(group->getChildType(0), RT_OBJECTTYPE_GEOMETRY_GROUP);
  EXPECT_EQ(group->getChild<optix::GeometryGroup>(0), gg);
  EXPECT_EQ(group->getChild<optix::Transform>(1), transform);
  EXPECT_EQ(group->addChild(selector), 2u);
  EXPECT_EQ(group->addChild(inner), 3u);
  EXPECT_EQ(group->getChild<optix::Selector>(2), selector);
  EXPECT_EQ(group->getChild<optix::Group>(3), inner);
  EXPECT_EQ(group->getChildIndex(selector), 2u);
  // Removal moves the last child into the hole.
  group->removeChild(transform);
  EXPECT_EQ(group->getChildCount(), 3u);
  EXPECT_EQ(group->getChild<optix::Group>(1), inner);
  group->removeChild(2u);
  EXPECT_EQ(group->getChildCount(), 2u);
  ExpectThrows(RT_ERROR_INVALID_VALUE, [&] { group->getChildIndex(transform); });
  ExpectThrows(RT_ERROR_INVALID_VALUE, [&] { group->getChildType(5); });

  // createGroup over a range of children.
  std::vector<optix::GeometryGroup> ggs = {ctx_->createGeometryGroup(),
                                           ctx_->createGeometryGroup()};
  optix::Group ranged = ctx_->createGroup(ggs.begin(), ggs.end());
  EXPECT_EQ(ranged->getChildCount(), 2u);
  EXPECT_EQ(ranged->getChild<optix::GeometryGroup>(1), ggs[1]);
  EXPECT_EQ(ranged->getContext(), ctx_);
  ranged->destroy();
  ExpectThrows(RT_ERROR_INVALID_VALUE, [&] { ranged->validate(); });
}

TEST_F(OptixppTest, GeometryGroupChildren) {
  optix::GeometryInstance a = ctx_->createGeometryInstance();
  optix::GeometryInstance b = ctx_->createGeometryInstance();
  optix::GeometryInstance c = ctx_->createGeometryInstance();
  optix::GeometryInstance list[] = {a, b};
  optix::GeometryGroup gg = ctx_->createGeometryGroup(list, list + 2);
  EXPECT_EQ(gg->getChildCount(), 2u);
  EXPECT_EQ(gg->getChild(0), a);
  EXPECT_EQ(gg->addChild(c), 2u);
  EXPECT_EQ(gg->getChildIndex(c), 2u);
  gg->removeChild(a);
  EXPECT_EQ(gg->getChildCount(), 2u);
  EXPECT_EQ(gg->getChild(0), c);
  gg->removeChild(1u);
  EXPECT_EQ(gg->getChildCount(), 1u);
  gg->setChildCount(3);
  gg->setChild(2, b);
  EXPECT_EQ(gg->getChild(2), b);
  EXPECT_FALSE(gg->getChild(1));
  ExpectThrows(RT_ERROR_INVALID_VALUE, [&] { gg->getChildIndex(a); });
  ExpectThrows(RT_ERROR_INVALID_VALUE, [&] { gg->setChild(3, a); });
  optix::Acceleration accel = ctx_->createAcceleration("NoAccel");
  EXPECT_EQ(accel->getTraverser(), "NoAccel");
  gg->setAcceleration(accel);
  EXPECT_EQ(gg->getAcceleration(), accel);
  EXPECT_EQ(gg->getContext(), ctx_);
}

TEST_F(OptixppTest, TransformMatrixAndChild) {
  optix::Transform t = ctx_->createTransform();
  const float m[16] = {2, 0, 0, 1, 0, 4, 0, 2, 0, 0, 8, 3, 0, 0, 0, 1};
  t->setMatrix(false, m, nullptr);
  float out[16] = {}, inv[16] = {};
  t->getMatrix(false, out, inv);
  EXPECT_EQ(std::memcmp(out, m, sizeof(m)), 0);
  EXPECT_EQ(inv[0], 0.5f);
  EXPECT_EQ(inv[5], 0.25f);
  EXPECT_EQ(inv[3], -0.5f);
  t->getMatrix(true, out, nullptr);
  EXPECT_EQ(out[12], 1.f);  // the translation, transposed into the last row
  const float singular[16] = {};
  ExpectThrows(RT_ERROR_INVALID_VALUE, [&] { t->setMatrix(false, singular, nullptr); });

  EXPECT_EQ(t->getChildType(), RT_OBJECTTYPE_UNKNOWN);
  EXPECT_FALSE(t->getChild<optix::Group>());
  optix::GeometryGroup gg = ctx_->createGeometryGroup();
  t->setChild(gg);
  EXPECT_EQ(t->getChildType(), RT_OBJECTTYPE_GEOMETRY_GROUP);
  EXPECT_EQ(t->getChild<optix::GeometryGroup>(), gg);
  EXPECT_EQ(t->getContext(), ctx_);
}

TEST_F(OptixppTest, SelectorProgramAndChildren) {
  optix::Selector s = ctx_->createSelector();
  optix::Program visit = Prog("visit");
  s->setVisitProgram(visit);
  EXPECT_EQ(s->getVisitProgram(), visit);
  optix::Group g = ctx_->createGroup();
  optix::Transform t = ctx_->createTransform();
  s->setChildCount(1);
  s->setChild(0, g);
  EXPECT_EQ(s->getChild<optix::Group>(0), g);
  EXPECT_EQ(s->getChildType(0), RT_OBJECTTYPE_GROUP);
  EXPECT_EQ(s->addChild(t), 1u);
  EXPECT_EQ(s->getChildIndex(t), 1u);
  s->removeChild(g);
  EXPECT_EQ(s->getChildCount(), 1u);
  EXPECT_EQ(s->getChild<optix::Transform>(0), t);
  ExpectThrows(RT_ERROR_TYPE_MISMATCH, [&] { s->getChild<optix::Group>(0); });
  s->removeChild(0u);
  EXPECT_EQ(s->getChildCount(), 0u);
}

// What OptiX 3-6 host code spells differently from the guide: int indices for removeChild,
// removeChild(node) returning the index, getMatrixNxM, map(level, flags) / unmap(level).
TEST_F(OptixppTest, OptixSpellingsOfRemoveChildMatrixGettersAndMap) {
  optix::Group group = ctx_->createGroup();
  optix::Transform t0 = ctx_->createTransform(), t1 = ctx_->createTransform();
  group->addChild(t0);
  group->addChild(t1);
  EXPECT_EQ(group->removeChild(t0), 0u);  // the index it had
  int index = 0;
  group->removeChild(index);  // int, as loops write it
  EXPECT_EQ(group->getChildCount(), 0u);

  // Selectors keep their order (visit programs pick children by index), as OptiX's do.
  optix::Selector s = ctx_->createSelector();
  std::vector<optix::Group> kids = {ctx_->createGroup(), ctx_->createGroup(), ctx_->createGroup()};
  for (const optix::Group& k : kids) s->addChild(k);
  s->removeChild(0);
  ASSERT_EQ(s->getChildCount(), 2u);
  EXPECT_EQ(s->getChild<optix::Group>(0), kids[1]);
  EXPECT_EQ(s->getChild<optix::Group>(1), kids[2]);

  // A null handle is nobody's child, not the first empty slot.
  group->setChildCount(1);
  ExpectThrows(RT_ERROR_INVALID_VALUE, [&] { group->getChildIndex(optix::Transform()); });
  ExpectThrows(RT_ERROR_INVALID_VALUE, [&] { group->removeChild(optix::Transform()); });
  EXPECT_EQ(group->getChildCount(), 1u);
  // Kind mismatches name both kinds.
  group->setChild(0, t1);
  const std::string message =
      ExpectThrows(RT_ERROR_TYPE_MISMATCH, [&] { group->getChild<optix::GeometryGroup>(0); });
  EXPECT_NE(message.find("is a transform, not a geometry group"), std::string::npos) << message;

  const float m[16] = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16};
  ctx_["m"]->setMatrix4x4fv(false, m);
  float out[16] = {};
  ctx_["m"]->getMatrix4x4(true, out);
  EXPECT_EQ(out[1], 5.f);

  optix::Buffer b = ctx_->createBuffer(RT_BUFFER_INPUT, RT_FORMAT_FLOAT, 4);
  float* w = static_cast<float*>(b->map(0, RT_BUFFER_MAP_WRITE_DISCARD));
  w[3] = 7.f;
  b->unmap(0);
  EXPECT_EQ(static_cast<const float*>(b->map(0, RT_BUFFER_MAP_READ))[3], 7.f);
  b->unmap();
  ExpectThrows(RT_ERROR_INVALID_VALUE, [&] { b->map(1); });  // no level 1
  ExpectThrows(RT_ERROR_INVALID_VALUE, [&] { b->map(0, 3); });
  float mine[4];
  ExpectThrows(RT_ERROR_NOT_SUPPORTED, [&] { b->map(0, RT_BUFFER_MAP_READ_WRITE, mine); });
  EXPECT_NO_THROW(b->map());  // none of the failed maps left it mapped
  b->unmap();
}

TEST_F(OptixppTest, AccelerationProperties) {
  optix::Acceleration a = ctx_->createAcceleration("Sbvh", "Bvh");
  EXPECT_EQ(a->getBuilder(), "Sbvh");
  EXPECT_EQ(a->getTraverser(), "Bvh");
  a->setBuilder("TriangleKdTree");
  a->setTraverser("KdTree");
  EXPECT_EQ(a->getBuilder(), "TriangleKdTree");
  EXPECT_EQ(a->getTraverser(), "KdTree");
  a->setProperty("refit", "1");
  EXPECT_EQ(a->getProperty("refit"), "1");
  EXPECT_EQ(a->getProperty("unset"), "");
  EXPECT_TRUE(a->isDirty());
  a->markDirty();
  EXPECT_TRUE(a->isDirty());
  // A dirty acceleration has no data, and an empty blob is none Tessera wrote
  // (docs/acceleration_data.md; tests/semantics/acceleration_data_test.cc round-trips real data).
  ExpectThrows(RT_ERROR_INVALID_VALUE, [&] { a->getDataSize(); });
  std::vector<char> data(64);
  ExpectThrows(RT_ERROR_INVALID_VALUE, [&] { a->getData(data.data()); });
  ExpectThrows(RT_ERROR_INVALID_VALUE, [&] { a->setData("", 0); });
  EXPECT_EQ(a->getBuilder(), "TriangleKdTree");  // a refused blob changes nothing
  a->validate();
  ExpectThrows(RT_ERROR_INVALID_VALUE, [&] { a->setBuilder("Magic"); });
  EXPECT_EQ(ctx_->createAcceleration("TriangleKdTree")->getTraverser(), "KdTree");
  EXPECT_EQ(ctx_->createAcceleration("Trbvh")->getTraverser(), "Bvh");
  EXPECT_EQ(a->getContext(), ctx_);
}

TEST_F(OptixppTest, GeometryAndInstanceAndMaterial) {
  optix::Geometry g = ctx_->createGeometry();
  g->setPrimitiveCount(7);
  EXPECT_EQ(g->getPrimitiveCount(), 7u);
  optix::Program bounds = Prog("sphere_bounds");
  optix::Program intersect = Prog("sphere_intersect");
  g->setBoundingBoxProgram(bounds);
  g->setIntersectionProgram(intersect);
  EXPECT_EQ(g->getBoundingBoxProgram(), bounds);
  EXPECT_EQ(g->getIntersectionProgram(), intersect);
  EXPECT_TRUE(g->isDirty());
  g->markDirty();
  EXPECT_TRUE(g->isDirty());
  g->validate();

  optix::Material m0 = ctx_->createMaterial();
  optix::Material m1 = ctx_->createMaterial();
  ctx_->setRayTypeCount(2);
  optix::Program ch = Prog("closest_hit_diffuse");
  optix::Program ah = Prog("miss");
  m0->setClosestHitProgram(1, ch);
  m0->setAnyHitProgram(0, ah);
  EXPECT_EQ(m0->getClosestHitProgram(1), ch);
  EXPECT_EQ(m0->getAnyHitProgram(0), ah);
  EXPECT_FALSE(m0->getClosestHitProgram(0));
  ExpectThrows(RT_ERROR_INVALID_VALUE, [&] { m0->getAnyHitProgram(2); });

  std::vector<optix::Material> materials = {m0, m1};
  optix::GeometryInstance gi = ctx_->createGeometryInstance(g, materials.begin(), materials.end());
  EXPECT_EQ(gi->getGeometry(), g);
  EXPECT_EQ(gi->getMaterialCount(), 2u);
  EXPECT_EQ(gi->getMaterial(1), m1);
  optix::Material m2 = ctx_->createMaterial();
  EXPECT_EQ(gi->addMaterial(m2), 2u);
  EXPECT_EQ(gi->getMaterial(2), m2);
  gi->setMaterial(0, m2);
  EXPECT_EQ(gi->getMaterial(0), m2);
  gi->setMaterialCount(1);
  EXPECT_EQ(gi->getMaterialCount(), 1u);
  EXPECT_FALSE(gi->getGeometryTriangles());
  gi->validate();
  EXPECT_EQ(gi->getContext(), ctx_);
  EXPECT_EQ(m0->getContext(), ctx_);
  EXPECT_EQ(g->getContext(), ctx_);
}

TEST_F(OptixppTest, GeometryTriangles) {
  optix::GeometryTriangles tris = ctx_->createGeometryTriangles();
  tris->setPrimitiveCount(2);
  EXPECT_EQ(tris->getPrimitiveCount(), 2u);
  tris->setPrimitiveIndexOffset(5);
  EXPECT_EQ(tris->getPrimitiveIndexOffset(), 5u);
  optix::Buffer vertices = ctx_->createBuffer(RT_BUFFER_INPUT, RT_FORMAT_FLOAT3, 4);
  optix::Buffer indices = ctx_->createBuffer(RT_BUFFER_INPUT, RT_FORMAT_UNSIGNED_INT3, 2);
  tris->setVertices(4, vertices, RT_FORMAT_FLOAT3);
  tris->setVertices(4, vertices, 0, 12, RT_FORMAT_FLOAT3);
  tris->setTriangleIndices(indices, RT_FORMAT_UNSIGNED_INT3);
  tris->setTriangleIndices(indices, 0, RT_FORMAT_UNSIGNED_INT3);
  tris->setTriangleIndices(indices, 0, 12, RT_FORMAT_UNSIGNED_INT3);
  ExpectThrows(RT_ERROR_INVALID_VALUE,
               [&] { tris->setVertices(4, vertices, 0, 4, RT_FORMAT_FLOAT3); });
  optix::Program attributes = Prog("miss");
  tris->setAttributeProgram(attributes);
  EXPECT_EQ(tris->getAttributeProgram(), attributes);
  tris->setMaterialCount(2);
  EXPECT_EQ(tris->getMaterialCount(), 2u);
  optix::Buffer material_indices = ctx_->createBuffer(RT_BUFFER_INPUT, RT_FORMAT_UNSIGNED_BYTE, 2);
  tris->setMaterialIndices(material_indices, 0, 1, RT_FORMAT_UNSIGNED_BYTE);
  optix::GeometryInstance gi = ctx_->createGeometryInstance();
  gi->setGeometryTriangles(tris);
  EXPECT_EQ(gi->getGeometryTriangles(), tris);
  EXPECT_FALSE(gi->getGeometry());
  EXPECT_EQ(tris->getContext(), ctx_);
  tris->destroy();
  ExpectThrows(RT_ERROR_INVALID_VALUE, [&] { tris->getPrimitiveCount(); });
}

// ---- End to end -------------------------------------------------------------------------------

constexpr RTsize kWidth = 96, kHeight = 64;

struct Light {
  float direction[3];
  float ambient;
};
constexpr Light kLight = {{0.f, 0.6f, 0.8f}, 0.2f};
constexpr float kSpheres[2][4] = {{-0.8f, 0.f, 0.f, 0.7f}, {0.9f, 0.2f, -0.5f, 0.9f}};
constexpr float kKd[2][3] = {{0.9f, 0.3f, 0.2f}, {0.2f, 0.5f, 0.9f}};
// Moves the spheres away from the camera and scales them in y.
constexpr float kMatrix[16] = {1, 0, 0, 0, 0, 1.2f, 0, 0.1f, 0, 0, 1, -0.5f, 0, 0, 0, 1};

std::vector<float> ReadFloat4s(void* p) {
  const float* f = static_cast<const float*>(p);
  return std::vector<float>(f, f + 4 * kWidth * kHeight);
}

// The scene through OptiXpp: context → Group → Transform → GeometryGroup → two spheres.
std::vector<float> RenderWithOptixpp() {
  optix::Context context = optix::Context::create();
  context->setRayTypeCount(1);
  context->setEntryPointCount(1);
  context->setRayGenerationProgram(0, context->createProgramFromPTXFile(kModule, "pinhole_camera"));
  context->setExceptionProgram(0, context->createProgramFromPTXFile(kModule, "exception"));
  context->setMissProgram(0, context->createProgramFromPTXFile(kModule, "miss"));
  context["eye"]->setFloat(0.f, 0.f, 4.f);
  context["U"]->setFloat(make_float3(1.5f, 0.f, 0.f));
  context["V"]->set3fv(std::vector<float>{0.f, 1.f, 0.f}.data());
  context["W"]->setFloat(0.f, 0.f, -2.f);
  context["bg_color"]->setFloat(0.1f, 0.1f, 0.3f);
  context["light"]->setUserData(sizeof(kLight), &kLight);
  optix::Buffer output = context->createBuffer(RT_BUFFER_OUTPUT, RT_FORMAT_FLOAT4, kWidth, kHeight);
  context["output_buffer"]->set(output);

  optix::Geometry sphere = context->createGeometry();
  sphere->setPrimitiveCount(1);
  sphere->setBoundingBoxProgram(context->createProgramFromPTXFile(kModule, "sphere_bounds"));
  sphere->setIntersectionProgram(context->createProgramFromPTXFile(kModule, "sphere_intersect"));
  optix::Program closest_hit = context->createProgramFromPTXFile(kModule, "closest_hit_diffuse");

  optix::GeometryGroup gg = context->createGeometryGroup();
  gg->setAcceleration(context->createAcceleration("Bvh", "Bvh"));
  for (int i = 0; i < 2; ++i) {
    optix::Material material = context->createMaterial();
    material->setClosestHitProgram(0, closest_hit);
    material["Kd"]->setFloat(kKd[i][0], kKd[i][1], kKd[i][2]);
    optix::GeometryInstance gi = context->createGeometryInstance(sphere, &material, &material + 1);
    gi["sphere"]->set4fv(kSpheres[i]);
    gg->addChild(gi);
  }
  optix::Transform transform = context->createTransform();
  transform->setMatrix(false, kMatrix, nullptr);
  transform->setChild(gg);
  optix::Group top = context->createGroup(&transform, &transform + 1);
  top->setAcceleration(context->createAcceleration("Bvh"));
  context["top_object"]->set(top);

  context->validate();
  context->compile();
  context->launch(0, kWidth, kHeight);
  std::vector<float> pixels = ReadFloat4s(output->map());
  output->unmap();
  context->destroy();
  return pixels;
}

#define RT_OK(call) \
  ASSERT_EQ((call), RT_SUCCESS) << #call << ": " << ErrorString(ctx, RT_ERROR_UNKNOWN)

RTvariable Declare(RTcontext ctx, const char* name) {
  RTvariable v = nullptr;
  EXPECT_EQ(rtContextDeclareVariable(ctx, name, &v), RT_SUCCESS);
  return v;
}

// The same scene through the C API.
void RenderWithCApi(std::vector<float>* pixels) {
  RTcontext ctx = nullptr;
  ASSERT_EQ(rtContextCreate(&ctx), RT_SUCCESS);
  RT_OK(rtContextSetRayTypeCount(ctx, 1));
  RT_OK(rtContextSetEntryPointCount(ctx, 1));
  RTprogram raygen, exception, miss, bounds, intersect, closest_hit;
  RT_OK(rtProgramCreateFromPTXFile(ctx, kModule.c_str(), "pinhole_camera", &raygen));
  RT_OK(rtProgramCreateFromPTXFile(ctx, kModule.c_str(), "exception", &exception));
  RT_OK(rtProgramCreateFromPTXFile(ctx, kModule.c_str(), "miss", &miss));
  RT_OK(rtProgramCreateFromPTXFile(ctx, kModule.c_str(), "sphere_bounds", &bounds));
  RT_OK(rtProgramCreateFromPTXFile(ctx, kModule.c_str(), "sphere_intersect", &intersect));
  RT_OK(rtProgramCreateFromPTXFile(ctx, kModule.c_str(), "closest_hit_diffuse", &closest_hit));
  RT_OK(rtContextSetRayGenerationProgram(ctx, 0, raygen));
  RT_OK(rtContextSetExceptionProgram(ctx, 0, exception));
  RT_OK(rtContextSetMissProgram(ctx, 0, miss));
  RT_OK(rtVariableSet3f(Declare(ctx, "eye"), 0.f, 0.f, 4.f));
  RT_OK(rtVariableSet3f(Declare(ctx, "U"), 1.5f, 0.f, 0.f));
  RT_OK(rtVariableSet3f(Declare(ctx, "V"), 0.f, 1.f, 0.f));
  RT_OK(rtVariableSet3f(Declare(ctx, "W"), 0.f, 0.f, -2.f));
  RT_OK(rtVariableSet3f(Declare(ctx, "bg_color"), 0.1f, 0.1f, 0.3f));
  RT_OK(rtVariableSetUserData(Declare(ctx, "light"), sizeof(kLight), &kLight));
  RTbuffer output;
  RT_OK(rtBufferCreate(ctx, RT_BUFFER_OUTPUT, &output));
  RT_OK(rtBufferSetFormat(output, RT_FORMAT_FLOAT4));
  RT_OK(rtBufferSetSize2D(output, kWidth, kHeight));
  RT_OK(rtVariableSetObject(Declare(ctx, "output_buffer"), output));

  RTgeometry sphere;
  RT_OK(rtGeometryCreate(ctx, &sphere));
  RT_OK(rtGeometrySetPrimitiveCount(sphere, 1));
  RT_OK(rtGeometrySetBoundingBoxProgram(sphere, bounds));
  RT_OK(rtGeometrySetIntersectionProgram(sphere, intersect));
  RTgeometrygroup gg;
  RTacceleration gg_accel, top_accel;
  RT_OK(rtGeometryGroupCreate(ctx, &gg));
  RT_OK(rtAccelerationCreate(ctx, &gg_accel));
  RT_OK(rtAccelerationSetBuilder(gg_accel, "Bvh"));
  RT_OK(rtAccelerationSetTraverser(gg_accel, "Bvh"));
  RT_OK(rtGeometryGroupSetAcceleration(gg, gg_accel));
  RT_OK(rtGeometryGroupSetChildCount(gg, 2));
  for (unsigned int i = 0; i < 2; ++i) {
    RTmaterial material;
    RT_OK(rtMaterialCreate(ctx, &material));
    RT_OK(rtMaterialSetClosestHitProgram(material, 0, closest_hit));
    RTvariable v;
    RT_OK(rtMaterialDeclareVariable(material, "Kd", &v));
    RT_OK(rtVariableSet3f(v, kKd[i][0], kKd[i][1], kKd[i][2]));
    RTgeometryinstance gi;
    RT_OK(rtGeometryInstanceCreate(ctx, &gi));
    RT_OK(rtGeometryInstanceSetGeometry(gi, sphere));
    RT_OK(rtGeometryInstanceSetMaterialCount(gi, 1));
    RT_OK(rtGeometryInstanceSetMaterial(gi, 0, material));
    RT_OK(rtGeometryInstanceDeclareVariable(gi, "sphere", &v));
    RT_OK(rtVariableSet4fv(v, kSpheres[i]));
    RT_OK(rtGeometryGroupSetChild(gg, i, gi));
  }
  RTtransform transform;
  RT_OK(rtTransformCreate(ctx, &transform));
  RT_OK(rtTransformSetMatrix(transform, 0, kMatrix, nullptr));
  RT_OK(rtTransformSetChild(transform, gg));
  RTgroup top;
  RT_OK(rtGroupCreate(ctx, &top));
  RT_OK(rtGroupSetChildCount(top, 1));
  RT_OK(rtGroupSetChild(top, 0, transform));
  RT_OK(rtAccelerationCreate(ctx, &top_accel));
  RT_OK(rtAccelerationSetBuilder(top_accel, "Bvh"));
  RT_OK(rtAccelerationSetTraverser(top_accel, "Bvh"));
  RT_OK(rtGroupSetAcceleration(top, top_accel));
  RT_OK(rtVariableSetObject(Declare(ctx, "top_object"), top));

  RT_OK(rtContextLaunch2D(ctx, 0, kWidth, kHeight));
  void* p = nullptr;
  RT_OK(rtBufferMap(output, &p));
  *pixels = ReadFloat4s(p);
  RT_OK(rtBufferUnmap(output));
  RT_OK(rtContextDestroy(ctx));
}

TEST(OptixppRenderTest, MatchesTheCApiBitForBit) {
  ScopedEnv devices("TESSERA_DEVICES", "inproc");
  std::vector<float> expected;
  ASSERT_NO_FATAL_FAILURE(RenderWithCApi(&expected));
  std::vector<float> actual;
  try {
    actual = RenderWithOptixpp();
  } catch (const optix::Exception& e) {
    FAIL() << "optix::Exception " << e.getErrorCode() << ": " << e.getErrorString();
  }
  ASSERT_EQ(actual.size(), expected.size());
  EXPECT_EQ(std::memcmp(actual.data(), expected.data(), actual.size() * sizeof(float)), 0);

  // The image has both spheres, the background, and no exception pixels.
  int hits[2] = {0, 0}, background = 0;
  for (size_t i = 0; i < actual.size(); i += 4) {
    const float depth = actual[i + 3];
    if (depth < 0.f) {
      ++background;
      EXPECT_EQ(actual[i + 2], 0.3f);
    } else {
      ASSERT_GT(depth, 0.f) << "pixel " << i / 4;
      ASSERT_NE(actual[i + 1], 0.f) << "pixel " << i / 4;  // exceptions write green 0
      ++hits[actual[i] > actual[i + 2] ? 0 : 1];           // red sphere or blue sphere
    }
  }
  EXPECT_GT(hits[0], 100);
  EXPECT_GT(hits[1], 100);
  EXPECT_GT(background, 100);
}

}  // namespace
}  // namespace tessera::test

// The C API sweep: every entry point of tessera/rt.h is called with null, wrong-type and
// destroyed handles, null pointers, out-of-range indices and mismatched types. Each must return
// the exact RTresult, and rtContextGetErrorString must return a message naming the function and
// the kind of object involved. Nothing may crash.
#include "c_api_sweep.h"

#include <cctype>
#include <fstream>
#include <set>
#include <string>

#include "api_test_util.h"
#include "gtest/gtest.h"
#include "tessera/rt.h"

namespace tessera::test {
namespace {

class CApiSweepTest : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_EQ(rtContextCreate(&w.ctx), RT_SUCCESS);
    RTcontext c = w.ctx;
    ASSERT_EQ(rtContextSetEntryPointCount(c, 1), RT_SUCCESS);
    ASSERT_EQ(rtContextSetRayTypeCount(c, 1), RT_SUCCESS);
    ASSERT_EQ(rtBufferCreate(c, RT_BUFFER_INPUT, &w.buffer), RT_SUCCESS);
    ASSERT_EQ(rtContextDeclareVariable(c, "v", &w.variable), RT_SUCCESS);
    ASSERT_EQ(rtProgramCreateFromPTXFile(c, kTestModule, "ray_gen", &w.program), RT_SUCCESS);
    ASSERT_EQ(rtGeometryCreate(c, &w.geometry), RT_SUCCESS);
    ASSERT_EQ(rtMaterialCreate(c, &w.material), RT_SUCCESS);
    ASSERT_EQ(rtGeometryInstanceCreate(c, &w.instance), RT_SUCCESS);
    ASSERT_EQ(rtGeometryInstanceSetMaterialCount(w.instance, 1), RT_SUCCESS);
    ASSERT_EQ(rtGeometryGroupCreate(c, &w.geometry_group), RT_SUCCESS);
    ASSERT_EQ(rtGeometryGroupSetChildCount(w.geometry_group, 1), RT_SUCCESS);
    ASSERT_EQ(rtGroupCreate(c, &w.group), RT_SUCCESS);
    ASSERT_EQ(rtGroupSetChildCount(w.group, 1), RT_SUCCESS);
    ASSERT_EQ(rtSelectorCreate(c, &w.selector), RT_SUCCESS);
    ASSERT_EQ(rtSelectorSetChildCount(w.selector, 1), RT_SUCCESS);
    ASSERT_EQ(rtTransformCreate(c, &w.transform), RT_SUCCESS);
    ASSERT_EQ(rtAccelerationCreate(c, &w.acceleration), RT_SUCCESS);
    ASSERT_EQ(rtGeometryTrianglesCreate(c, &w.triangles), RT_SUCCESS);
    ASSERT_EQ(rtTextureSamplerCreate(c, &w.sampler), RT_SUCCESS);

    ASSERT_EQ(rtContextCreate(&w.dead_ctx), RT_SUCCESS);
    ASSERT_EQ(rtContextDestroy(w.dead_ctx), RT_SUCCESS);
    ASSERT_EQ(rtBufferCreate(c, RT_BUFFER_INPUT, &w.dead_buffer), RT_SUCCESS);
    ASSERT_EQ(rtBufferDestroy(w.dead_buffer), RT_SUCCESS);
    ASSERT_EQ(rtContextDeclareVariable(c, "dead", &w.dead_variable), RT_SUCCESS);
    ASSERT_EQ(rtContextRemoveVariable(c, w.dead_variable), RT_SUCCESS);
    ASSERT_EQ(rtProgramCreateFromPTXFile(c, kTestModule, "miss", &w.dead_program), RT_SUCCESS);
    ASSERT_EQ(rtProgramDestroy(w.dead_program), RT_SUCCESS);
    ASSERT_EQ(rtGeometryCreate(c, &w.dead_geometry), RT_SUCCESS);
    ASSERT_EQ(rtGeometryDestroy(w.dead_geometry), RT_SUCCESS);
    ASSERT_EQ(rtMaterialCreate(c, &w.dead_material), RT_SUCCESS);
    ASSERT_EQ(rtMaterialDestroy(w.dead_material), RT_SUCCESS);
    ASSERT_EQ(rtGeometryInstanceCreate(c, &w.dead_instance), RT_SUCCESS);
    ASSERT_EQ(rtGeometryInstanceDestroy(w.dead_instance), RT_SUCCESS);
    ASSERT_EQ(rtGeometryGroupCreate(c, &w.dead_geometry_group), RT_SUCCESS);
    ASSERT_EQ(rtGeometryGroupDestroy(w.dead_geometry_group), RT_SUCCESS);
    ASSERT_EQ(rtGroupCreate(c, &w.dead_group), RT_SUCCESS);
    ASSERT_EQ(rtGroupDestroy(w.dead_group), RT_SUCCESS);
    ASSERT_EQ(rtSelectorCreate(c, &w.dead_selector), RT_SUCCESS);
    ASSERT_EQ(rtSelectorDestroy(w.dead_selector), RT_SUCCESS);
    ASSERT_EQ(rtTransformCreate(c, &w.dead_transform), RT_SUCCESS);
    ASSERT_EQ(rtTransformDestroy(w.dead_transform), RT_SUCCESS);
    ASSERT_EQ(rtAccelerationCreate(c, &w.dead_acceleration), RT_SUCCESS);
    ASSERT_EQ(rtAccelerationDestroy(w.dead_acceleration), RT_SUCCESS);
    ASSERT_EQ(rtGeometryTrianglesCreate(c, &w.dead_triangles), RT_SUCCESS);
    ASSERT_EQ(rtGeometryTrianglesDestroy(w.dead_triangles), RT_SUCCESS);
    ASSERT_EQ(rtTextureSamplerCreate(c, &w.dead_sampler), RT_SUCCESS);
    ASSERT_EQ(rtTextureSamplerDestroy(w.dead_sampler), RT_SUCCESS);
  }

  void TearDown() override { EXPECT_EQ(rtContextDestroy(w.ctx), RT_SUCCESS); }

  // The message for the failure just seen names the function and, if given, `word`.
  void ExpectMessage(RTresult code, const std::string& call, const char* word) {
    const std::string fn = call.substr(0, call.find('('));
    const std::string message = ErrorString(w.ctx, code);
    // "rtFn(object #n): …" for calls about an object, "rtFn: …" otherwise.
    EXPECT_TRUE(message.rfind(fn + "(", 0) == 0 || message.rfind(fn + ":", 0) == 0)
        << call << ": '" << message << "'";
    if (word != nullptr) {
      EXPECT_NE(message.find(word), std::string::npos)
          << call << ": '" << message << "' does not name the " << word;
    }
  }

  World w;
};

RTresult HandleError(K kind) {
  return kind == K::kContext ? RT_ERROR_INVALID_CONTEXT : RT_ERROR_INVALID_VALUE;
}

// The functions a header declares as `RTAPI <type> rt<Name>(`. Scanned by hand: std::regex's
// inlined automaton makes g++ 12 warn (-Wmaybe-uninitialized, inside <functional>) when built
// with -fsanitize=address (tools/sanitize.sh), and warnings are errors.
std::set<std::string> DeclaredEntryPoints(const std::string& text) {
  size_t i = 0;
  auto spaces = [&] {
    const size_t start = i;
    while (i < text.size() && std::isspace(static_cast<unsigned char>(text[i]))) ++i;
    return i > start;
  };
  auto word = [&] {
    const size_t start = i;
    while (i < text.size() &&
           (std::isalnum(static_cast<unsigned char>(text[i])) || text[i] == '_')) {
      ++i;
    }
    return text.substr(start, i - start);
  };
  std::set<std::string> names;
  for (size_t at = text.find("RTAPI"); at != std::string::npos; at = text.find("RTAPI", at + 1)) {
    i = at + 5;
    if (!spaces() || word().empty() || !spaces()) continue;
    const std::string name = word();
    spaces();
    if (name.size() > 2 && name.compare(0, 2, "rt") == 0 && i < text.size() && text[i] == '(') {
      names.insert(name);
    }
  }
  return names;
}

TEST_F(CApiSweepTest, EveryEntryPointIsSwept) {
  std::ifstream in(TESSERA_RT_H);
  ASSERT_TRUE(in) << TESSERA_RT_H;
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::set<std::string> declared = DeclaredEntryPoints(text);
  // OptiX 3.0's 256, the three CUDA-interop calls, OptiX 6's 23 GeometryTriangles calls, the
  // 26 texture sampler calls, OptiX 3.9's 7 buffer mip level calls and OptiX 3.6's
  // rtProgramGetId and rtContextGetProgramFromId.
  EXPECT_EQ(declared.size(), 317u);
  std::set<std::string> swept = {"rtContextGetErrorString"};  // void: own test below
  auto name = [](const char* call) {
    std::string s = call;
    return s.substr(0, s.find('('));
  };
  for (const auto& c : SubjectCases()) swept.insert(name(c.call));
  for (const auto& c : NullPointerCases()) swept.insert(name(c.call));
  for (const std::string& fn : declared) EXPECT_TRUE(swept.count(fn)) << fn << " is not swept";
}

TEST_F(CApiSweepTest, NullHandles) {
  for (const SubjectCase& c : SubjectCases()) {
    RTresult expected = HandleError(c.kind);
    EXPECT_EQ(c.run(w, nullptr), expected) << c.call;
    ExpectMessage(expected, c.call, KindWord(c.kind));
  }
}

TEST_F(CApiSweepTest, WrongTypeHandles) {
  for (const SubjectCase& c : SubjectCases()) {
    RTresult expected = HandleError(c.kind);
    EXPECT_EQ(c.run(w, w.Wrong(c.kind)), expected) << c.call;
    ExpectMessage(expected, c.call, KindWord(c.kind));
  }
}

TEST_F(CApiSweepTest, DestroyedHandles) {
  for (const SubjectCase& c : SubjectCases()) {
    RTresult expected = HandleError(c.kind);
    EXPECT_EQ(c.run(w, w.Dead(c.kind)), expected) << c.call;
    ExpectMessage(expected, c.call, "destroyed");
  }
}

TEST_F(CApiSweepTest, ForeignPointersAreNotHandles) {
  int not_a_handle = 0;
  for (const SubjectCase& c : SubjectCases()) {
    RTresult expected = HandleError(c.kind);
    EXPECT_EQ(c.run(w, &not_a_handle), expected) << c.call;
    ExpectMessage(expected, c.call, KindWord(c.kind));
  }
}

TEST_F(CApiSweepTest, NullPointers) {
  for (const CallCase& c : NullPointerCases()) {
    EXPECT_EQ(c.run(w), RT_ERROR_INVALID_VALUE) << c.call;
    ExpectMessage(RT_ERROR_INVALID_VALUE, c.call, "null");
  }
}

K ArgKind(const std::string& type, const std::string& call) {
  if (type == "RTprogram") return K::kProgram;
  if (type == "RTvariable") return K::kVariable;
  if (type == "RTacceleration") return K::kAcceleration;
  if (type == "RTgeometryinstance") return K::kInstance;
  if (type == "RTgeometry") return K::kGeometry;
  if (type == "RTmaterial") return K::kMaterial;
  if (type == "RTgeometrytriangles") return K::kTriangles;
  return call.rfind("rtVariableSetObject", 0) == 0 ? K::kBuffer : K::kGroup;
}

TEST_F(CApiSweepTest, BadHandleArguments) {
  for (const ArgCase& c : ArgCases()) {
    const std::string type = c.type;
    const bool any_object = type == "RTobject";
    EXPECT_EQ(c.run(w, nullptr), RT_ERROR_INVALID_VALUE) << c.call << " (null)";
    ExpectMessage(RT_ERROR_INVALID_VALUE, c.call, "null");
    EXPECT_EQ(c.run(w, w.Dead(ArgKind(type, c.call))), RT_ERROR_INVALID_VALUE)
        << c.call << " (destroyed)";
    ExpectMessage(RT_ERROR_INVALID_VALUE, c.call, "destroyed");
    // A geometry instance is never a valid RTobject argument; a buffer is never a valid typed
    // argument here.
    void* wrong = any_object ? static_cast<void*>(w.instance) : static_cast<void*>(w.buffer);
    RTresult expected = any_object ? RT_ERROR_TYPE_MISMATCH : RT_ERROR_INVALID_VALUE;
    EXPECT_EQ(c.run(w, wrong), expected) << c.call << " (wrong type)";
    ExpectMessage(expected, c.call, any_object ? "geometry instance" : "buffer");
  }
}

TEST_F(CApiSweepTest, HandlesFromAnotherContext) {
  RTcontext other;
  ASSERT_EQ(rtContextCreate(&other), RT_SUCCESS);
  RTprogram foreign;
  ASSERT_EQ(rtProgramCreateFromPTXFile(other, kTestModule, "ray_gen", &foreign), RT_SUCCESS);
  EXPECT_EQ(rtContextSetRayGenerationProgram(w.ctx, 0, foreign), RT_ERROR_INVALID_VALUE);
  ExpectMessage(RT_ERROR_INVALID_VALUE, "rtContextSetRayGenerationProgram", "another context");
  EXPECT_EQ(rtContextDestroy(other), RT_SUCCESS);
}

TEST_F(CApiSweepTest, IndicesOutOfRange) {
  struct Case {
    const char* call;
    RTresult expected;
    std::function<RTresult()> run;
  };
  RTsize dims[4] = {1, 1, 1, 1};
  int bad_device = 99;
  RTsize size = 0;
  const std::vector<Case> cases = {
      {"rtContextSetRayGenerationProgram", RT_ERROR_INVALID_VALUE,
       [&] { return rtContextSetRayGenerationProgram(w.ctx, 1, w.program); }},
      {"rtContextGetRayGenerationProgram", RT_ERROR_INVALID_VALUE,
       [&] { return rtContextGetRayGenerationProgram(w.ctx, 1, &w.out.program); }},
      {"rtContextSetExceptionProgram", RT_ERROR_INVALID_VALUE,
       [&] { return rtContextSetExceptionProgram(w.ctx, 7, w.program); }},
      {"rtContextGetExceptionProgram", RT_ERROR_INVALID_VALUE,
       [&] { return rtContextGetExceptionProgram(w.ctx, 7, &w.out.program); }},
      {"rtContextSetMissProgram", RT_ERROR_INVALID_VALUE,
       [&] { return rtContextSetMissProgram(w.ctx, 1, w.program); }},
      {"rtContextGetMissProgram", RT_ERROR_INVALID_VALUE,
       [&] { return rtContextGetMissProgram(w.ctx, 1, &w.out.program); }},
      {"rtContextGetVariable", RT_ERROR_INVALID_VALUE,
       [&] { return rtContextGetVariable(w.ctx, 99, &w.out.variable); }},
      {"rtProgramGetVariable", RT_ERROR_INVALID_VALUE,
       [&] { return rtProgramGetVariable(w.program, 0, &w.out.variable); }},
      {"rtGeometryGetVariable", RT_ERROR_INVALID_VALUE,
       [&] { return rtGeometryGetVariable(w.geometry, 0, &w.out.variable); }},
      {"rtMaterialGetVariable", RT_ERROR_INVALID_VALUE,
       [&] { return rtMaterialGetVariable(w.material, 0, &w.out.variable); }},
      {"rtGeometryInstanceGetVariable", RT_ERROR_INVALID_VALUE,
       [&] { return rtGeometryInstanceGetVariable(w.instance, 0, &w.out.variable); }},
      {"rtSelectorGetVariable", RT_ERROR_INVALID_VALUE,
       [&] { return rtSelectorGetVariable(w.selector, 0, &w.out.variable); }},
      {"rtGroupSetChild", RT_ERROR_INVALID_VALUE,
       [&] { return rtGroupSetChild(w.group, 1, w.transform); }},
      {"rtGroupGetChild", RT_ERROR_INVALID_VALUE,
       [&] { return rtGroupGetChild(w.group, 1, &w.obj); }},
      {"rtGroupGetChildType", RT_ERROR_INVALID_VALUE,
       [&] { return rtGroupGetChildType(w.group, 1, &w.type); }},
      {"rtSelectorSetChild", RT_ERROR_INVALID_VALUE,
       [&] { return rtSelectorSetChild(w.selector, 1, w.transform); }},
      {"rtSelectorGetChild", RT_ERROR_INVALID_VALUE,
       [&] { return rtSelectorGetChild(w.selector, 1, &w.obj); }},
      {"rtSelectorGetChildType", RT_ERROR_INVALID_VALUE,
       [&] { return rtSelectorGetChildType(w.selector, 1, &w.type); }},
      {"rtGeometryGroupSetChild", RT_ERROR_INVALID_VALUE,
       [&] { return rtGeometryGroupSetChild(w.geometry_group, 1, w.instance); }},
      {"rtGeometryGroupGetChild", RT_ERROR_INVALID_VALUE,
       [&] { return rtGeometryGroupGetChild(w.geometry_group, 1, &w.out.instance); }},
      {"rtGeometryInstanceSetMaterial", RT_ERROR_INVALID_VALUE,
       [&] { return rtGeometryInstanceSetMaterial(w.instance, 1, w.material); }},
      {"rtGeometryInstanceGetMaterial", RT_ERROR_INVALID_VALUE,
       [&] { return rtGeometryInstanceGetMaterial(w.instance, 1, &w.out.material); }},
      {"rtMaterialSetClosestHitProgram", RT_ERROR_INVALID_VALUE,
       [&] { return rtMaterialSetClosestHitProgram(w.material, 1, w.program); }},
      {"rtMaterialGetClosestHitProgram", RT_ERROR_INVALID_VALUE,
       [&] { return rtMaterialGetClosestHitProgram(w.material, 1, &w.out.program); }},
      {"rtMaterialSetAnyHitProgram", RT_ERROR_INVALID_VALUE,
       [&] { return rtMaterialSetAnyHitProgram(w.material, 1, w.program); }},
      {"rtMaterialGetAnyHitProgram", RT_ERROR_INVALID_VALUE,
       [&] { return rtMaterialGetAnyHitProgram(w.material, 1, &w.out.program); }},
      {"rtContextLaunch2D", RT_ERROR_INVALID_VALUE,
       [&] { return rtContextLaunch2D(w.ctx, 1, 4, 4); }},
      {"rtDeviceGetAttribute", RT_ERROR_INVALID_VALUE,
       [&] {
         return rtDeviceGetAttribute(99, RT_DEVICE_ATTRIBUTE_MULTIPROCESSOR_COUNT, sizeof(int),
                                     w.i);
       }},
      {"rtDeviceGetAttribute", RT_ERROR_INVALID_VALUE,
       [&] {
         return rtDeviceGetAttribute(-1, RT_DEVICE_ATTRIBUTE_MULTIPROCESSOR_COUNT, sizeof(int),
                                     w.i);
       }},
      {"rtContextSetDevices", RT_ERROR_INVALID_DEVICE,
       [&] { return rtContextSetDevices(w.ctx, 1, &bad_device); }},
      {"rtContextGetAttribute", RT_ERROR_INVALID_VALUE,
       [&] {
         return rtContextGetAttribute(
             w.ctx,
             static_cast<RTcontextattribute>(RT_CONTEXT_ATTRIBUTE_AVAILABLE_DEVICE_MEMORY + 99),
             sizeof(RTsize), &size);
       }},
      {"rtBufferSetSizev", RT_ERROR_INVALID_VALUE,
       [&] { return rtBufferSetSizev(w.buffer, 4, dims); }},
      {"rtBufferGetSizev", RT_ERROR_INVALID_VALUE,
       [&] { return rtBufferGetSizev(w.buffer, 0, dims); }},
  };
  for (const Case& c : cases) {
    EXPECT_EQ(c.run(), c.expected) << c.call;
    ExpectMessage(c.expected, c.call, nullptr);
  }
}

TEST_F(CApiSweepTest, TypeMismatches) {
  RTvariable v = w.variable;
  ASSERT_EQ(rtVariableSet3f(v, 1, 2, 3), RT_SUCCESS);
  float f[16];
  int i[4];
  unsigned u[4];
  unsigned char user[12];
  struct Case {
    const char* call;
    std::function<RTresult()> run;
  };
  const std::vector<Case> cases = {
      {"rtVariableSet1f", [&] { return rtVariableSet1f(v, 1); }},
      {"rtVariableSet4f", [&] { return rtVariableSet4f(v, 1, 2, 3, 4); }},
      {"rtVariableSet3i", [&] { return rtVariableSet3i(v, 1, 2, 3); }},
      {"rtVariableSet3ui", [&] { return rtVariableSet3ui(v, 1, 2, 3); }},
      {"rtVariableSetMatrix3x3fv", [&] { return rtVariableSetMatrix3x3fv(v, 0, w.f); }},
      {"rtVariableSetUserData", [&] { return rtVariableSetUserData(v, 12, user); }},
      {"rtVariableSetObject", [&] { return rtVariableSetObject(v, w.buffer); }},
      {"rtVariableGet1f", [&] { return rtVariableGet1f(v, f); }},
      {"rtVariableGet2f", [&] { return rtVariableGet2f(v, f, f + 1); }},
      {"rtVariableGet4fv", [&] { return rtVariableGet4fv(v, f); }},
      {"rtVariableGet3i", [&] { return rtVariableGet3i(v, i, i + 1, i + 2); }},
      {"rtVariableGet3iv", [&] { return rtVariableGet3iv(v, i); }},
      {"rtVariableGet3ui", [&] { return rtVariableGet3ui(v, u, u + 1, u + 2); }},
      {"rtVariableGet3uiv", [&] { return rtVariableGet3uiv(v, u); }},
      {"rtVariableGetMatrix3x4fv", [&] { return rtVariableGetMatrix3x4fv(v, 0, f); }},
      {"rtVariableGetUserData", [&] { return rtVariableGetUserData(v, 12, user); }},
      {"rtVariableGetObject", [&] { return rtVariableGetObject(v, &w.obj); }},
  };
  for (const Case& c : cases) {
    EXPECT_EQ(c.run(), RT_ERROR_TYPE_MISMATCH) << c.call;
    ExpectMessage(RT_ERROR_TYPE_MISMATCH, c.call, "float3");
  }

  // Object variables: a buffer variable cannot hold a program or a group, nor a value.
  RTvariable obj;
  ASSERT_EQ(rtContextDeclareVariable(w.ctx, "obj", &obj), RT_SUCCESS);
  ASSERT_EQ(rtVariableSetObject(obj, w.buffer), RT_SUCCESS);
  EXPECT_EQ(rtVariableSetObject(obj, w.program), RT_ERROR_TYPE_MISMATCH);
  EXPECT_EQ(rtVariableSetObject(obj, w.group), RT_ERROR_TYPE_MISMATCH);
  EXPECT_EQ(rtVariableSet1i(obj, 3), RT_ERROR_TYPE_MISMATCH);
  ExpectMessage(RT_ERROR_TYPE_MISMATCH, "rtVariableSet1i", "buffer");
  EXPECT_EQ(rtVariableSetObject(obj, w.material), RT_ERROR_TYPE_MISMATCH);
  ExpectMessage(RT_ERROR_TYPE_MISMATCH, "rtVariableSetObject", "material");

  // A variable without a value has no type to read.
  RTvariable unset;
  ASSERT_EQ(rtContextDeclareVariable(w.ctx, "unset", &unset), RT_SUCCESS);
  EXPECT_EQ(rtVariableGet1f(unset, f), RT_ERROR_TYPE_MISMATCH);
  ExpectMessage(RT_ERROR_TYPE_MISMATCH, "rtVariableGet1f", "no value");

  // Group children must be nodes.
  EXPECT_EQ(rtGroupSetChild(w.group, 0, w.acceleration), RT_ERROR_TYPE_MISMATCH);
  ExpectMessage(RT_ERROR_TYPE_MISMATCH, "rtGroupSetChild", "acceleration");
  EXPECT_EQ(rtTransformSetChild(w.transform, w.material), RT_ERROR_TYPE_MISMATCH);
  EXPECT_EQ(rtSelectorSetChild(w.selector, 0, w.geometry), RT_ERROR_TYPE_MISMATCH);
}

TEST_F(CApiSweepTest, ErrorStringFallbacks) {
  // No error recorded: a generic text for the code.
  EXPECT_NE(ErrorString(nullptr, RT_ERROR_NOT_SUPPORTED).find("RT_ERROR_NOT_SUPPORTED"),
            std::string::npos);
  EXPECT_FALSE(ErrorString(nullptr, static_cast<RTresult>(12345)).empty());
  rtContextGetErrorString(w.ctx, RT_SUCCESS, nullptr);  // must not crash
  // A failure on the context is reported for its code only.
  EXPECT_EQ(rtBufferSetFormat(w.buffer, static_cast<RTformat>(7)), RT_ERROR_INVALID_VALUE);
  EXPECT_NE(ErrorString(w.ctx, RT_ERROR_INVALID_VALUE).find("rtBufferSetFormat(buffer #"),
            std::string::npos);
  EXPECT_EQ(ErrorString(w.ctx, RT_ERROR_TYPE_MISMATCH).find("rtBufferSetFormat"),
            std::string::npos);
  // Errors with no context (null handle) are found through a null context too.
  EXPECT_EQ(rtBufferSetFormat(nullptr, RT_FORMAT_FLOAT), RT_ERROR_INVALID_VALUE);
  EXPECT_NE(ErrorString(nullptr, RT_ERROR_INVALID_VALUE).find("buffer handle is null"),
            std::string::npos);
}

}  // namespace
}  // namespace tessera::test

// OptiX 3.5+ buffer and program ids (rtBufferGetId, rtProgramGetId; rtBufferId,
// rtCallableProgramId, rtCallableProgramX): ids carried by buffers of RT_FORMAT_BUFFER_ID and
// RT_FORMAT_PROGRAM_ID, structs and int variables; writes through an id gathered to the host;
// bindless callables with their own scope; invalid ids with the exceptions on and off; host
// errors. Every launch on an in-process device and on 1 and 3 worker processes, with small tiles
// so that 3 devices share each launch.
#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

#include "rt_fixture.h"
#include "tessera/rt_ext.h"

namespace tessera::testing {
namespace {

constexpr char kModule[] = "bindless_programs";
constexpr unsigned kWidth = 8, kHeight = 6;

class BindlessTest : public GridFixture {
 protected:
  BindlessTest() : GridFixture(kWidth, kHeight) {}
  void SetUp() override {
    GridFixture::SetUp();
    const RTsize tile[2] = {2, 2};
    Ok(tesseraContextSetTileSize(ctx_, 2, tile));
  }

  // An unbound buffer of `format` (RT_FORMAT_USER: elements of `element_size`) holding `values`.
  template <typename T>
  RTbuffer Unbound(unsigned type, RTformat format, const std::vector<size_t>& dims,
                   const std::vector<T>& values, size_t element_size = 0) {
    RTbuffer b = nullptr;
    Ok(rtBufferCreate(ctx_, type, &b));
    Ok(rtBufferSetFormat(b, format));
    if (element_size != 0) Ok(rtBufferSetElementSize(b, element_size));
    if (dims.size() == 1) Ok(rtBufferSetSize1D(b, dims[0]));
    if (dims.size() == 2) Ok(rtBufferSetSize2D(b, dims[0], dims[1]));
    if (!values.empty()) Write(b, values);
    return b;
  }
  template <typename T>
  void Write(RTbuffer b, const std::vector<T>& values) {
    void* p = nullptr;
    Ok(rtBufferMap(b, &p));
    std::memcpy(p, values.data(), values.size() * sizeof(T));
    Ok(rtBufferUnmap(b));
  }
  int BufferId(RTbuffer b) {
    int id = 0;
    EXPECT_EQ(rtBufferGetId(b, &id), RT_SUCCESS);
    return id;
  }
  int ProgramId(RTprogram p) {
    int id = 0;
    EXPECT_EQ(rtProgramGetId(p, &id), RT_SUCCESS);
    return id;
  }
  RTvariable ProgramVar(RTprogram p, const char* name) {
    RTvariable v = nullptr;
    EXPECT_EQ(rtProgramDeclareVariable(p, name, &v), RT_SUCCESS);
    return v;
  }
  void RayGen(const char* function) {
    Ok(rtContextSetRayGenerationProgram(ctx_, 0, Program(kModule, function)));
  }
};

TEST_P(BindlessTest, ABufferOfBufferIdsReachesBuffersNoVariableNames) {
  std::vector<std::vector<float>> contents = {{1.f, 2.f, 3.f}, {7.f}, {0.5f, 1.5f}};
  std::vector<int> ids;
  for (const auto& c : contents) {
    ids.push_back(BufferId(Unbound(RT_BUFFER_INPUT, RT_FORMAT_FLOAT, {c.size()}, c)));
  }
  RTbuffer tables = Unbound(RT_BUFFER_INPUT, RT_FORMAT_BUFFER_ID, {ids.size()}, ids);
  Ok(rtVariableSetObject(ContextVar("tables"), tables));
  RayGen("read_tables");
  auto expected = [&](unsigned x, unsigned y) {
    const auto& c = contents[y % contents.size()];
    return c[x % c.size()] + 100.f * static_cast<float>(c.size());
  };
  ExpectEach(Launch(), expected);

  // Ids travel as the buffer's bytes: a new order is a new mapping, and new contents arrive.
  std::swap(ids[0], ids[2]);
  Write(tables, ids);
  std::swap(contents[0], contents[2]);
  ExpectEach(Launch(), expected);
}

// Ids much sparser than the buffers they name (objects made in between) resolve through the
// engine's sorted table instead of its array: the same results.
TEST_P(BindlessTest, SparseIdsResolveAlike) {
  for (int i = 0; i < 9000; ++i) {
    RTmaterial m = nullptr;
    Ok(rtMaterialCreate(ctx_, &m));
  }
  const std::vector<float> values = {4.f, 5.f};
  RTbuffer b = Unbound(RT_BUFFER_INPUT, RT_FORMAT_FLOAT, {values.size()}, values);
  ASSERT_GT(BufferId(b), 9000);
  RTbuffer tables =
      Unbound(RT_BUFFER_INPUT, RT_FORMAT_BUFFER_ID, {1}, std::vector<int>{BufferId(b)});
  Ok(rtVariableSetObject(ContextVar("tables"), tables));
  RayGen("read_tables");
  ExpectEach(Launch(), [&](unsigned x, unsigned) { return values[x % 2] + 200.f; });
}

TEST_P(BindlessTest, AStructCarriesBufferIds) {
  struct Mesh {
    int positions, indices;
    float scale;
  };
  const std::vector<float> positions = {1, 2, 3, 4, 5, 6, 7, 8, 9};  // three float3
  const std::vector<int> indices = {2, 0, 1, 1, 2};
  Mesh mesh{BufferId(Unbound(RT_BUFFER_INPUT, RT_FORMAT_FLOAT3, {3}, positions)),
            BufferId(Unbound(RT_BUFFER_INPUT, RT_FORMAT_INT, {indices.size()}, indices)), 0.5f};
  Ok(rtVariableSetUserData(ContextVar("mesh"), sizeof(mesh), &mesh));
  RayGen("read_mesh");
  ExpectEach(Launch(), [&](unsigned x, unsigned y) {
    const int p = indices[(y * 4 + x) % indices.size()];
    return (positions[3 * p] + 10.f * positions[3 * p + 1] + 100.f * positions[3 * p + 2]) * 0.5f;
  });
}

// An OUTPUT buffer written only through an id comes back from every device that wrote it; an
// INPUT_OUTPUT one accumulates across launches.
TEST_P(BindlessTest, WritesThroughAnIdReachTheHost) {
  std::vector<float> src(kWidth * kHeight);
  for (size_t i = 0; i < src.size(); ++i) src[i] = static_cast<float>(i) * 0.25f;
  RTbuffer source = Unbound(RT_BUFFER_INPUT, RT_FORMAT_FLOAT, {kWidth, kHeight}, src);
  Ok(rtVariableSet1i(ContextVar("source"), BufferId(source)));
  RayGen("copy_by_id");

  RTbuffer out = Unbound(RT_BUFFER_INPUT_OUTPUT, RT_FORMAT_FLOAT, {kWidth, kHeight},
                         std::vector<float>(kWidth * kHeight, 1.f));
  Ok(rtVariableSet1i(ContextVar("target"), BufferId(out)));
  ExpectEach(Launch(), [](unsigned, unsigned) { return kWidth * 1000.f + kHeight; });
  std::vector<float> got = ReadAs<float>(out);
  for (size_t i = 0; i < src.size(); ++i) ASSERT_EQ(got[i], 1.f + 2.f * src[i]) << i;
  Launch();
  got = ReadAs<float>(out);
  for (size_t i = 0; i < src.size(); ++i) ASSERT_EQ(got[i], 1.f + 4.f * src[i]) << i;

  // An OUTPUT buffer: programs read what they wrote, starting from zeros on every device.
  RTbuffer output =
      Unbound(RT_BUFFER_OUTPUT, RT_FORMAT_FLOAT, {kWidth, kHeight}, std::vector<float>());
  Ok(rtVariableSet1i(ContextVar("target"), BufferId(output)));
  Launch();
  got = ReadAs<float>(output);
  for (size_t i = 0; i < src.size(); ++i) ASSERT_EQ(got[i], 2.f * src[i]) << i;
}

class BindlessMaterialsTest : public BindlessTest {
 protected:
  // One primitive every ray hits; its closest hit `ch` (ch_shade: calls shaders[x % count](y + 1)).
  void Scene(const std::vector<RTprogram>& shaders, const char* ch = "ch_shade") {
    scene_ = MakeInstance(Program(kModule, "intersect"), Program(kModule, "bounds"), 1,
                          Program(kModule, ch));
    Ok(rtVariableSetObject(ContextVar("top_object"), scene_.group));
    RayGen("trace_raygen");
    std::vector<int> ids;
    for (RTprogram p : shaders) ids.push_back(ProgramId(p));
    shaders_ = Unbound(RT_BUFFER_INPUT, RT_FORMAT_PROGRAM_ID, {ids.size()}, ids);
    Ok(rtVariableSetObject(ContextVar("shaders"), shaders_));
  }
  RTvariable MaterialVar(const char* name) {
    RTvariable v = nullptr;
    EXPECT_EQ(rtMaterialDeclareVariable(scene_.material, name, &v), RT_SUCCESS);
    return v;
  }
  Instance scene_;
  RTbuffer shaders_ = nullptr;
};

TEST_P(BindlessMaterialsTest, EachHitCallsTheProgramItsIdSelectsWithTheCalleesOwnScope) {
  // One function, two program objects: each call sees its own program's `factor`.
  RTprogram by3 = Program(kModule, "scale_by");
  RTprogram by5 = Program(kModule, "scale_by");
  RTprogram square = Program(kModule, "square");
  Ok(rtVariableSet1f(ProgramVar(by3, "factor"), 3.f));
  Ok(rtVariableSet1f(ProgramVar(by5, "factor"), 5.f));
  Scene({by3, square, by5});
  // The caller's scopes (here its material) do not reach a bindless callee: only its own and the
  // context's do.
  Ok(rtVariableSet1f(MaterialVar("offset"), 1000.f));
  Ok(rtVariableSet1f(MaterialVar("factor"), 1000.f));
  Ok(rtVariableSet1f(ContextVar("offset"), 0.25f));
  const auto expected = [](unsigned x, unsigned y) {
    const float a = static_cast<float>(y) + 1.f;
    switch (x % 3) {
      case 0:
        return a * 3.f + 0.25f;
      case 1:
        return a * a + 0.25f;
      default:
        return a * 5.f + 0.25f;
    }
  };
  ExpectEach(Launch(), expected);

  // New ids in the buffer: the calls follow it.
  int ids[3] = {ProgramId(square), ProgramId(square), ProgramId(by3)};
  Write(shaders_, std::vector<int>(ids, ids + 3));
  ExpectEach(Launch(), [](unsigned x, unsigned y) {
    const float a = static_cast<float>(y) + 1.f;
    return x % 3 == 2 ? a * 3.f + 0.25f : a * a + 0.25f;
  });
}

TEST_P(BindlessMaterialsTest, ACalleeCallsAnotherByAnIdOfItsOwnScope) {
  RTprogram twice = Program(kModule, "twice_inner");
  RTprogram by7 = Program(kModule, "scale_by");
  Ok(rtVariableSet1f(ProgramVar(by7, "factor"), 7.f));
  Ok(rtVariableSet1i(ProgramVar(twice, "inner"), ProgramId(by7)));
  Scene({twice});
  ExpectEach(Launch(), [](unsigned, unsigned y) { return 2.f * 7.f * (y + 1.f); });
}

// rtCallableProgramX is bound, as an rtCallableProgram variable: set with rtVariableSetObject, its
// callee sees its caller's scopes (here the material) after its own.
TEST_P(BindlessMaterialsTest, ABoundCallableProgramXSeesItsCallersScopes) {
  RTprogram by = Program(kModule, "scale_by");
  Scene({by}, "ch_bound");
  Ok(rtVariableSetObject(MaterialVar("bound_fn"), by));
  Ok(rtVariableSet1f(MaterialVar("factor"), 6.f));
  Ok(rtVariableSet1f(ContextVar("offset"), 0.5f));
  ExpectEach(Launch(), [](unsigned, unsigned y) { return 6.f * (y + 1.f) + 0.5f; });
}

class BindlessInvalidTest : public BindlessTest {
 protected:
  void Use(int mode, int buffer_id, int program_id, bool exceptions) {
    RayGen("invalid_ids");
    Ok(rtContextSetExceptionProgram(ctx_, 0, Program(kModule, "on_exception")));
    Ok(rtContextSetExceptionEnabled(ctx_, RT_EXCEPTION_ALL, exceptions ? 1 : 0));
    Ok(rtVariableSet1i(ContextVar("mode"), mode));
    Ok(rtVariableSet1i(ContextVar("some_buffer"), buffer_id));
    Ok(rtVariableSet1i(ContextVar("some_program"), program_id));
  }
  void ExpectAll(float value) {
    ExpectEach(Launch(), [&](unsigned, unsigned) { return value; });
  }
};

TEST_P(BindlessInvalidTest, InvalidIdsRaiseTheirExceptions) {
  const int unknown = 1 << 20;
  for (int id : {0, unknown}) {
    SCOPED_TRACE(id);
    Use(0, id, 0, true);
    ExpectAll(-static_cast<float>(RT_EXCEPTION_BUFFER_ID_INVALID));
    Use(2, 0, id, true);
    ExpectAll(-static_cast<float>(RT_EXCEPTION_PROGRAM_ID_INVALID));
  }
  // A buffer's id is no program's.
  RTbuffer b = Unbound(RT_BUFFER_INPUT, RT_FORMAT_FLOAT, {kWidth}, std::vector<float>(kWidth, 1.f));
  Use(2, 0, BufferId(b), true);
  ExpectAll(-static_cast<float>(RT_EXCEPTION_PROGRAM_ID_INVALID));
  // A valid id, indexed past its end.
  Use(4, BufferId(b), 0, true);
  ExpectAll(-static_cast<float>(RT_EXCEPTION_BUFFER_INDEX_OUT_OF_BOUNDS));
}

TEST_P(BindlessInvalidTest, WithTheExceptionsOffInvalidIdsAreEmptyAndCallsAreSkipped) {
  Use(0, 0, 0, false);
  ExpectAll(0.f);  // reads zero, size 0
  Use(1, 1 << 20, 0, false);
  ExpectAll(0.f);  // a write went to scratch memory, the read saw zeros
  Use(2, 0, 0, false);
  ExpectAll(0.f);  // float(): the call was skipped
  Use(5, 0, 0, false);
  ExpectAll(10.f);  // both null: false, false, equal ids
  // A call whose type has no default value cannot be skipped: the launch fails, naming it.
  Use(3, 0, 0, false);
  const std::string message = FailedLaunch();
  EXPECT_NE(message.find("rtCallableProgramId 0 called from"), std::string::npos) << message;
  EXPECT_NE(message.find("RT_PROGRAM_ID_NULL"), std::string::npos) << message;
}

TEST_P(BindlessInvalidTest, ValidIdsCallAndReadThrough) {
  RTprogram make = Program(kModule, "make_no_default");
  Use(3, 0, 0, true);
  Ok(rtVariableSet1i(ContextVar("no_default"), ProgramId(make)));
  ExpectAll(3.5f);
  RTbuffer b = Unbound(RT_BUFFER_INPUT, RT_FORMAT_FLOAT, {kWidth}, std::vector<float>(kWidth, 2.f));
  Use(5, BufferId(b), ProgramId(make), true);
  ExpectAll(3.f);  // both valid, different ids
}

TEST_P(BindlessTest, ABufferOfOtherElementsFailsTheLaunchNamingIt) {
  RTbuffer b = Unbound(RT_BUFFER_INPUT, RT_FORMAT_FLOAT, {4}, std::vector<float>(4, 1.f));
  Ok(rtVariableSet1i(ContextVar("wide"), BufferId(b)));
  RayGen("read_wide");
  const std::string message = FailedLaunch();
  EXPECT_NE(message.find("rtBufferId of 1D elements of 16 bytes reaches buffer #" +
                         std::to_string(BufferId(b)) + ", which is 1D with elements of 4 bytes"),
            std::string::npos)
      << message;
}

// OptiX 3.6's templated rtCallableProgram (RT_USE_TEMPLATED_RTCALLABLEPROGRAM) is the bound kind
// too: set with rtVariableSetObject, a callee of another module, its `factor` from the context.
TEST_P(BindlessTest, TheTemplatedRtCallableProgramIsBound) {
  Ok(rtContextSetRayGenerationProgram(ctx_, 0,
                                      Program("bindless_templated_programs", "call_templated")));
  Ok(rtVariableSetObject(ContextVar("templated_fn"), Program(kModule, "scale_by")));
  Ok(rtVariableSet1f(ContextVar("factor"), 3.f));
  ExpectEach(Launch(), [](unsigned x, unsigned) { return 3.f * static_cast<float>(x); });
}

// A program with an id that cannot be bound fails only the launches that call it, naming it.
TEST_P(BindlessMaterialsTest, AnUnbindableProgramFailsOnlyTheLaunchesThatCallIt) {
  RTprogram broken = Program(kModule, "scale_by");
  Ok(rtVariableSet1i(ProgramVar(broken, "factor"), 3));  // declared as a float
  RTprogram square = Program(kModule, "square");
  Scene({square});
  const int broken_id = ProgramId(broken);
  ExpectEach(Launch(), [](unsigned, unsigned y) { return (y + 1.f) * (y + 1.f); });

  Write(shaders_, std::vector<int>{broken_id});
  const std::string message = FailedLaunch();
  EXPECT_NE(message.find("rtCallableProgramId " + std::to_string(broken_id) + " called from"),
            std::string::npos)
      << message;
  EXPECT_NE(message.find("variable 'factor' is declared as float but was set as int"),
            std::string::npos)
      << message;
}

// An rtCallableProgramId variable takes the program's id, not the program.
TEST_P(BindlessInvalidTest, AProgramIdVariableSetToTheProgramSaysHow) {
  Use(3, 0, 0, true);
  Ok(rtVariableSetObject(ContextVar("no_default"), Program(kModule, "make_no_default")));
  const std::string message = FailedLaunch();
  EXPECT_NE(message.find("variable 'no_default' is declared with rtDeclareVariable but bound to "
                         "a program"),
            std::string::npos)
      << message;
  EXPECT_NE(message.find("rtCallableProgramId takes the object's id, set with rtVariableSet1i"),
            std::string::npos)
      << message;
}

INSTANTIATE_TEST_SUITE_P(Devices, BindlessTest, ::testing::Values("inproc", "local:1", "local:3"),
                         DeviceName);
INSTANTIATE_TEST_SUITE_P(Devices, BindlessMaterialsTest,
                         ::testing::Values("inproc", "local:1", "local:3"), DeviceName);
INSTANTIATE_TEST_SUITE_P(Devices, BindlessInvalidTest,
                         ::testing::Values("inproc", "local:1", "local:3"), DeviceName);

// ---- Host side ---------------------------------------------------------------------------------

class BindlessHostTest : public RtFixture {};

TEST_F(BindlessHostTest, ProgramIdsRoundTripAndUnknownIdsAreErrors) {
  RTprogram p = Program(kModule, "square");
  int id = 0;
  Ok(rtProgramGetId(p, &id));
  EXPECT_GT(id, 0);
  int again = 0;
  Ok(rtProgramGetId(p, &again));
  EXPECT_EQ(again, id);
  RTprogram back = nullptr;
  Ok(rtContextGetProgramFromId(ctx_, id, &back));
  EXPECT_EQ(back, p);

  for (int bad : {0, -3, id + 1000}) {
    SCOPED_TRACE(bad);
    EXPECT_EQ(rtContextGetProgramFromId(ctx_, bad, &back), RT_ERROR_INVALID_VALUE);
    EXPECT_NE(Error(RT_ERROR_INVALID_VALUE).find("no live program has id " + std::to_string(bad)),
              std::string::npos)
        << Error(RT_ERROR_INVALID_VALUE);
  }
  // A buffer's id is no program's, and a destroyed program's id is gone.
  RTbuffer b = nullptr;
  Ok(rtBufferCreate(ctx_, RT_BUFFER_INPUT, &b));
  int buffer_id = 0;
  Ok(rtBufferGetId(b, &buffer_id));
  EXPECT_EQ(rtContextGetProgramFromId(ctx_, buffer_id, &back), RT_ERROR_INVALID_VALUE);
  Ok(rtProgramDestroy(p));
  EXPECT_EQ(rtContextGetProgramFromId(ctx_, id, &back), RT_ERROR_INVALID_VALUE);
  EXPECT_NE(rtProgramGetId(p, &again), RT_SUCCESS);
}

TEST_F(BindlessHostTest, ProgramIdBuffersAreInputOnly) {
  for (unsigned type : {RT_BUFFER_OUTPUT, RT_BUFFER_INPUT_OUTPUT}) {
    RTbuffer b = nullptr;
    Ok(rtBufferCreate(ctx_, type, &b));
    EXPECT_EQ(rtBufferSetFormat(b, RT_FORMAT_PROGRAM_ID), RT_ERROR_INVALID_VALUE);
    EXPECT_NE(Error(RT_ERROR_INVALID_VALUE).find("RT_FORMAT_PROGRAM_ID needs an RT_BUFFER_INPUT"),
              std::string::npos);
  }
  RTbuffer b = nullptr;
  Ok(rtBufferCreate(ctx_, RT_BUFFER_INPUT, &b));
  Ok(rtBufferSetFormat(b, RT_FORMAT_PROGRAM_ID));
  RTsize size = 0;
  Ok(rtBufferGetElementSize(b, &size));
  EXPECT_EQ(size, sizeof(int));
}

}  // namespace
}  // namespace tessera::testing

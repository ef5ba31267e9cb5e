// OptiX 3.0 callable programs (guide, "Callable Programs"): the host sets an rtCallableProgram
// variable to a program like any object variable, through any scope of the caller; the callable
// program's own variables come from its own scope and then its caller's; it sees and writes its
// caller's semantic values in any module; it may trace, recurse, throw, and take pickled
// pointers. Each on an in-process device and on worker processes.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "rt_fixture.h"
#include "tessera/rt_ext.h"

namespace tessera::testing {
namespace {

constexpr char kModule[] = "callable_programs";
constexpr char kOther[] = "callable_other_programs";
constexpr char kPlain[] = "callable_plain_programs";
constexpr unsigned kWidth = 6, kHeight = 3;

class CallableTest : public GridFixture {
 protected:
  CallableTest() : GridFixture(kWidth, kHeight) {}

  RTvariable ProgramVar(RTprogram p, const char* name) {
    RTvariable v = nullptr;
    EXPECT_EQ(rtProgramDeclareVariable(p, name, &v), RT_SUCCESS);
    return v;
  }

  // A scene every ray of trace_raygen hits once at t = 1, with closest hit `ch`.
  Instance Scene(RTprogram ch, const char* intersect = "intersect") {
    Instance i = MakeInstance(Program(kModule, intersect), Program(kModule, "bounds"), 1, ch);
    Ok(rtVariableSetObject(ContextVar("top_object"), i.group));
    Ok(rtContextSetRayGenerationProgram(ctx_, 0, Program(kModule, "trace_raygen")));
    return i;
  }
};

TEST_P(CallableTest, RayGenerationCallsWhatTheHostSetsWithTheCalleesOwnVariables) {
  RTprogram raygen = Program(kModule, "call_from_raygen");
  Ok(rtContextSetRayGenerationProgram(ctx_, 0, raygen));
  Ok(rtVariableSet1f(ContextVar("scale"), 2.f));
  Ok(rtVariableSetObject(ContextVar("shade"), Program(kModule, "add")));
  ExpectEach(Launch(), [](float x, float y) { return x + y + 2000.f; });

  // Swapped between launches; the callee's own scope comes before the context, and the caller
  // gets back its own value of the variable they share.
  RTprogram times = Program(kModule, "times");
  Ok(rtVariableSetObject(ContextVar("shade"), times));
  RTvariable own = ProgramVar(times, "scale");
  Ok(rtVariableSet1f(own, 10.f));
  Ok(rtVariableSet1f(ProgramVar(raygen, "scale"), 3.f));
  ExpectEach(Launch(), [](float x, float y) { return x * y * 10.f + 3000.f; });

  Ok(rtProgramRemoveVariable(times, own));
  ExpectEach(Launch(), [](float x, float y) { return x * y * 2.f + 3000.f; });
}

TEST_P(CallableTest, ClosestHitScopesChooseTheProgramAndItsVariables) {
  Instance scene = Scene(Program(kModule, "ch_tint"));
  RTvariable v = nullptr;
  Ok(rtMaterialDeclareVariable(scene.material, "tint", &v));
  Ok(rtVariableSetObject(v, Program(kModule, "tint_up")));
  Ok(rtMaterialDeclareVariable(scene.material, "level", &v));
  Ok(rtVariableSet1f(v, 5.f));
  Ok(rtVariableSet1f(ContextVar("level"), 100.f));
  ExpectEach(Launch(), [](float, float) { return 1.f + 5.f; });

  // The geometry instance's definitions shadow the material's (Table 5), for the program
  // variable and for the callee's own variables alike.
  Ok(rtGeometryInstanceDeclareVariable(scene.instance, "tint", &v));
  Ok(rtVariableSetObject(v, Program(kModule, "tint_down")));
  ExpectEach(Launch(), [](float, float) { return 1.f - 5.f; });
  Ok(rtGeometryInstanceDeclareVariable(scene.instance, "level", &v));
  Ok(rtVariableSet1f(v, 7.f));
  ExpectEach(Launch(), [](float, float) { return 1.f - 7.f; });

  // A callable program of another module, with its own declaration of `level`.
  Ok(rtGeometryInstanceQueryVariable(scene.instance, "tint", &v));
  Ok(rtVariableSetObject(v, Program(kOther, "tint_twice")));
  ExpectEach(Launch(), [](float, float) { return 2.f * 1.f + 7.f; });
}

// shade_here and shade_other read the hit's distance (1), attribute (x) and payload, write the
// payload, and trace once more: 100 + x at depth 1, and 1001 * (100 + x) in all.
TEST_P(CallableTest, ACalleeSharesItsCallersValuesInAnyModule) {
  const std::pair<const char*, const char*> cases[] = {{kModule, "shade_here"},
                                                       {kOther, "shade_other"}};
  for (const char* caller : {kModule, kPlain}) {
    for (const auto& [module, function] : cases) {
      SCOPED_TRACE(std::string(caller) + " calls " + module + ":" + function);
      Instance scene = Scene(Program(caller, caller == kModule ? "ch_shade" : "ch_plain"));
      RTvariable v = nullptr;
      Ok(rtMaterialDeclareVariable(scene.material, "shade_hit", &v));
      Ok(rtVariableSetObject(v, Program(module, function)));
      ExpectEach(Launch(), [](float x, float) { return 1001.f * (100.f + x); });
    }
  }
}

// The callee traces, and the nested hit runs the caller's own program: the caller's values
// (attribute, distance) must be its own after the call.
TEST_P(CallableTest, ACalleeThatTracesLeavesItsCallersValuesAlone) {
  Instance scene = Scene(Program(kModule, "ch_values_after"));
  RTvariable v = nullptr;
  Ok(rtMaterialDeclareVariable(scene.material, "shade_hit", &v));
  Ok(rtVariableSetObject(v, Program(kOther, "trace_shifted")));
  ExpectEach(Launch(), [](float x, float) { return x + 0.5f + 1000.f; });
}

// A callee of another module ends the any-hit program that called it: what it wrote to the
// payload before stays (OptiX keeps an any-hit program's payload writes).
TEST_P(CallableTest, AnAnyHitProgramsCalleeMayEndIt) {
  Instance scene = MakeInstance(Program(kModule, "intersect_indexed"), Program(kModule, "bounds"),
                                3, Program(kModule, "ch_add"), Program(kModule, "ah_calls"));
  Ok(rtVariableSetObject(ContextVar("top_object"), scene.group));
  Ok(rtContextSetRayGenerationProgram(ctx_, 0, Program(kModule, "trace_raygen")));
  RTvariable v = nullptr;
  Ok(rtMaterialDeclareVariable(scene.material, "on_candidate", &v));
  Ok(rtVariableSetObject(v, Program(kOther, "count_and_ignore")));
  // Every candidate ignored: 100 + t for t = 1, 2, 3, and no closest hit.
  ExpectEach(Launch(), [](float, float) { return 306.f; });
  // One candidate, which the callee accepts and ends the ray at: the closest hit adds 1000 * t.
  Instance one = MakeInstance(Program(kModule, "intersect_indexed"), Program(kModule, "bounds"), 1,
                              Program(kModule, "ch_add"), Program(kModule, "ah_calls"));
  Ok(rtVariableSetObject(ContextVar("top_object"), one.group));
  Ok(rtMaterialDeclareVariable(one.material, "on_candidate", &v));
  Ok(rtVariableSetObject(v, Program(kOther, "count_and_terminate")));
  ExpectEach(Launch(), [](float, float) { return 101.f + 1000.f; });
}

TEST_P(CallableTest, AnIntersectionProgramsCalleeWritesAttributes) {
  Instance scene = Scene(Program(kModule, "ch_attribute"), "intersect_via_callable");
  RTvariable v = nullptr;
  Ok(rtGeometryDeclareVariable(scene.geometry, "make_attributes", &v));
  Ok(rtVariableSetObject(v, Program(kModule, "attributes_here")));
  ExpectEach(Launch(), [](float x, float) { return x + 0.25f; });
  Ok(rtVariableSetObject(v, Program(kOther, "attributes_other")));
  ExpectEach(Launch(), [](float x, float) { return x + 0.5f; });
}

TEST_P(CallableTest, RecursionWorksAndEndlessRecursionOverflowsTheStack) {
  Ok(rtContextSetRayGenerationProgram(ctx_, 0, Program(kModule, "call_factorial")));
  Ok(rtVariableSetObject(ContextVar("fact"), Program(kModule, "factorial")));
  ExpectEach(Launch(), [](float x, float) {
    float f = 1.f;
    for (int i = 2; i <= static_cast<int>(x) + 1; ++i) f *= static_cast<float>(i);
    return f;
  });

  Ok(rtContextSetExceptionProgram(ctx_, 0, Program(kModule, "on_exception")));
  Ok(rtContextSetExceptionEnabled(ctx_, RT_EXCEPTION_STACK_OVERFLOW, 1));
  Ok(rtVariableSetObject(ContextVar("fact"), Program(kModule, "endless")));
  ExpectEach(Launch(),
             [](float, float) { return -static_cast<float>(RT_EXCEPTION_STACK_OVERFLOW); });
}

TEST_P(CallableTest, ACalleeThrowsAndTakesPickledPointers) {
  Ok(rtContextSetRayGenerationProgram(ctx_, 0, Program(kModule, "call_from_raygen")));
  Ok(rtContextSetExceptionProgram(ctx_, 0, Program(kModule, "on_exception")));
  Ok(rtContextSetExceptionEnabled(ctx_, RT_EXCEPTION_USER, 1));
  Ok(rtVariableSetObject(ContextVar("shade"), Program(kModule, "throws")));
  ExpectEach(Launch(), [](float, float) { return -static_cast<float>(RT_EXCEPTION_USER + 7); });

  // The guide's example: 42 plus one.
  Ok(rtContextSetRayGenerationProgram(ctx_, 0, Program(kModule, "pickled")));
  Ok(rtVariableSetObject(ContextVar("pbr"), Program(kModule, "plus_one")));
  ExpectEach(Launch(), [](float, float) { return 43.f; });
}

TEST_P(CallableTest, VariablesSetToTheWrongThingAreNamed) {
  RTprogram raygen = Program(kModule, "call_from_raygen");
  Ok(rtContextSetRayGenerationProgram(ctx_, 0, raygen));
  std::string message = FailedLaunch();
  EXPECT_NE(message.find("rtCallableProgram 'shade' called from ray generation program "
                         "'call_from_raygen'"),
            std::string::npos)
      << message;
  EXPECT_NE(message.find("no scope sets it"), std::string::npos) << message;

  RTbuffer b = nullptr;
  Ok(rtBufferCreate(ctx_, RT_BUFFER_INPUT, &b));
  Ok(rtBufferSetFormat(b, RT_FORMAT_FLOAT));
  Ok(rtBufferSetSize1D(b, 1));
  RTvariable shade = ProgramVar(raygen, "shade");
  Ok(rtVariableSetObject(shade, b));
  message = FailedLaunch();
  EXPECT_NE(message.find("rtCallableProgram 'shade' is set to a buffer"), std::string::npos)
      << message;

  // A plain variable set to a program says what to declare instead.
  Ok(rtProgramRemoveVariable(raygen, shade));
  Ok(rtVariableSetObject(ContextVar("shade"), Program(kModule, "add")));
  Ok(rtVariableSetObject(ProgramVar(raygen, "scale"), Program(kModule, "add")));
  message = FailedLaunch();
  EXPECT_NE(message.find("'scale' is declared with rtDeclareVariable but bound to a program"),
            std::string::npos)
      << message;
  EXPECT_NE(message.find("rtCallableProgram for programs"), std::string::npos) << message;
}

// Where deep recursion raises RT_EXCEPTION_STACK_OVERFLOW depends on the program alone, not on
// the thread that ran the launch index (TBB's threads have half the stack of others), the
// thread count or the device set.
class CallableDepthTest : public RtFixture {};

TEST_F(CallableDepthTest, RecursionRunsOutAtTheSameDepthOnEveryThreadAndDevice) {
  constexpr unsigned kIndices = 40;
  std::vector<float> first;
  for (auto [spec, threads] :
       {std::pair{"inproc", 1}, std::pair{"inproc", 2}, std::pair{"local:2", 0}}) {
    SCOPED_TRACE(std::string(spec) + " with " + std::to_string(threads) + " threads");
    rtContextDestroy(ctx_);
    Ok(rtContextCreate(&ctx_));
    Ok(tesseraContextSetDeviceSpec(ctx_, spec));
    if (threads > 0) {
      Ok(rtContextSetAttribute(ctx_, RT_CONTEXT_ATTRIBUTE_CPU_NUM_THREADS, sizeof(threads),
                               &threads));
    }
    Ok(rtContextSetEntryPointCount(ctx_, 1));
    Ok(rtContextSetRayGenerationProgram(ctx_, 0, Program(kModule, "call_fat")));
    Ok(rtContextSetExceptionProgram(ctx_, 0, Program(kModule, "on_exception")));
    Ok(rtContextSetExceptionEnabled(ctx_, RT_EXCEPTION_STACK_OVERFLOW, 1));
    Ok(rtVariableSetObject(ContextVar("fat"), Program(kModule, "fat_levels")));
    RTbuffer result = Buffer2D("result", RT_BUFFER_OUTPUT, RT_FORMAT_FLOAT, kIndices, 1);
    // Tiles of one launch index each, so that both threads run some.
    const RTsize one[2] = {1, 1};
    Ok(tesseraContextSetTileSize(ctx_, 2, one));
    Ok(rtContextLaunch2D(ctx_, 0, kIndices, 1));
    std::vector<float> values = ReadAs<float>(result);
    // Some indices finish and some run out: the test straddles the limit.
    EXPECT_EQ(values[1], 200.f);
    EXPECT_EQ(values[kIndices - 1], -static_cast<float>(RT_EXCEPTION_STACK_OVERFLOW));
    if (first.empty()) {
      first = values;
    } else {
      EXPECT_EQ(values, first);
    }
  }
}

// Twenty thousand program objects of one callable function, each calling the one before it:
// binding them must not recurse once per link (the plan's thread has a bounded stack).
TEST_F(CallableDepthTest, ALongChainOfCallableProgramsBinds) {
#ifdef TESSERA_SANITIZER_BUILD
  // ASan's redzones make every native frame of the calls several times larger: 20,000 nested
  // calls outgrow the native stack a launch index may use, and the launch (rightly) raises
  // RT_EXCEPTION_STACK_OVERFLOW. Fewer links still bind and run the whole chain.
  constexpr int kLinks = 4000;
#else
  constexpr int kLinks = 20000;
#endif
  Ok(tesseraContextSetDeviceSpec(ctx_, "inproc"));
  Ok(rtContextSetEntryPointCount(ctx_, 1));
  Ok(rtContextSetRayGenerationProgram(ctx_, 0, Program(kModule, "call_chain")));
  RTbuffer result = Buffer2D("result", RT_BUFFER_OUTPUT, RT_FORMAT_FLOAT, 1, 1);
  RTprogram previous = Program(kModule, "chain_end");
  for (int i = 0; i < kLinks; ++i) {
    RTprogram link = Program(kModule, "chain_link");
    RTvariable v = nullptr;
    Ok(rtProgramDeclareVariable(link, "next_link", &v));
    Ok(rtVariableSetObject(v, previous));
    previous = link;
  }
  Ok(rtVariableSetObject(ContextVar("next_link"), previous));
  Ok(rtContextLaunch2D(ctx_, 0, 1, 1));
  EXPECT_EQ(ReadAs<float>(result)[0], static_cast<float>(kLinks));
}

INSTANTIATE_TEST_SUITE_P(Devices, CallableTest, ::testing::Values("inproc", "local:2"), DeviceName);

}  // namespace
}  // namespace tessera::testing

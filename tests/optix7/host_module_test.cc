// Modules (from source text, a .cu file, a .so file, module bytes; compile errors in the log),
// program groups of every kind, and the stack-size helpers of optix_stack_size.h.
#include <optix_stack_size.h>

#include <cstring>
#include <fstream>
#include <iterator>
#include <string>

#include "host_api_fixture.h"

namespace tessera_test {
namespace {

using ModuleTest = OptixHostTest;

std::string ReadFile(const char* path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

TEST_F(ModuleTest, FromSourceStringWithItsLog) {
  char log[2048];
  size_t log_size = sizeof(log);
  OptixModule module = nullptr;
  ASSERT_EQ(optixModuleCreate(context_, &module_options_, &pipeline_options_, kAllKindsSource,
                              std::strlen(kAllKindsSource), log, &log_size, &module),
            OPTIX_SUCCESS)
      << log;
  ASSERT_NE(module, nullptr);
  EXPECT_NE(std::string(log).find("optixModuleCreate: module "), std::string::npos) << log;
  EXPECT_NE(std::string(log).find("from <string>"), std::string::npos) << log;
  EXPECT_EQ(log_size, std::strlen(log) + 1);
  OptixModuleCompileState state{};
  ASSERT_EQ(optixModuleGetCompilationState(module, &state), OPTIX_SUCCESS);
  EXPECT_EQ(state, OPTIX_MODULE_COMPILE_STATE_COMPLETED);
  EXPECT_EQ(optixModuleDestroy(module), OPTIX_SUCCESS);
  EXPECT_EQ(optixModuleDestroy(module), OPTIX_ERROR_INVALID_VALUE);
  EXPECT_EQ(optixModuleGetCompilationState(module, &state), OPTIX_ERROR_INVALID_VALUE);
}

// The SDK's sample module as a .cu path, as its compiled .so path, and as the .so's bytes.
TEST_F(ModuleTest, FromCuFileSoFileAndModuleBytes) {
  const std::string bytes = ReadFile(TESSERA_TEST_PROGRAM_SO);
  ASSERT_EQ(bytes.compare(0, 4,
                          "\x7f"
                          "ELF"),
            0);
  const std::string inputs[] = {TESSERA_TEST_PROGRAM_CU, TESSERA_TEST_PROGRAM_SO, bytes};
  for (const std::string& input : inputs) {
    OptixModule module = nullptr;
    ASSERT_EQ(optixModuleCreate(context_, &module_options_, &pipeline_options_, input.data(),
                                input.size(), nullptr, nullptr, &module),
              OPTIX_SUCCESS)
        << input.substr(0, 100);
    OptixProgramGroupDesc desc = Raygen(module, "__raygen__rg");
    OptixProgramGroup group = nullptr;
    EXPECT_EQ(optixProgramGroupCreate(context_, &desc, 1, nullptr, nullptr, nullptr, &group),
              OPTIX_SUCCESS);
    EXPECT_EQ(optixProgramGroupDestroy(group), OPTIX_SUCCESS);
    EXPECT_EQ(optixModuleDestroy(module), OPTIX_SUCCESS);
  }
  // Not a shared object: INVALID_INPUT, saying so.
  const std::string not_so = std::string(
                                 "\x7f"
                                 "ELF") +
                             std::string(60, '\0');
  OptixModule module = nullptr;
  EXPECT_EQ(optixModuleCreate(context_, &module_options_, &pipeline_options_, not_so.data(),
                              not_so.size(), nullptr, nullptr, &module),
            OPTIX_ERROR_INVALID_INPUT);
  EXPECT_TRUE(Logged(2, "not a program module"));
}

TEST_F(ModuleTest, CompileErrorReachesLogBufferAndCallbackCutToTheBuffer) {
  const std::string bad =
      "#include <optix.h>\nextern \"C\" __global__ void __raygen__rg() { "
      "undeclared_thing(); }\n";
  char log[2048];
  size_t log_size = sizeof(log);
  OptixModule module = nullptr;
  EXPECT_EQ(optixModuleCreate(context_, &module_options_, &pipeline_options_, bad.c_str(),
                              bad.size(), log, &log_size, &module),
            OPTIX_ERROR_INVALID_INPUT);
  EXPECT_EQ(module, nullptr);
  EXPECT_NE(std::string(log).find("undeclared_thing"), std::string::npos) << log;
  EXPECT_TRUE(Logged(2, "undeclared_thing"));
  const size_t whole = log_size;
  EXPECT_GT(whole, 20u);

  char small[16];
  size_t small_size = sizeof(small);
  EXPECT_EQ(optixModuleCreate(context_, &module_options_, &pipeline_options_, bad.c_str(),
                              bad.size(), small, &small_size, &module),
            OPTIX_ERROR_INVALID_INPUT);
  EXPECT_EQ(std::strlen(small), 15u);    // cut short, NUL-terminated
  EXPECT_GT(small_size, sizeof(small));  // the whole log's size says it was cut
  EXPECT_EQ(std::string(small), std::string(log).substr(0, 15));
}

TEST_F(ModuleTest, CompileOptionsAreChecked) {
  auto create = [&](const OptixModuleCompileOptions& m, const OptixPipelineCompileOptions& p) {
    OptixModule module = nullptr;
    return optixModuleCreate(context_, &m, &p, kAllKindsSource, std::strlen(kAllKindsSource),
                             nullptr, nullptr, &module);
  };
  OptixPipelineCompileOptions p = pipeline_options_;
  p.numPayloadValues = 33;
  EXPECT_EQ(create(module_options_, p), OPTIX_ERROR_INVALID_VALUE);
  EXPECT_TRUE(Logged(2, "pipelineCompileOptions.numPayloadValues is 33; OptiX allows 0 to 32"));
  p = pipeline_options_;
  p.numAttributeValues = 9;
  EXPECT_EQ(create(module_options_, p), OPTIX_ERROR_INVALID_VALUE);
  EXPECT_TRUE(Logged(2, "numAttributeValues is 9"));
  p = pipeline_options_;
  p.exceptionFlags = 0x10;
  EXPECT_EQ(create(module_options_, p), OPTIX_ERROR_INVALID_VALUE);
  EXPECT_TRUE(Logged(2, "exceptionFlags 0x10"));
  p = pipeline_options_;
  p.usesPrimitiveTypeFlags = 1u << 20;
  EXPECT_EQ(create(module_options_, p), OPTIX_ERROR_INVALID_VALUE);
  EXPECT_TRUE(Logged(2, "usesPrimitiveTypeFlags 0x100000"));

  OptixModuleCompileOptions m = module_options_;
  unsigned semantics[2] = {OPTIX_PAYLOAD_SEMANTICS_TRACE_CALLER_READ_WRITE,
                           OPTIX_PAYLOAD_SEMANTICS_CH_WRITE};
  OptixPayloadType type{2, semantics};
  m.numPayloadTypes = 1;
  m.payloadTypes = &type;
  EXPECT_EQ(create(m, pipeline_options_), OPTIX_ERROR_INVALID_VALUE);  // numPayloadValues 3
  EXPECT_TRUE(Logged(2, "numPayloadValues must be 0 when the module gives payload types"));
  p = pipeline_options_;
  p.numPayloadValues = 0;
  type.numPayloadValues = 40;
  EXPECT_EQ(create(m, p), OPTIX_ERROR_INVALID_VALUE);
  EXPECT_TRUE(Logged(2, "payloadTypes[0].numPayloadValues is 40"));
  m = module_options_;
  m.optLevel = static_cast<OptixCompileOptimizationLevel>(7);
  EXPECT_EQ(create(m, pipeline_options_), OPTIX_ERROR_INVALID_VALUE);
  EXPECT_TRUE(Logged(2, "moduleCompileOptions.optLevel 0x7"));
  m = module_options_;
  const int bound = 7;
  OptixModuleCompileBoundValueEntry entry{0, sizeof(bound), &bound, "bound"};
  m.boundValues = &entry;
  m.numBoundValues = 1;
  EXPECT_EQ(create(m, pipeline_options_), OPTIX_SUCCESS);  // accepted, not specialized on

  // The launch parameters' name: a function is an error, a missing variable a warning.
  p = pipeline_options_;
  p.pipelineLaunchParamsVariableName = "__raygen__rg";
  EXPECT_EQ(create(module_options_, p), OPTIX_ERROR_INVALID_VALUE);
  EXPECT_TRUE(Logged(2, "pipelineLaunchParamsVariableName '__raygen__rg' names a function"));
  p.pipelineLaunchParamsVariableName = "launch_params";
  EXPECT_EQ(create(module_options_, p), OPTIX_SUCCESS);
  EXPECT_TRUE(Logged(3, "exports no variable 'launch_params'"));

  OptixModule module = nullptr;
  EXPECT_EQ(optixModuleCreate(context_, &module_options_, &pipeline_options_, nullptr, 10, nullptr,
                              nullptr, &module),
            OPTIX_ERROR_INVALID_VALUE);
  EXPECT_TRUE(Logged(2, "input is null or inputSize is 0"));
  EXPECT_EQ(optixModuleCreate(context_, nullptr, &pipeline_options_, kAllKindsSource, 10, nullptr,
                              nullptr, &module),
            OPTIX_ERROR_INVALID_VALUE);
  EXPECT_TRUE(Logged(2, "moduleCompileOptions is null"));
}

TEST_F(ModuleTest, WithTasksRunsOneTaskOnce) {
  OptixModule module = nullptr;
  OptixTask task = nullptr;
  ASSERT_EQ(
      optixModuleCreateWithTasks(context_, &module_options_, &pipeline_options_, kAllKindsSource,
                                 std::strlen(kAllKindsSource), nullptr, nullptr, &module, &task),
      OPTIX_SUCCESS);
  ASSERT_NE(task, nullptr);
  OptixTask more[4];
  unsigned created = 99;
  EXPECT_EQ(optixTaskExecute(task, more, 4, &created), OPTIX_SUCCESS);
  EXPECT_EQ(created, 0u);
  EXPECT_EQ(optixTaskExecute(task, more, 4, &created), OPTIX_ERROR_INVALID_VALUE);
  OptixModuleCompileState state{};
  ASSERT_EQ(optixModuleGetCompilationState(module, &state), OPTIX_SUCCESS);
  EXPECT_EQ(state, OPTIX_MODULE_COMPILE_STATE_COMPLETED);
}

TEST_F(ModuleTest, BuiltinIntersectionModules) {
  OptixBuiltinISOptions is{};
  is.builtinISModuleType = OPTIX_PRIMITIVE_TYPE_SPHERE;
  OptixModule sphere = nullptr;
  // usesPrimitiveTypeFlags 0 means triangles and custom primitives: no spheres.
  EXPECT_EQ(optixBuiltinISModuleGet(context_, &module_options_, &pipeline_options_, &is, &sphere),
            OPTIX_ERROR_INVALID_VALUE);
  EXPECT_TRUE(Logged(2, "usesPrimitiveTypeFlags 0x80000001 lacks the flag 0x40"));
  pipeline_options_.usesPrimitiveTypeFlags =
      OPTIX_PRIMITIVE_TYPE_FLAGS_TRIANGLE | OPTIX_PRIMITIVE_TYPE_FLAGS_SPHERE;
  ASSERT_EQ(optixBuiltinISModuleGet(context_, &module_options_, &pipeline_options_, &is, &sphere),
            OPTIX_SUCCESS);
  is.builtinISModuleType = OPTIX_PRIMITIVE_TYPE_CUSTOM;
  OptixModule custom = nullptr;
  EXPECT_EQ(optixBuiltinISModuleGet(context_, &module_options_, &pipeline_options_, &is, &custom),
            OPTIX_ERROR_INVALID_VALUE);

  OptixModule module = CompileModule();
  OptixProgramGroupDesc desc{};
  desc.kind = OPTIX_PROGRAM_GROUP_KIND_HITGROUP;
  desc.hitgroup.moduleCH = module;
  desc.hitgroup.entryFunctionNameCH = "__closesthit__ch";
  desc.hitgroup.moduleIS = sphere;
  OptixProgramGroup group = nullptr;
  ASSERT_EQ(optixProgramGroupCreate(context_, &desc, 1, nullptr, nullptr, nullptr, &group),
            OPTIX_SUCCESS);
  OptixStackSizes sizes{};
  ASSERT_EQ(optixProgramGroupGetStackSize(group, &sizes, nullptr), OPTIX_SUCCESS);
  EXPECT_EQ(sizes.cssCH, 64u);
  EXPECT_EQ(sizes.cssIS, 0u);  // built-in
  desc.hitgroup.entryFunctionNameIS = "__intersection__sphere";
  EXPECT_EQ(optixProgramGroupCreate(context_, &desc, 1, nullptr, nullptr, nullptr, &group),
            OPTIX_ERROR_INVALID_VALUE);
  EXPECT_TRUE(Logged(2, "the entry function name must be null for built-in intersection 0x2506"));
  desc.hitgroup.entryFunctionNameIS = nullptr;
  desc.hitgroup.moduleCH = sphere;
  EXPECT_EQ(optixProgramGroupCreate(context_, &desc, 1, nullptr, nullptr, nullptr, &group),
            OPTIX_ERROR_INVALID_VALUE);
  EXPECT_TRUE(Logged(2, "can only be a hit group's intersection module"));
}

using ProgramGroupTest = OptixHostTest;

TEST_F(ProgramGroupTest, EveryKindAndItsStackSizes) {
  OptixModule m = CompileModule();
  OptixProgramGroupDesc d[7] = {};
  d[0] = Raygen(m, "__raygen__rg");
  d[1].kind = OPTIX_PROGRAM_GROUP_KIND_MISS;
  d[1].miss = {m, "__miss__ms"};
  d[2].kind = OPTIX_PROGRAM_GROUP_KIND_MISS;  // no program: rays that miss do nothing
  d[3].kind = OPTIX_PROGRAM_GROUP_KIND_EXCEPTION;
  d[3].exception = {m, "__exception__ex"};
  d[4].kind = OPTIX_PROGRAM_GROUP_KIND_HITGROUP;
  d[4].hitgroup = {m, "__closesthit__ch", m, "__anyhit__ah", m, "__intersection__is"};
  d[5].kind = OPTIX_PROGRAM_GROUP_KIND_HITGROUP;  // any hit only, on triangles
  d[5].hitgroup.moduleAH = m;
  d[5].hitgroup.entryFunctionNameAH = "__anyhit__ah";
  d[6].kind = OPTIX_PROGRAM_GROUP_KIND_CALLABLES;
  d[6].callables = {m, "__direct_callable__dc", m, "__continuation_callable__cc"};
  OptixProgramGroupOptions options{};
  OptixProgramGroup g[7] = {};
  ASSERT_EQ(optixProgramGroupCreate(context_, d, 7, &options, nullptr, nullptr, g), OPTIX_SUCCESS);

  const OptixStackSizes expected[7] = {
      {96, 0, 0, 0, 0, 0, 0},  {0, 32, 0, 0, 0, 0, 0},   {0, 0, 0, 0, 0, 0, 0},
      {0, 0, 0, 0, 0, 0, 0},   {0, 0, 64, 16, 32, 0, 0}, {0, 0, 0, 16, 0, 0, 0},
      {0, 0, 0, 0, 0, 64, 32},
  };
  OptixStackSizes all{};
  for (int i = 0; i < 7; ++i) {
    OptixStackSizes s{};
    ASSERT_EQ(optixProgramGroupGetStackSize(g[i], &s, nullptr), OPTIX_SUCCESS);
    EXPECT_EQ(std::memcmp(&s, &expected[i], sizeof(s)), 0) << "group " << i;
  }

  OptixPipelineLinkOptions link{};
  link.maxTraceDepth = 2;
  OptixPipeline pipeline = nullptr;
  char log[1024];
  size_t log_size = sizeof(log);
  ASSERT_EQ(
      optixPipelineCreate(context_, &pipeline_options_, &link, g, 7, log, &log_size, &pipeline),
      OPTIX_SUCCESS)
      << log;
  EXPECT_EQ(log_size, 0u);  // nothing to say
  // optix_stack_size.h (Programming Guide listings 6.14/6.15): css = cssRG + cssCCTree +
  // (depth - 1) * (max(CH, MS) + cssCCTree) + max(max(CH, MS) + cssCCTree, IS + AH)
  // = 96 + 64 + 1 * (64 + 64) + max(128, 48) = 416.
  for (int i = 0; i < 7; ++i) {
    ASSERT_EQ(optixUtilAccumulateStackSizes(g[i], &all, pipeline), OPTIX_SUCCESS);
  }
  unsigned dc_traversal = 0, dc_state = 0, css = 0;
  ASSERT_EQ(optixUtilComputeStackSizes(&all, 2, 1, 1, &dc_traversal, &dc_state, &css),
            OPTIX_SUCCESS);
  EXPECT_EQ(dc_traversal, 32u);
  EXPECT_EQ(dc_state, 32u);
  EXPECT_EQ(css, 416u);
  EXPECT_EQ(optixPipelineSetStackSize(pipeline, dc_traversal, dc_state, css, 2), OPTIX_SUCCESS);
  EXPECT_EQ(optixPipelineSetStackSize(pipeline, dc_traversal, dc_state, css, 0),
            OPTIX_ERROR_INVALID_VALUE);
  EXPECT_TRUE(Logged(2, "maxTraversableGraphDepth is 0"));
  EXPECT_EQ(optixProgramGroupGetStackSize(g[0], &all, reinterpret_cast<OptixPipeline>(g[1])),
            OPTIX_ERROR_INVALID_VALUE);  // a program group is no pipeline
  EXPECT_EQ(optixPipelineDestroy(pipeline), OPTIX_SUCCESS);
  EXPECT_EQ(optixPipelineDestroy(pipeline), OPTIX_ERROR_INVALID_VALUE);
  for (OptixProgramGroup group : g) EXPECT_EQ(optixProgramGroupDestroy(group), OPTIX_SUCCESS);
  EXPECT_EQ(optixProgramGroupDestroy(g[0]), OPTIX_ERROR_INVALID_VALUE);
}

TEST_F(ProgramGroupTest, WrongNamesAndModulesAreRefusedWithMessages) {
  OptixModule m = CompileModule();
  struct Case {
    OptixProgramGroupDesc desc;
    const char* message;
  };
  OptixProgramGroupDesc miss_named_raygen = Raygen(m, "__raygen__rg");
  miss_named_raygen.kind = OPTIX_PROGRAM_GROUP_KIND_MISS;
  OptixProgramGroupDesc empty_callables{};
  empty_callables.kind = OPTIX_PROGRAM_GROUP_KIND_CALLABLES;
  OptixProgramGroupDesc bad_kind = Raygen(m, "__raygen__rg");
  bad_kind.kind = static_cast<OptixProgramGroupKind>(0x2420);
  OptixProgramGroupDesc flags = Raygen(m, "__raygen__rg");
  flags.flags = 1;
  const Case cases[] = {
      {Raygen(m, "__miss__ms"),
       "programDescriptions[0].raygen: entry function '__miss__ms' does not start with "
       "'__raygen__'"},
      {Raygen(m, "__raygen__nope"),
       "programDescriptions[0].raygen: module <string> exports no function '__raygen__nope'"},
      {Raygen(m, nullptr), "programDescriptions[0].raygen: entry function name is null"},
      {Raygen(nullptr, "__raygen__rg"),
       "names entry function '__raygen__rg' but its module is null"},
      {Raygen(nullptr, nullptr), "a raygen group needs a module and an entry function"},
      {Raygen(reinterpret_cast<OptixModule>(context_), "__raygen__rg"), "raygen module (0x"},
      {miss_named_raygen, "does not start with '__miss__'"},
      {empty_callables, "a callables group needs a direct or a continuation callable"},
      {bad_kind, "programDescriptions[0].kind 0x2420 is no OptixProgramGroupKind"},
      {flags, "programDescriptions[0].flags is 0x1"},
  };
  for (const Case& c : cases) {
    char log[1024];
    size_t log_size = sizeof(log);
    OptixProgramGroup group = nullptr;
    EXPECT_EQ(optixProgramGroupCreate(context_, &c.desc, 1, nullptr, log, &log_size, &group),
              OPTIX_ERROR_INVALID_VALUE)
        << c.message;
    EXPECT_EQ(group, nullptr);
    EXPECT_NE(std::string(log).find(c.message), std::string::npos) << log;
    EXPECT_TRUE(Logged(2, c.message)) << c.message;
  }
  // The helper function exists but is not an entry point of the right kind by its name; `params`
  // is a variable.
  OptixProgramGroupDesc d[2] = {Raygen(m, "__raygen__rg"), Raygen(m, "__raygen__missing")};
  OptixProgramGroup groups[2] = {};
  EXPECT_EQ(optixProgramGroupCreate(context_, d, 2, nullptr, nullptr, nullptr, groups),
            OPTIX_ERROR_INVALID_VALUE);
  EXPECT_EQ(groups[0], nullptr);  // all or nothing
  EXPECT_TRUE(Logged(2, "programDescriptions[1].raygen"));
}

}  // namespace
}  // namespace tessera_test

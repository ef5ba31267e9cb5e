#include "host_api_fixture.h"

#include <optix_function_table_definition.h>

namespace tessera_test {

const char kAllKindsSource[] = R"(
#include <optix.h>
struct Params { unsigned int* out; };
extern "C" { __constant__ Params params; }
extern "C" __global__ void __raygen__rg() { params.out[optixGetLaunchIndex().x] = 1; }
extern "C" __global__ void __miss__ms() {}
extern "C" __global__ void __closesthit__ch() {}
extern "C" __global__ void __anyhit__ah() {}
extern "C" __global__ void __intersection__is() {}
extern "C" __global__ void __exception__ex() {}
extern "C" __device__ float __direct_callable__dc(float x) { return 2.0f * x; }
extern "C" __device__ float __continuation_callable__cc(float x) { return x + 1.0f; }
extern "C" __device__ void helper() {}
)";

OptixProgramGroupDesc Raygen(OptixModule module, const char* name) {
  OptixProgramGroupDesc d{};
  d.kind = OPTIX_PROGRAM_GROUP_KIND_RAYGEN;
  d.raygen.module = module;
  d.raygen.entryFunctionName = name;
  return d;
}

namespace {

void Collect(unsigned level, const char* tag, const char* message, void* data) {
  static_cast<std::vector<LogMessage>*>(data)->push_back({level, tag, message});
}

}  // namespace

void OptixHostTest::SetUp() {
  ASSERT_EQ(optixInit(), OPTIX_SUCCESS);
  context_ = CreateContext(false);
  ASSERT_NE(context_, nullptr);
  module_options_.optLevel = OPTIX_COMPILE_OPTIMIZATION_DEFAULT;
  pipeline_options_.numPayloadValues = 3;
  pipeline_options_.numAttributeValues = 2;
  pipeline_options_.exceptionFlags = OPTIX_EXCEPTION_FLAG_NONE;
  pipeline_options_.pipelineLaunchParamsVariableName = "params";
  pipeline_options_.traversableGraphFlags = OPTIX_TRAVERSABLE_GRAPH_FLAG_ALLOW_ANY;
}

void OptixHostTest::TearDown() {
  for (OptixDeviceContext c : contexts_) EXPECT_EQ(optixDeviceContextDestroy(c), OPTIX_SUCCESS);
}

OptixDeviceContext OptixHostTest::CreateContext(bool validation) {
  OptixDeviceContextOptions options{};
  options.logCallbackFunction = &Collect;
  options.logCallbackData = &log_;
  options.logCallbackLevel = 4;
  options.validationMode = validation ? OPTIX_DEVICE_CONTEXT_VALIDATION_MODE_ALL
                                      : OPTIX_DEVICE_CONTEXT_VALIDATION_MODE_OFF;
  OptixDeviceContext context = nullptr;
  EXPECT_EQ(optixDeviceContextCreate(0, &options, &context), OPTIX_SUCCESS);
  // Modules compile into the build tree: a second run of the tests finds them there.
  EXPECT_EQ(optixDeviceContextSetCacheLocation(context, TESSERA_TEST_MODULE_CACHE), OPTIX_SUCCESS);
  contexts_.push_back(context);
  return context;
}

bool OptixHostTest::Logged(unsigned level, const std::string& text) const {
  for (const LogMessage& m : log_) {
    if (m.level == level && m.message.find(text) != std::string::npos) return true;
  }
  return false;
}

OptixModule OptixHostTest::CompileModule(const std::string& source, OptixDeviceContext context) {
  char log[2048];
  size_t log_size = sizeof(log);
  OptixModule module = nullptr;
  const OptixResult r =
      optixModuleCreate(context != nullptr ? context : context_, &module_options_,
                        &pipeline_options_, source.c_str(), source.size(), log, &log_size, &module);
  EXPECT_EQ(r, OPTIX_SUCCESS) << log;
  return module;
}

}  // namespace tessera_test

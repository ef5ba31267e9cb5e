// The OptiX 7 consumer: optixInit, a module from the embedded program, a raygen-only pipeline, one
// launch of 64x16 on the devices of TESSERA_DEVICES, and a check of what it wrote.
#include <cuda_runtime.h>
#include <optix.h>
#include <optix_function_table_definition.h>
#include <optix_stubs.h>

#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

extern "C" const char index_programs[];

#define CHECK(call)                                                    \
  do {                                                                 \
    if ((call) != 0) {                                                 \
      std::fprintf(stderr, "%s failed at line %d\n", #call, __LINE__); \
      return 1;                                                        \
    }                                                                  \
  } while (0)

struct Params {
  unsigned int* out;
  unsigned int width;
};
struct alignas(OPTIX_SBT_RECORD_ALIGNMENT) Record {
  char header[OPTIX_SBT_RECORD_HEADER_SIZE];
  unsigned int add;
};

int main() {
  const unsigned width = 64, height = 16;
  CHECK(cudaFree(nullptr));
  CHECK(optixInit());
  OptixDeviceContext context = nullptr;
  CHECK(optixDeviceContextCreate(nullptr, nullptr, &context));
  OptixModuleCompileOptions module_options = {};
  OptixPipelineCompileOptions pipeline_options = {};
  pipeline_options.numPayloadValues = 0;
  pipeline_options.pipelineLaunchParamsVariableName = "params";
  const std::string input = index_programs;
  OptixModule module = nullptr;
  CHECK(optixModuleCreate(context, &module_options, &pipeline_options, input.c_str(), input.size(),
                          nullptr, nullptr, &module));
  OptixProgramGroupDesc desc = {};
  desc.kind = OPTIX_PROGRAM_GROUP_KIND_RAYGEN;
  desc.raygen.module = module;
  desc.raygen.entryFunctionName = "__raygen__index";
  OptixProgramGroupOptions group_options = {};
  OptixProgramGroup group = nullptr;
  CHECK(optixProgramGroupCreate(context, &desc, 1, &group_options, nullptr, nullptr, &group));
  OptixPipelineLinkOptions link = {};
  link.maxTraceDepth = 1;
  OptixPipeline pipeline = nullptr;
  CHECK(optixPipelineCreate(context, &pipeline_options, &link, &group, 1, nullptr, nullptr,
                            &pipeline));
  Record record;
  CHECK(optixSbtRecordPackHeader(group, &record));
  record.add = 1000;
  void *d_record = nullptr, *d_out = nullptr, *d_params = nullptr;
  CHECK(cudaMalloc(&d_record, sizeof(record)));
  CHECK(cudaMemcpy(d_record, &record, sizeof(record), cudaMemcpyHostToDevice));
  CHECK(cudaMalloc(&d_out, width * height * sizeof(unsigned)));
  Params params = {static_cast<unsigned*>(d_out), width};
  CHECK(cudaMalloc(&d_params, sizeof(params)));
  CHECK(cudaMemcpy(d_params, &params, sizeof(params), cudaMemcpyHostToDevice));
  OptixShaderBindingTable sbt = {};
  sbt.raygenRecord = reinterpret_cast<CUdeviceptr>(d_record);
  CHECK(optixLaunch(pipeline, nullptr, reinterpret_cast<CUdeviceptr>(d_params), sizeof(params),
                    &sbt, width, height, 1));
  std::vector<unsigned> out(width * height);
  CHECK(cudaMemcpy(out.data(), d_out, out.size() * sizeof(unsigned), cudaMemcpyDeviceToHost));
  for (unsigned i = 0; i < out.size(); ++i) {
    if (out[i] != i + 1000) {
      std::fprintf(stderr, "index %u holds %u, not %u\n", i, out[i], i + 1000);
      return 1;
    }
  }
  std::printf("the OptiX 7 launch wrote what it should\n");
  optixPipelineDestroy(pipeline);
  optixProgramGroupDestroy(group);
  optixModuleDestroy(module);
  optixDeviceContextDestroy(context);
  return 0;
}

// The exceptions sample: a user exception (optixThrowException with details) and a trace-depth
// overflow, both reported to the pipeline's exception program, which records the code and
// details per pixel. Checks what it caught, prints a summary and writes exceptions.png.
#include <cuda_runtime.h>
#include <optix.h>
#include <optix_function_table_definition.h>
#include <optix_stubs.h>

#include <cstdio>
#include <vector>

#include "../common/sample_util.h"
#include "../common/vec_math.h"
#include "exceptions.h"

extern "C" const char exceptions_programs[];

int main(int argc, char** argv) {
  const std::string out = sample::Option(argc, argv, "--out", "exceptions.png");
  const unsigned width = 96, height = 32;
  const unsigned max_depth = 4;
  OptixDeviceContext context = sample::CreateContext();

  const std::vector<float3> quad = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0},
                                    {-1, -1, 0}, {1, 1, 0},  {-1, 1, 0}};
  CUdeviceptr d_quad = sample::Upload(quad);
  const uint32_t flags[1] = {OPTIX_GEOMETRY_FLAG_NONE};
  OptixBuildInput input = {};
  input.type = OPTIX_BUILD_INPUT_TYPE_TRIANGLES;
  input.triangleArray.vertexFormat = OPTIX_VERTEX_FORMAT_FLOAT3;
  input.triangleArray.numVertices = static_cast<unsigned>(quad.size());
  input.triangleArray.vertexBuffers = &d_quad;
  input.triangleArray.flags = flags;
  input.triangleArray.numSbtRecords = 1;
  CUdeviceptr storage = 0;
  const OptixTraversableHandle gas = sample::BuildAccel(context, &input, 1, 0, &storage);

  OptixModuleCompileOptions module_options = {};
  OptixPipelineCompileOptions pipeline_options = {};
  pipeline_options.traversableGraphFlags = OPTIX_TRAVERSABLE_GRAPH_FLAG_ALLOW_SINGLE_GAS;
  pipeline_options.numPayloadValues = 2;
  pipeline_options.numAttributeValues = 2;
  pipeline_options.exceptionFlags = OPTIX_EXCEPTION_FLAG_USER | OPTIX_EXCEPTION_FLAG_TRACE_DEPTH;
  pipeline_options.pipelineLaunchParamsVariableName = "params";
  OptixModule module =
      sample::CreateModule(context, module_options, pipeline_options, exceptions_programs);
  OptixProgramGroupDesc descs[4] = {};
  descs[0].kind = OPTIX_PROGRAM_GROUP_KIND_RAYGEN;
  descs[0].raygen = {module, "__raygen__rg"};
  descs[1].kind = OPTIX_PROGRAM_GROUP_KIND_MISS;
  descs[1].miss = {module, "__miss__none"};
  descs[2].kind = OPTIX_PROGRAM_GROUP_KIND_HITGROUP;
  descs[2].hitgroup.moduleCH = module;
  descs[2].hitgroup.entryFunctionNameCH = "__closesthit__again";
  descs[3].kind = OPTIX_PROGRAM_GROUP_KIND_EXCEPTION;
  descs[3].exception = {module, "__exception__record"};
  OptixProgramGroupOptions group_options = {};
  OptixProgramGroup groups[4] = {};
  OPTIX_CHECK(optixProgramGroupCreate(context, descs, 4, &group_options, nullptr, nullptr, groups));
  OptixPipelineLinkOptions link_options = {};
  link_options.maxTraceDepth = max_depth;
  OptixPipeline pipeline = nullptr;
  OPTIX_CHECK(optixPipelineCreate(context, &pipeline_options, &link_options, groups, 4, nullptr,
                                  nullptr, &pipeline));

  OptixShaderBindingTable sbt = {};
  sbt.raygenRecord = sample::UploadRecord(groups[0], EmptyData{});
  sbt.missRecordBase = sample::UploadRecord(groups[1], EmptyData{});
  sbt.missRecordStrideInBytes = sizeof(SbtRecord<EmptyData>);
  sbt.missRecordCount = 1;
  sbt.hitgroupRecordBase = sample::UploadRecord(groups[2], EmptyData{});
  sbt.hitgroupRecordStrideInBytes = sizeof(SbtRecord<EmptyData>);
  sbt.hitgroupRecordCount = 1;
  sbt.exceptionRecord = sample::UploadRecord(groups[3], EmptyData{});

  const size_t pixels = size_t(width) * height;
  void *image = nullptr, *codes = nullptr, *details = nullptr;
  CUDA_CHECK(cudaMalloc(&image, pixels * sizeof(uchar4)));
  CUDA_CHECK(cudaMalloc(&codes, pixels * sizeof(int)));
  CUDA_CHECK(cudaMalloc(&details, pixels * sizeof(unsigned)));
  Params params = {static_cast<uchar4*>(image),    width, height, gas, static_cast<int*>(codes),
                   static_cast<unsigned*>(details)};
  CUdeviceptr d_params = sample::Upload(&params, sizeof(params));
  OPTIX_CHECK(optixLaunch(pipeline, nullptr, d_params, sizeof(Params), &sbt, width, height, 1));
  CUDA_CHECK(cudaDeviceSynchronize());

  const auto got_codes = sample::Download<int>(reinterpret_cast<CUdeviceptr>(codes), pixels);
  const auto got_details =
      sample::Download<unsigned>(reinterpret_cast<CUdeviceptr>(details), pixels);
  size_t user = 0, depth = 0, none = 0, wrong = 0;
  for (unsigned y = 0; y < height; ++y) {
    for (unsigned x = 0; x < width; ++x) {
      const size_t i = size_t(y) * width + x;
      if (x < width / 3) {
        user += got_codes[i] == kUserCode && got_details[i] == x * 1000 + y;
        wrong += got_codes[i] != kUserCode || got_details[i] != x * 1000 + y;
      } else if (x < 2 * width / 3) {
        depth += got_codes[i] == OPTIX_EXCEPTION_CODE_TRACE_DEPTH_EXCEEDED;
        wrong += got_codes[i] != OPTIX_EXCEPTION_CODE_TRACE_DEPTH_EXCEEDED;
      } else {
        none += got_codes[i] == 0;
        wrong += got_codes[i] != 0;
      }
    }
  }
  std::printf("user exceptions %zu, trace depth exceeded %zu, no exception %zu, unexpected %zu\n",
              user, depth, none, wrong);
  sample::WriteImage(out, width, height,
                     sample::Download<uchar4>(reinterpret_cast<CUdeviceptr>(image), pixels));
  std::printf("wrote %s\n", out.c_str());
  OPTIX_CHECK(optixPipelineDestroy(pipeline));
  for (OptixProgramGroup g : groups) OPTIX_CHECK(optixProgramGroupDestroy(g));
  OPTIX_CHECK(optixModuleDestroy(module));
  OPTIX_CHECK(optixDeviceContextDestroy(context));
  return wrong == 0 ? 0 : 1;
}

// The OptiX 7 triangle sample, written as the SDK's optixTriangle is: one triangle in a GAS, a
// pinhole camera in raygen, barycentric colours in closest-hit, a background in miss. Writes
// triangle.png (or --out FILE).
#include <cuda_runtime.h>
#include <optix.h>
#include <optix_function_table_definition.h>
#include <optix_stack_size.h>
#include <optix_stubs.h>

#include <cstdio>
#include <vector>

#include "../common/sample_util.h"
#include "../common/vec_math.h"
#include "triangle.h"

extern "C" const char triangle_programs[];  // tessera_embed_program

int main(int argc, char** argv) {
  const std::string out = sample::Option(argc, argv, "--out", "triangle.png");
  const int width = 320, height = 240;
  OptixDeviceContext context = sample::CreateContext();

  // Geometry: one triangle.
  const std::vector<float3> vertices = {
      {-0.5f, -0.5f, 0.0f}, {0.5f, -0.5f, 0.0f}, {0.0f, 0.5f, 0.0f}};
  CUdeviceptr d_vertices = sample::Upload(vertices);
  const uint32_t triangle_flags[1] = {OPTIX_GEOMETRY_FLAG_NONE};
  OptixBuildInput input = {};
  input.type = OPTIX_BUILD_INPUT_TYPE_TRIANGLES;
  input.triangleArray.vertexFormat = OPTIX_VERTEX_FORMAT_FLOAT3;
  input.triangleArray.numVertices = static_cast<unsigned>(vertices.size());
  input.triangleArray.vertexBuffers = &d_vertices;
  input.triangleArray.flags = triangle_flags;
  input.triangleArray.numSbtRecords = 1;
  CUdeviceptr gas_storage = 0;
  const OptixTraversableHandle gas =
      sample::BuildAccel(context, &input, 1, OPTIX_BUILD_FLAG_NONE, &gas_storage);

  // Module, program groups, pipeline.
  OptixModuleCompileOptions module_options = {};
  module_options.optLevel = OPTIX_COMPILE_OPTIMIZATION_DEFAULT;
  module_options.debugLevel = OPTIX_COMPILE_DEBUG_LEVEL_MINIMAL;
  OptixPipelineCompileOptions pipeline_options = {};
  pipeline_options.usesMotionBlur = false;
  pipeline_options.traversableGraphFlags = OPTIX_TRAVERSABLE_GRAPH_FLAG_ALLOW_SINGLE_GAS;
  pipeline_options.numPayloadValues = 3;
  pipeline_options.numAttributeValues = 3;
  pipeline_options.exceptionFlags = OPTIX_EXCEPTION_FLAG_NONE;
  pipeline_options.pipelineLaunchParamsVariableName = "params";
  pipeline_options.usesPrimitiveTypeFlags = OPTIX_PRIMITIVE_TYPE_FLAGS_TRIANGLE;
  OptixModule module =
      sample::CreateModule(context, module_options, pipeline_options, triangle_programs);

  OptixProgramGroupOptions group_options = {};
  OptixProgramGroupDesc descs[3] = {};
  descs[0].kind = OPTIX_PROGRAM_GROUP_KIND_RAYGEN;
  descs[0].raygen.module = module;
  descs[0].raygen.entryFunctionName = "__raygen__rg";
  descs[1].kind = OPTIX_PROGRAM_GROUP_KIND_MISS;
  descs[1].miss.module = module;
  descs[1].miss.entryFunctionName = "__miss__ms";
  descs[2].kind = OPTIX_PROGRAM_GROUP_KIND_HITGROUP;
  descs[2].hitgroup.moduleCH = module;
  descs[2].hitgroup.entryFunctionNameCH = "__closesthit__ch";
  OptixProgramGroup groups[3] = {};
  char log[2048];
  size_t log_size = sizeof(log);
  OPTIX_CHECK(optixProgramGroupCreate(context, descs, 3, &group_options, log, &log_size, groups));

  OptixPipelineLinkOptions link_options = {};
  link_options.maxTraceDepth = 1;
  OptixPipeline pipeline = nullptr;
  log_size = sizeof(log);
  OPTIX_CHECK(optixPipelineCreate(context, &pipeline_options, &link_options, groups, 3, log,
                                  &log_size, &pipeline));
  OptixStackSizes stack_sizes = {};
  for (OptixProgramGroup g : groups) {
    OPTIX_CHECK(optixUtilAccumulateStackSizes(g, &stack_sizes, pipeline));
  }
  uint32_t from_traversal = 0, from_state = 0, continuation = 0;
  OPTIX_CHECK(optixUtilComputeStackSizes(&stack_sizes, 1, 0, 0, &from_traversal, &from_state,
                                         &continuation));
  OPTIX_CHECK(optixPipelineSetStackSize(pipeline, from_traversal, from_state, continuation, 1));

  // Shader binding table.
  OptixShaderBindingTable sbt = {};
  sbt.raygenRecord = sample::UploadRecord(groups[0], RayGenData{});
  sbt.missRecordBase = sample::UploadRecord(groups[1], MissData{{0.3f, 0.1f, 0.2f}});
  sbt.missRecordStrideInBytes = sizeof(SbtRecord<MissData>);
  sbt.missRecordCount = 1;
  sbt.hitgroupRecordBase = sample::UploadRecord(groups[2], HitGroupData{});
  sbt.hitgroupRecordStrideInBytes = sizeof(SbtRecord<HitGroupData>);
  sbt.hitgroupRecordCount = 1;

  // Launch.
  uchar4* image = nullptr;
  CUDA_CHECK(cudaMalloc(reinterpret_cast<void**>(&image), sizeof(uchar4) * width * height));
  Params params = {};
  params.image = image;
  params.image_width = width;
  params.image_height = height;
  params.cam_eye = make_float3(0.0f, 0.0f, 2.0f);
  params.cam_u = make_float3(1.0f * width / height * 0.5f, 0.0f, 0.0f);
  params.cam_v = make_float3(0.0f, 0.5f, 0.0f);
  params.cam_w = make_float3(0.0f, 0.0f, -1.0f);
  params.handle = gas;
  CUdeviceptr d_params = sample::Upload(&params, sizeof(params));
  cudaStream_t stream = nullptr;
  CUDA_CHECK(cudaStreamCreate(&stream));
  OPTIX_CHECK(optixLaunch(pipeline, stream, d_params, sizeof(Params), &sbt, width, height, 1));
  CUDA_CHECK(cudaStreamSynchronize(stream));

  const std::vector<uchar4> pixels =
      sample::Download<uchar4>(reinterpret_cast<CUdeviceptr>(image), size_t(width) * height);
  sample::WriteImage(out, width, height, pixels);
  std::printf("wrote %s\n", out.c_str());

  CUDA_CHECK(cudaStreamDestroy(stream));
  OPTIX_CHECK(optixPipelineDestroy(pipeline));
  for (OptixProgramGroup g : groups) OPTIX_CHECK(optixProgramGroupDestroy(g));
  OPTIX_CHECK(optixModuleDestroy(module));
  OPTIX_CHECK(optixDeviceContextDestroy(context));
  return 0;
}

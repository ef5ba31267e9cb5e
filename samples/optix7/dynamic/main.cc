// The dynamic geometry sample: a rippling height field rendered over five frames. Frame 0 builds
// the GAS with ALLOW_UPDATE; frames 1 to 3 move the vertices (cudaMemcpy) and refit it
// (OPTIX_BUILD_OPERATION_UPDATE, the same output buffer); frame 4 rebuilds it from scratch. The
// frames are written side by side into dynamic.png (--out FILE).
#include <cuda_runtime.h>
#include <optix.h>
#include <optix_function_table_definition.h>
#include <optix_stubs.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "../common/sample_util.h"
#include "../common/vec_math.h"
#include "dynamic.h"

extern "C" const char dynamic_programs[];

namespace {

constexpr int kGrid = 48;

std::vector<float3> Surface(float phase) {
  std::vector<float3> v;
  for (int j = 0; j <= kGrid; ++j) {
    for (int i = 0; i <= kGrid; ++i) {
      const float x = -1.0f + 2.0f * i / kGrid, z = -1.0f + 2.0f * j / kGrid;
      const float r = std::sqrt(x * x + z * z);
      v.push_back(make_float3(x, 0.12f * std::sin(10.0f * r - phase) / (1.0f + 3.0f * r), z));
    }
  }
  return v;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string out = sample::Option(argc, argv, "--out", "dynamic.png");
  const unsigned width = 128, height = 96, frames = 5;
  OptixDeviceContext context = sample::CreateContext();

  std::vector<uint3> indices;
  for (int j = 0; j < kGrid; ++j) {
    for (int i = 0; i < kGrid; ++i) {
      const unsigned a = j * (kGrid + 1) + i, b = a + 1, c = a + kGrid + 1, d = c + 1;
      indices.push_back(make_uint3(a, c, b));
      indices.push_back(make_uint3(b, c, d));
    }
  }
  std::vector<float3> vertices = Surface(0.0f);
  CUdeviceptr d_vertices = sample::Upload(vertices);
  CUdeviceptr d_indices = sample::Upload(indices);
  const uint32_t flags[1] = {OPTIX_GEOMETRY_FLAG_DISABLE_ANYHIT};
  OptixBuildInput input = {};
  input.type = OPTIX_BUILD_INPUT_TYPE_TRIANGLES;
  input.triangleArray.vertexFormat = OPTIX_VERTEX_FORMAT_FLOAT3;
  input.triangleArray.numVertices = static_cast<unsigned>(vertices.size());
  input.triangleArray.vertexBuffers = &d_vertices;
  input.triangleArray.indexFormat = OPTIX_INDICES_FORMAT_UNSIGNED_INT3;
  input.triangleArray.numIndexTriplets = static_cast<unsigned>(indices.size());
  input.triangleArray.indexBuffer = d_indices;
  input.triangleArray.flags = flags;
  input.triangleArray.numSbtRecords = 1;

  OptixAccelBuildOptions options = {};
  options.buildFlags = OPTIX_BUILD_FLAG_ALLOW_UPDATE | OPTIX_BUILD_FLAG_PREFER_FAST_BUILD;
  options.operation = OPTIX_BUILD_OPERATION_BUILD;
  OptixAccelBufferSizes sizes;
  OPTIX_CHECK(optixAccelComputeMemoryUsage(context, &options, &input, 1, &sizes));
  void *temp = nullptr, *output = nullptr;
  CUDA_CHECK(cudaMalloc(&temp, std::max(sizes.tempSizeInBytes, sizes.tempUpdateSizeInBytes)));
  CUDA_CHECK(cudaMalloc(&output, sizes.outputSizeInBytes));
  OptixTraversableHandle gas = 0;
  OPTIX_CHECK(optixAccelBuild(context, nullptr, &options, &input, 1,
                              reinterpret_cast<CUdeviceptr>(temp), sizes.tempSizeInBytes,
                              reinterpret_cast<CUdeviceptr>(output), sizes.outputSizeInBytes, &gas,
                              nullptr, 0));

  OptixModuleCompileOptions module_options = {};
  OptixPipelineCompileOptions pipeline_options = {};
  pipeline_options.traversableGraphFlags = OPTIX_TRAVERSABLE_GRAPH_FLAG_ALLOW_SINGLE_GAS;
  pipeline_options.numPayloadValues = 3;
  pipeline_options.numAttributeValues = 2;
  pipeline_options.pipelineLaunchParamsVariableName = "params";
  OptixModule module =
      sample::CreateModule(context, module_options, pipeline_options, dynamic_programs);
  OptixProgramGroupDesc descs[3] = {};
  descs[0].kind = OPTIX_PROGRAM_GROUP_KIND_RAYGEN;
  descs[0].raygen = {module, "__raygen__rg"};
  descs[1].kind = OPTIX_PROGRAM_GROUP_KIND_MISS;
  descs[1].miss = {module, "__miss__ms"};
  descs[2].kind = OPTIX_PROGRAM_GROUP_KIND_HITGROUP;
  descs[2].hitgroup.moduleCH = module;
  descs[2].hitgroup.entryFunctionNameCH = "__closesthit__ch";
  OptixProgramGroupOptions group_options = {};
  OptixProgramGroup groups[3] = {};
  OPTIX_CHECK(optixProgramGroupCreate(context, descs, 3, &group_options, nullptr, nullptr, groups));
  OptixPipelineLinkOptions link_options = {};
  link_options.maxTraceDepth = 1;
  OptixPipeline pipeline = nullptr;
  OPTIX_CHECK(optixPipelineCreate(context, &pipeline_options, &link_options, groups, 3, nullptr,
                                  nullptr, &pipeline));
  OptixShaderBindingTable sbt = {};
  sbt.raygenRecord = sample::UploadRecord(groups[0], EmptyData{});
  sbt.missRecordBase = sample::UploadRecord(groups[1], EmptyData{});
  sbt.missRecordStrideInBytes = sizeof(SbtRecord<EmptyData>);
  sbt.missRecordCount = 1;
  sbt.hitgroupRecordBase =
      sample::UploadRecord(groups[2], HitData{reinterpret_cast<const float3*>(d_vertices),
                                              reinterpret_cast<const uint3*>(d_indices)});
  sbt.hitgroupRecordStrideInBytes = sizeof(SbtRecord<HitData>);
  sbt.hitgroupRecordCount = 1;

  const size_t pixels = size_t(width) * frames * height;
  void* image = nullptr;
  CUDA_CHECK(cudaMalloc(&image, pixels * sizeof(uchar4)));
  Params params = {};
  params.image = static_cast<uchar4*>(image);
  params.stride = width * frames;
  params.width = width;
  params.height = height;
  params.eye = make_float3(0.0f, 1.2f, 1.8f);
  params.w = normalize(make_float3(0.0f, -1.2f, -1.8f));
  params.u = make_float3(0.6f * width / height, 0.0f, 0.0f);
  params.v = normalize(cross(params.u, params.w)) * 0.6f;
  params.handle = gas;
  void* d_params = nullptr;
  CUDA_CHECK(cudaMalloc(&d_params, sizeof(Params)));
  for (unsigned f = 0; f < frames; ++f) {
    if (f > 0) {
      vertices = Surface(1.3f * f);
      CUDA_CHECK(cudaMemcpy(reinterpret_cast<void*>(d_vertices), vertices.data(),
                            vertices.size() * sizeof(float3), cudaMemcpyHostToDevice));
      options.operation =
          f < frames - 1 ? OPTIX_BUILD_OPERATION_UPDATE : OPTIX_BUILD_OPERATION_BUILD;
      OPTIX_CHECK(optixAccelBuild(
          context, nullptr, &options, &input, 1, reinterpret_cast<CUdeviceptr>(temp),
          options.operation == OPTIX_BUILD_OPERATION_UPDATE ? sizes.tempUpdateSizeInBytes
                                                            : sizes.tempSizeInBytes,
          reinterpret_cast<CUdeviceptr>(output), sizes.outputSizeInBytes, &gas, nullptr, 0));
      params.handle = gas;
    }
    params.x_offset = f * width;
    CUDA_CHECK(cudaMemcpy(d_params, &params, sizeof(params), cudaMemcpyHostToDevice));
    OPTIX_CHECK(optixLaunch(pipeline, nullptr, reinterpret_cast<CUdeviceptr>(d_params),
                            sizeof(Params), &sbt, width, height, 1));
  }
  CUDA_CHECK(cudaDeviceSynchronize());
  sample::WriteImage(out, width * frames, height,
                     sample::Download<uchar4>(reinterpret_cast<CUdeviceptr>(image), pixels));
  std::printf("wrote %s (%u frames: build, %u refits, rebuild)\n", out.c_str(), frames, frames - 2);
  OPTIX_CHECK(optixPipelineDestroy(pipeline));
  for (OptixProgramGroup g : groups) OPTIX_CHECK(optixProgramGroupDestroy(g));
  OPTIX_CHECK(optixModuleDestroy(module));
  OPTIX_CHECK(optixDeviceContextDestroy(context));
  return 0;
}

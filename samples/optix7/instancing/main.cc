// The instancing sample: one cube GAS placed 24 times by an IAS, each instance with its own
// rotation, scale, instance id and SBT offset (three materials), and one instance hidden from
// camera rays by its visibility mask. Writes instancing.png (--out FILE).
#include <cuda_runtime.h>
#include <optix.h>
#include <optix_function_table_definition.h>
#include <optix_stubs.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <vector>

#include "../common/sample_util.h"
#include "../common/vec_math.h"
#include "instancing.h"

extern "C" const char instancing_programs[];

namespace {

// A unit cube's 12 triangles, wound counter-clockwise seen from outside.
std::vector<float3> Cube() {
  const float3 c[8] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                       {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};
  const int faces[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4},
                           {3, 7, 6, 2}, {0, 4, 7, 3}, {1, 2, 6, 5}};
  std::vector<float3> v;
  for (const auto& f : faces) {
    for (int k : {f[0], f[1], f[2], f[0], f[2], f[3]}) v.push_back(c[k] * 0.5f);
  }
  return v;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string out = sample::Option(argc, argv, "--out", "instancing.png");
  const unsigned width = 320, height = 240;
  OptixDeviceContext context = sample::CreateContext();

  const std::vector<float3> cube = Cube();
  CUdeviceptr d_cube = sample::Upload(cube);
  const uint32_t flags[1] = {OPTIX_GEOMETRY_FLAG_DISABLE_ANYHIT};
  OptixBuildInput input = {};
  input.type = OPTIX_BUILD_INPUT_TYPE_TRIANGLES;
  input.triangleArray.vertexFormat = OPTIX_VERTEX_FORMAT_FLOAT3;
  input.triangleArray.numVertices = static_cast<unsigned>(cube.size());
  input.triangleArray.vertexBuffers = &d_cube;
  input.triangleArray.flags = flags;
  input.triangleArray.numSbtRecords = 1;
  CUdeviceptr gas_storage = 0;
  const OptixTraversableHandle gas = sample::BuildAccel(context, &input, 1, 0, &gas_storage);

  std::vector<OptixInstance> instances;
  for (int i = 0; i < 25; ++i) {
    OptixInstance inst = {};
    const float angle = 0.3f * i;
    const float scale = 0.25f + 0.05f * (i % 3);
    const float c = std::cos(angle) * scale, s = std::sin(angle) * scale;
    const float x = -1.6f + 0.8f * (i % 5), y = -1.2f + 0.6f * (i / 5);
    const float m[12] = {c, 0, s, x, 0, scale, 0, y, -s, 0, c, -2.0f};
    std::memcpy(inst.transform, m, sizeof(m));
    inst.instanceId = 100 + i;
    inst.sbtOffset = i % 3;  // one hit group record per material
    // The last instance sits in front of everything but only mask bit 2 sees it.
    inst.visibilityMask = i == 24 ? 2 : 1;
    inst.flags = OPTIX_INSTANCE_FLAG_NONE;
    inst.traversableHandle = gas;
    if (i == 24) {
      const float front[12] = {2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 2, -1.0f};
      std::memcpy(inst.transform, front, sizeof(front));
    }
    instances.push_back(inst);
  }
  CUdeviceptr d_instances = sample::Upload(instances);
  OptixBuildInput ias_input = {};
  ias_input.type = OPTIX_BUILD_INPUT_TYPE_INSTANCES;
  ias_input.instanceArray.instances = d_instances;
  ias_input.instanceArray.numInstances = static_cast<unsigned>(instances.size());
  CUdeviceptr ias_storage = 0;
  const OptixTraversableHandle ias = sample::BuildAccel(context, &ias_input, 1, 0, &ias_storage);

  OptixModuleCompileOptions module_options = {};
  OptixPipelineCompileOptions pipeline_options = {};
  pipeline_options.traversableGraphFlags =
      OPTIX_TRAVERSABLE_GRAPH_FLAG_ALLOW_SINGLE_LEVEL_INSTANCING;
  pipeline_options.numPayloadValues = 3;
  pipeline_options.numAttributeValues = 2;
  pipeline_options.pipelineLaunchParamsVariableName = "params";
  OptixModule module =
      sample::CreateModule(context, module_options, pipeline_options, instancing_programs);
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

  SbtRecord<HitData> materials[3];
  const float3 colors[3] = {{0.9f, 0.3f, 0.2f}, {0.3f, 0.8f, 0.3f}, {0.3f, 0.4f, 0.95f}};
  for (int k = 0; k < 3; ++k) {
    OPTIX_CHECK(optixSbtRecordPackHeader(groups[2], &materials[k]));
    materials[k].data.color = colors[k];
  }
  OptixShaderBindingTable sbt = {};
  sbt.raygenRecord = sample::UploadRecord(groups[0], EmptyData{});
  sbt.missRecordBase = sample::UploadRecord(groups[1], EmptyData{});
  sbt.missRecordStrideInBytes = sizeof(SbtRecord<EmptyData>);
  sbt.missRecordCount = 1;
  sbt.hitgroupRecordBase = sample::Upload(materials, sizeof(materials));
  sbt.hitgroupRecordStrideInBytes = sizeof(materials[0]);
  sbt.hitgroupRecordCount = 3;

  void* image = nullptr;
  CUDA_CHECK(cudaMalloc(&image, sizeof(uchar4) * width * height));
  Params params = {};
  params.image = static_cast<uchar4*>(image);
  params.width = width;
  params.height = height;
  params.eye = make_float3(0.0f, 0.0f, 1.5f);
  params.u = make_float3(0.5f * width / height, 0.0f, 0.0f);
  params.v = make_float3(0.0f, 0.5f, 0.0f);
  params.w = make_float3(0.0f, 0.0f, -0.9f);
  params.handle = ias;
  CUdeviceptr d_params = sample::Upload(&params, sizeof(params));
  OPTIX_CHECK(optixLaunch(pipeline, nullptr, d_params, sizeof(Params), &sbt, width, height, 1));
  CUDA_CHECK(cudaDeviceSynchronize());
  sample::WriteImage(
      out, width, height,
      sample::Download<uchar4>(reinterpret_cast<CUdeviceptr>(image), size_t(width) * height));
  std::printf("wrote %s\n", out.c_str());
  OPTIX_CHECK(optixPipelineDestroy(pipeline));
  for (OptixProgramGroup g : groups) OPTIX_CHECK(optixProgramGroupDestroy(g));
  OPTIX_CHECK(optixModuleDestroy(module));
  OPTIX_CHECK(optixDeviceContextDestroy(context));
  return 0;
}

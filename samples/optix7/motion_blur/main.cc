// The motion blur sample: a triangle mesh whose vertices move along three motion keys (a GAS
// built with motion options), a square spun a quarter turn by an SRT motion transform, and a
// square that stays put, all under one IAS built with two motion keys. Each pixel traces rays at
// times spread over the shutter interval, accumulated over --launches launches of --spp samples
// (defaults 4 and 4). Writes motion_blur.png (--out FILE).
#include <cuda_runtime.h>
#include <optix.h>
#include <optix_function_table_definition.h>
#include <optix_stubs.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "../common/sample_util.h"
#include "../common/vec_math.h"
#include "motion_blur.h"

extern "C" const char motion_blur_programs[];

namespace {

// A square of side `side` in the z = 0 plane around (cx, cy): two triangles.
std::vector<float3> Square(float cx, float cy, float side) {
  const float h = 0.5f * side;
  return {{cx - h, cy - h, 0}, {cx + h, cy - h, 0}, {cx + h, cy + h, 0},
          {cx - h, cy - h, 0}, {cx + h, cy + h, 0}, {cx - h, cy + h, 0}};
}

OptixBuildInput TriangleInput(const CUdeviceptr* keys, unsigned vertices, const uint32_t* flags) {
  OptixBuildInput input = {};
  input.type = OPTIX_BUILD_INPUT_TYPE_TRIANGLES;
  input.triangleArray.vertexFormat = OPTIX_VERTEX_FORMAT_FLOAT3;
  input.triangleArray.numVertices = vertices;
  input.triangleArray.vertexBuffers = keys;
  input.triangleArray.flags = flags;
  input.triangleArray.numSbtRecords = 1;
  return input;
}

// optixAccelBuild with motion options (sample::BuildAccel builds without).
OptixTraversableHandle BuildMotionAccel(OptixDeviceContext context, const OptixBuildInput& input,
                                        const OptixMotionOptions& motion) {
  OptixAccelBuildOptions options = {};
  options.buildFlags = OPTIX_BUILD_FLAG_NONE;
  options.operation = OPTIX_BUILD_OPERATION_BUILD;
  options.motionOptions = motion;
  OptixAccelBufferSizes sizes = {};
  OPTIX_CHECK(optixAccelComputeMemoryUsage(context, &options, &input, 1, &sizes));
  void* temp = nullptr;
  void* output = nullptr;
  CUDA_CHECK(cudaMalloc(&temp, sizes.tempSizeInBytes));
  CUDA_CHECK(cudaMalloc(&output, sizes.outputSizeInBytes));
  OptixTraversableHandle handle = 0;
  OPTIX_CHECK(optixAccelBuild(context, nullptr, &options, &input, 1,
                              reinterpret_cast<CUdeviceptr>(temp), sizes.tempSizeInBytes,
                              reinterpret_cast<CUdeviceptr>(output), sizes.outputSizeInBytes,
                              &handle, nullptr, 0));
  CUDA_CHECK(cudaFree(temp));
  return handle;
}

OptixInstance Instance(unsigned id, unsigned sbt_offset, OptixTraversableHandle child) {
  OptixInstance inst = {};
  const float identity[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
  std::memcpy(inst.transform, identity, sizeof(identity));
  inst.instanceId = id;
  inst.sbtOffset = sbt_offset;
  inst.visibilityMask = 255;
  inst.traversableHandle = child;
  return inst;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string out = sample::Option(argc, argv, "--out", "motion_blur.png");
  const unsigned launches = std::atoi(sample::Option(argc, argv, "--launches", "4").c_str());
  const unsigned spp = std::atoi(sample::Option(argc, argv, "--spp", "4").c_str());
  const unsigned width = 320, height = 240;
  OptixDeviceContext context = sample::CreateContext();
  const uint32_t flags[1] = {OPTIX_GEOMETRY_FLAG_DISABLE_ANYHIT};

  // The moving mesh: a square 0.5 wide at (-1.15, 0.55) at time 0, (-0.75, 0.75) at 0.5 and
  // (-0.35, 0.55) at 1: three keys, its vertices interpolated between neighbours.
  const float3 path[3] = {{-1.15f, 0.55f, 0}, {-0.75f, 0.75f, 0}, {-0.35f, 0.55f, 0}};
  CUdeviceptr mesh_keys[3];
  for (int k = 0; k < 3; ++k) mesh_keys[k] = sample::Upload(Square(path[k].x, path[k].y, 0.5f));
  const OptixTraversableHandle mesh = BuildMotionAccel(context, TriangleInput(mesh_keys, 6, flags),
                                                       OptixMotionOptions{3, 0, 0.0f, 1.0f});

  // A square 0.5 wide around the origin without motion, placed twice: spun by an SRT motion
  // transform (a quarter turn about z, moved to (0.8, -0.5)) and still at (0.8, 0.55).
  CUdeviceptr square_vertices = sample::Upload(Square(0, 0, 0.5f));
  CUdeviceptr square_storage = 0;
  const OptixBuildInput square_input = TriangleInput(&square_vertices, 6, flags);
  const OptixTraversableHandle square =
      sample::BuildAccel(context, &square_input, 1, 0, &square_storage);
  OptixSRTMotionTransform srt = {};
  srt.child = square;
  srt.motionOptions = OptixMotionOptions{2, 0, 0.0f, 1.0f};
  const float s = std::sqrt(0.5f);
  srt.srtData[0] = OptixSRTData{1, 0, 0, 0, 1, 0, 0, 1, 0, 0, 0, 0, 1, 0.8f, -0.5f, 0};
  srt.srtData[1] = OptixSRTData{1, 0, 0, 0, 1, 0, 0, 1, 0, 0, 0, s, s, 0.8f, -0.5f, 0};
  const CUdeviceptr d_srt = sample::Upload(&srt, sizeof(srt));
  OptixTraversableHandle spinning = 0;
  OPTIX_CHECK(optixConvertPointerToTraversableHandle(
      context, d_srt, OPTIX_TRAVERSABLE_TYPE_SRT_MOTION_TRANSFORM, &spinning));

  std::vector<OptixInstance> instances = {Instance(0, 0, mesh), Instance(1, 1, spinning),
                                          Instance(2, 2, square)};
  instances[2].transform[3] = 0.8f;
  instances[2].transform[7] = 0.55f;
  const CUdeviceptr d_instances = sample::Upload(instances);
  OptixBuildInput ias_input = {};
  ias_input.type = OPTIX_BUILD_INPUT_TYPE_INSTANCES;
  ias_input.instanceArray.instances = d_instances;
  ias_input.instanceArray.numInstances = static_cast<unsigned>(instances.size());
  const OptixTraversableHandle ias =
      BuildMotionAccel(context, ias_input, OptixMotionOptions{2, 0, 0.0f, 1.0f});

  OptixModuleCompileOptions module_options = {};
  OptixPipelineCompileOptions pipeline_options = {};
  pipeline_options.usesMotionBlur = 1;
  pipeline_options.traversableGraphFlags = OPTIX_TRAVERSABLE_GRAPH_FLAG_ALLOW_ANY;
  pipeline_options.numPayloadValues = 3;
  pipeline_options.numAttributeValues = 2;
  pipeline_options.pipelineLaunchParamsVariableName = "params";
  OptixModule module =
      sample::CreateModule(context, module_options, pipeline_options, motion_blur_programs);
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
  // Two levels: the IAS, then a motion transform (the spinning square).
  OPTIX_CHECK(optixPipelineSetStackSize(pipeline, 0, 0, 2048, 3));

  SbtRecord<HitData> materials[3];
  const float3 colors[3] = {{0.9f, 0.15f, 0.1f}, {0.1f, 0.85f, 0.2f}, {0.15f, 0.3f, 0.95f}};
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
  void* accum = nullptr;
  CUDA_CHECK(cudaMalloc(&image, sizeof(uchar4) * width * height));
  CUDA_CHECK(cudaMalloc(&accum, sizeof(float4) * width * height));
  Params params = {};
  params.accum = static_cast<float4*>(accum);
  params.image = static_cast<uchar4*>(image);
  params.width = width;
  params.height = height;
  params.launches = launches;
  params.spp = spp;
  params.half_extent = make_float2(1.6f, 1.2f);
  params.handle = ias;
  void* d_params = nullptr;
  CUDA_CHECK(cudaMalloc(&d_params, sizeof(params)));
  for (unsigned i = 0; i < launches; ++i) {
    params.launch = i;  // each launch takes its own slice of the shutter interval's strata
    CUDA_CHECK(cudaMemcpy(d_params, &params, sizeof(params), cudaMemcpyHostToDevice));
    OPTIX_CHECK(optixLaunch(pipeline, nullptr, reinterpret_cast<CUdeviceptr>(d_params),
                            sizeof(Params), &sbt, width, height, 1));
  }
  CUDA_CHECK(cudaDeviceSynchronize());
  sample::WriteImage(
      out, width, height,
      sample::Download<uchar4>(reinterpret_cast<CUdeviceptr>(image), size_t(width) * height));
  std::printf("wrote %s (%u launches of %u samples per pixel)\n", out.c_str(), launches, spp);
  OPTIX_CHECK(optixPipelineDestroy(pipeline));
  for (OptixProgramGroup g : groups) OPTIX_CHECK(optixProgramGroupDestroy(g));
  OPTIX_CHECK(optixModuleDestroy(module));
  OPTIX_CHECK(optixDeviceContextDestroy(context));
  return 0;
}

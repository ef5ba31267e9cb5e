// The spheres sample: a field of spheres on a ground sphere, all custom primitives bounded by
// AABBs, with shadow rays. Exercises two ray types, intersection programs with attributes and
// the terminate-on-first-hit / disable-closest-hit ray flags. Writes spheres.png (--out FILE).
#include <cuda_runtime.h>
#include <optix.h>
#include <optix_function_table_definition.h>
#include <optix_stubs.h>

#include <cstdio>
#include <vector>

#include "../common/sample_util.h"
#include "../common/vec_math.h"
#include "spheres.h"

extern "C" const char spheres_programs[];

int main(int argc, char** argv) {
  const std::string out = sample::Option(argc, argv, "--out", "spheres.png");
  const int width = 320, height = 200;
  OptixDeviceContext context = sample::CreateContext();

  std::vector<Sphere> spheres;
  spheres.push_back({{0.0f, -1000.0f, 0.0f}, 999.5f, {0.6f, 0.6f, 0.55f}});  // the ground
  for (int i = 0; i < 5; ++i) {
    for (int j = 0; j < 3; ++j) {
      const float r = 0.15f + 0.05f * ((i + j) % 3);
      spheres.push_back({{-1.6f + 0.8f * i, -0.5f + r, -0.8f * j},
                         r,
                         {0.2f + 0.15f * i, 0.9f - 0.25f * j, 0.3f + 0.1f * ((i * j) % 5)}});
    }
  }
  std::vector<OptixAabb> boxes;
  for (const Sphere& s : spheres) {
    boxes.push_back({s.center.x - s.radius, s.center.y - s.radius, s.center.z - s.radius,
                     s.center.x + s.radius, s.center.y + s.radius, s.center.z + s.radius});
  }
  CUdeviceptr d_boxes = sample::Upload(boxes);
  CUdeviceptr d_spheres = sample::Upload(spheres);
  const uint32_t flags[1] = {OPTIX_GEOMETRY_FLAG_DISABLE_ANYHIT};
  OptixBuildInput input = {};
  input.type = OPTIX_BUILD_INPUT_TYPE_CUSTOM_PRIMITIVES;
  input.customPrimitiveArray.aabbBuffers = &d_boxes;
  input.customPrimitiveArray.numPrimitives = static_cast<unsigned>(boxes.size());
  input.customPrimitiveArray.flags = flags;
  input.customPrimitiveArray.numSbtRecords = 1;
  CUdeviceptr gas_storage = 0;
  const OptixTraversableHandle gas =
      sample::BuildAccel(context, &input, 1, OPTIX_BUILD_FLAG_PREFER_FAST_TRACE, &gas_storage);

  OptixModuleCompileOptions module_options = {};
  OptixPipelineCompileOptions pipeline_options = {};
  pipeline_options.traversableGraphFlags = OPTIX_TRAVERSABLE_GRAPH_FLAG_ALLOW_SINGLE_GAS;
  pipeline_options.numPayloadValues = 3;
  pipeline_options.numAttributeValues = 4;
  pipeline_options.pipelineLaunchParamsVariableName = "params";
  pipeline_options.usesPrimitiveTypeFlags = OPTIX_PRIMITIVE_TYPE_FLAGS_CUSTOM;
  OptixModule module =
      sample::CreateModule(context, module_options, pipeline_options, spheres_programs);

  OptixProgramGroupDesc descs[5] = {};
  descs[0].kind = OPTIX_PROGRAM_GROUP_KIND_RAYGEN;
  descs[0].raygen = {module, "__raygen__camera"};
  descs[1].kind = OPTIX_PROGRAM_GROUP_KIND_MISS;
  descs[1].miss = {module, "__miss__sky"};
  descs[2].kind = OPTIX_PROGRAM_GROUP_KIND_MISS;
  descs[2].miss = {module, "__miss__shadow"};
  descs[3].kind = OPTIX_PROGRAM_GROUP_KIND_HITGROUP;
  descs[3].hitgroup.moduleCH = module;
  descs[3].hitgroup.entryFunctionNameCH = "__closesthit__sphere";
  descs[3].hitgroup.moduleIS = module;
  descs[3].hitgroup.entryFunctionNameIS = "__intersection__sphere";
  descs[4].kind = OPTIX_PROGRAM_GROUP_KIND_HITGROUP;  // shadow rays: intersection only
  descs[4].hitgroup.moduleIS = module;
  descs[4].hitgroup.entryFunctionNameIS = "__intersection__sphere";
  OptixProgramGroupOptions group_options = {};
  OptixProgramGroup groups[5] = {};
  OPTIX_CHECK(optixProgramGroupCreate(context, descs, 5, &group_options, nullptr, nullptr, groups));
  OptixPipelineLinkOptions link_options = {};
  link_options.maxTraceDepth = 2;
  OptixPipeline pipeline = nullptr;
  OPTIX_CHECK(optixPipelineCreate(context, &pipeline_options, &link_options, groups, 5, nullptr,
                                  nullptr, &pipeline));

  // Records of one kind lie back to back: miss [radiance, shadow], hit groups likewise.
  SbtRecord<MissData> miss[2];
  OPTIX_CHECK(optixSbtRecordPackHeader(groups[1], &miss[0]));
  OPTIX_CHECK(optixSbtRecordPackHeader(groups[2], &miss[1]));
  miss[0].data.sky = miss[1].data.sky = make_float3(0.5f, 0.7f, 1.0f);
  SbtRecord<HitData> hits[2];
  OPTIX_CHECK(optixSbtRecordPackHeader(groups[3], &hits[0]));
  OPTIX_CHECK(optixSbtRecordPackHeader(groups[4], &hits[1]));
  hits[0].data.spheres = hits[1].data.spheres = reinterpret_cast<const Sphere*>(d_spheres);
  OptixShaderBindingTable sbt = {};
  sbt.raygenRecord = sample::UploadRecord(groups[0], EmptyData{});
  sbt.missRecordBase = sample::Upload(miss, sizeof(miss));
  sbt.missRecordStrideInBytes = sizeof(miss[0]);
  sbt.missRecordCount = 2;
  sbt.hitgroupRecordBase = sample::Upload(hits, sizeof(hits));
  sbt.hitgroupRecordStrideInBytes = sizeof(hits[0]);
  sbt.hitgroupRecordCount = 2;

  uchar4* image = nullptr;
  CUDA_CHECK(cudaMalloc(reinterpret_cast<void**>(&image), sizeof(uchar4) * width * height));
  Params params = {};
  params.image = image;
  params.width = width;
  params.height = height;
  params.eye = make_float3(0.0f, 0.6f, 3.0f);
  params.w = normalize(make_float3(0.0f, -0.8f, -3.0f));
  params.u = normalize(cross(params.w, make_float3(0.0f, 1.0f, 0.0f))) * (0.5f * width / height);
  params.v = normalize(cross(params.u, params.w)) * 0.5f;
  params.light_direction = normalize(make_float3(-1.0f, 2.0f, 1.0f));
  params.handle = gas;
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

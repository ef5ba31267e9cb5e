// The cutouts sample: a row of leaves (quads with holes cut by an any-hit program) in front of an
// opaque floor, lit by a directional light whose shadow rays see the holes too. One build input
// asks for a single any-hit call per primitive (REQUIRE_SINGLE_ANYHIT_CALL). Writes cutouts.png
// (--out FILE) and prints how many any-hit calls camera rays made.
#include <cuda_runtime.h>
#include <optix.h>
#include <optix_function_table_definition.h>
#include <optix_stubs.h>

#include <cstdio>
#include <numeric>
#include <vector>

#include "../common/sample_util.h"
#include "../common/vec_math.h"
#include "cutouts.h"

extern "C" const char cutouts_programs[];

namespace {

void Quad(std::vector<float3>& v, float3 a, float3 b, float3 c, float3 d) {
  for (float3 p : {a, b, c, a, c, d}) v.push_back(p);
}

}  // namespace

int main(int argc, char** argv) {
  const std::string out = sample::Option(argc, argv, "--out", "cutouts.png");
  const unsigned width = 320, height = 200;
  OptixDeviceContext context = sample::CreateContext();

  std::vector<float3> floor, leaves;
  Quad(floor, {-4, -1, -6}, {4, -1, -6}, {4, -1, 2}, {-4, -1, 2});
  for (int i = 0; i < 4; ++i) {
    const float x = -1.9f + 1.0f * i, z = -1.5f - 0.4f * i;
    Quad(leaves, {x, -0.6f, z}, {x + 0.8f, -0.6f, z - 0.2f}, {x + 0.8f, 0.6f, z - 0.2f},
         {x, 0.6f, z});
  }
  CUdeviceptr d_floor = sample::Upload(floor), d_leaves = sample::Upload(leaves);
  const uint32_t floor_flags[1] = {OPTIX_GEOMETRY_FLAG_DISABLE_ANYHIT};
  const uint32_t leaf_flags[1] = {OPTIX_GEOMETRY_FLAG_REQUIRE_SINGLE_ANYHIT_CALL};
  OptixBuildInput inputs[2] = {};
  for (int k = 0; k < 2; ++k) {
    OptixBuildInputTriangleArray& t = inputs[k].triangleArray;
    inputs[k].type = OPTIX_BUILD_INPUT_TYPE_TRIANGLES;
    t.vertexFormat = OPTIX_VERTEX_FORMAT_FLOAT3;
    t.numVertices = static_cast<unsigned>(k == 0 ? floor.size() : leaves.size());
    t.vertexBuffers = k == 0 ? &d_floor : &d_leaves;
    t.flags = k == 0 ? floor_flags : leaf_flags;
    t.numSbtRecords = 1;
  }
  CUdeviceptr gas_storage = 0;
  const OptixTraversableHandle gas = sample::BuildAccel(context, inputs, 2, 0, &gas_storage);

  OptixModuleCompileOptions module_options = {};
  OptixPipelineCompileOptions pipeline_options = {};
  pipeline_options.traversableGraphFlags = OPTIX_TRAVERSABLE_GRAPH_FLAG_ALLOW_SINGLE_GAS;
  pipeline_options.numPayloadValues = 4;
  pipeline_options.numAttributeValues = 2;
  pipeline_options.pipelineLaunchParamsVariableName = "params";
  OptixModule module =
      sample::CreateModule(context, module_options, pipeline_options, cutouts_programs);
  enum { kRaygen, kMissSky, kMissShadow, kHitRadiance, kHitShadow, kGroupCount };
  OptixProgramGroupDesc descs[kGroupCount] = {};
  descs[kRaygen].kind = OPTIX_PROGRAM_GROUP_KIND_RAYGEN;
  descs[kRaygen].raygen = {module, "__raygen__rg"};
  descs[kMissSky].kind = OPTIX_PROGRAM_GROUP_KIND_MISS;
  descs[kMissSky].miss = {module, "__miss__sky"};
  descs[kMissShadow].kind = OPTIX_PROGRAM_GROUP_KIND_MISS;
  descs[kMissShadow].miss = {module, "__miss__shadow"};
  descs[kHitRadiance].kind = OPTIX_PROGRAM_GROUP_KIND_HITGROUP;
  descs[kHitRadiance].hitgroup.moduleCH = module;
  descs[kHitRadiance].hitgroup.entryFunctionNameCH = "__closesthit__radiance";
  descs[kHitRadiance].hitgroup.moduleAH = module;
  descs[kHitRadiance].hitgroup.entryFunctionNameAH = "__anyhit__radiance";
  descs[kHitShadow].kind = OPTIX_PROGRAM_GROUP_KIND_HITGROUP;
  descs[kHitShadow].hitgroup.moduleAH = module;
  descs[kHitShadow].hitgroup.entryFunctionNameAH = "__anyhit__shadow";
  OptixProgramGroupOptions group_options = {};
  OptixProgramGroup groups[kGroupCount] = {};
  OPTIX_CHECK(optixProgramGroupCreate(context, descs, kGroupCount, &group_options, nullptr, nullptr,
                                      groups));
  OptixPipelineLinkOptions link_options = {};
  link_options.maxTraceDepth = 2;
  OptixPipeline pipeline = nullptr;
  OPTIX_CHECK(optixPipelineCreate(context, &pipeline_options, &link_options, groups, kGroupCount,
                                  nullptr, nullptr, &pipeline));

  // Hit records: build input 0 (floor), then input 1 (leaves); per input radiance, shadow.
  SbtRecord<HitData> hits[4];
  const HitData data[2] = {{{0.7f, 0.65f, 0.55f}, 0}, {{0.3f, 0.75f, 0.25f}, 1}};
  for (int k = 0; k < 2; ++k) {
    OPTIX_CHECK(optixSbtRecordPackHeader(groups[kHitRadiance], &hits[2 * k]));
    OPTIX_CHECK(optixSbtRecordPackHeader(groups[kHitShadow], &hits[2 * k + 1]));
    hits[2 * k].data = hits[2 * k + 1].data = data[k];
  }
  SbtRecord<EmptyData> miss[2];
  OPTIX_CHECK(optixSbtRecordPackHeader(groups[kMissSky], &miss[0]));
  OPTIX_CHECK(optixSbtRecordPackHeader(groups[kMissShadow], &miss[1]));
  OptixShaderBindingTable sbt = {};
  sbt.raygenRecord = sample::UploadRecord(groups[kRaygen], EmptyData{});
  sbt.missRecordBase = sample::Upload(miss, sizeof(miss));
  sbt.missRecordStrideInBytes = sizeof(miss[0]);
  sbt.missRecordCount = 2;
  sbt.hitgroupRecordBase = sample::Upload(hits, sizeof(hits));
  sbt.hitgroupRecordStrideInBytes = sizeof(hits[0]);
  sbt.hitgroupRecordCount = 4;

  const size_t pixels = size_t(width) * height;
  void *image = nullptr, *calls = nullptr;
  CUDA_CHECK(cudaMalloc(&image, pixels * sizeof(uchar4)));
  CUDA_CHECK(cudaMalloc(&calls, pixels * sizeof(unsigned)));
  Params params = {};
  params.image = static_cast<uchar4*>(image);
  params.width = width;
  params.height = height;
  params.eye = make_float3(0.0f, 0.3f, 2.0f);
  params.w = normalize(make_float3(0.0f, -0.2f, -1.0f));
  params.u = make_float3(0.5f * width / height, 0.0f, 0.0f);
  params.v = normalize(cross(params.u, params.w)) * 0.5f;
  params.light_direction = normalize(make_float3(0.4f, 1.0f, 0.7f));
  params.handle = gas;
  params.any_hit_calls = static_cast<unsigned*>(calls);
  CUdeviceptr d_params = sample::Upload(&params, sizeof(params));
  OPTIX_CHECK(optixLaunch(pipeline, nullptr, d_params, sizeof(Params), &sbt, width, height, 1));
  CUDA_CHECK(cudaDeviceSynchronize());
  const auto counts = sample::Download<unsigned>(reinterpret_cast<CUdeviceptr>(calls), pixels);
  std::printf("any-hit calls of camera rays: %llu\n",
              static_cast<unsigned long long>(std::accumulate(counts.begin(), counts.end(), 0ull)));
  sample::WriteImage(out, width, height,
                     sample::Download<uchar4>(reinterpret_cast<CUdeviceptr>(image), pixels));
  std::printf("wrote %s\n", out.c_str());
  OPTIX_CHECK(optixPipelineDestroy(pipeline));
  for (OptixProgramGroup g : groups) OPTIX_CHECK(optixProgramGroupDestroy(g));
  OPTIX_CHECK(optixModuleDestroy(module));
  OPTIX_CHECK(optixDeviceContextDestroy(context));
  return 0;
}

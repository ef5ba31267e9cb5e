// The path tracer sample: the Cornell box (the SDK's optixPathTracer dimensions) with a diffuse
// short box and a glossy tall one, next-event estimation, materials as direct callables chosen
// per triangle through the GAS's SBT index offsets, and --launches launches of --spp samples
// accumulated in device memory (the parameters change between launches: the subframe index).
// Writes path_tracer.png (--out FILE).
#include <cuda_runtime.h>
#include <optix.h>
#include <optix_function_table_definition.h>
#include <optix_stubs.h>

#include <cstdio>
#include <cstdlib>
#include <vector>

#include "../common/sample_util.h"
#include "../common/vec_math.h"
#include "path_tracer.h"

extern "C" const char path_tracer_programs[];

namespace {

enum Material { kWhite = 0, kRed, kGreen, kLight, kMirror, kMaterialCount };

struct Scene {
  std::vector<float3> vertices;    // three per triangle
  std::vector<uint32_t> material;  // per triangle
  void Quad(float3 a, float3 b, float3 c, float3 d, Material m) {
    for (float3 v : {a, b, c, a, c, d}) vertices.push_back(v);
    material.push_back(m);
    material.push_back(m);
  }
  // An axis-aligned box's four sides and top, rotated about y by (cos, sin) around (cx, cz).
  void Box(float cx, float cz, float half, float height, float c, float s, Material m) {
    auto at = [&](float x, float y, float z) {
      return make_float3(cx + c * x - s * z, y, cz + s * x + c * z);
    };
    const float h = half;
    Quad(at(-h, height, -h), at(-h, height, h), at(h, height, h), at(h, height, -h), m);
    Quad(at(-h, 0, h), at(h, 0, h), at(h, height, h), at(-h, height, h), m);
    Quad(at(h, 0, -h), at(-h, 0, -h), at(-h, height, -h), at(h, height, -h), m);
    Quad(at(-h, 0, -h), at(-h, 0, h), at(-h, height, h), at(-h, height, -h), m);
    Quad(at(h, 0, h), at(h, 0, -h), at(h, height, -h), at(h, height, h), m);
  }
};

}  // namespace

int main(int argc, char** argv) {
  const std::string out = sample::Option(argc, argv, "--out", "path_tracer.png");
  const unsigned launches = std::atoi(sample::Option(argc, argv, "--launches", "4").c_str());
  const unsigned spp = std::atoi(sample::Option(argc, argv, "--spp", "4").c_str());
  const unsigned width = 256, height = 256;
  OptixDeviceContext context = sample::CreateContext();

  Scene scene;
  scene.Quad({0, 0, 0}, {0, 0, 559.2f}, {556, 0, 559.2f}, {556, 0, 0}, kWhite);  // floor
  scene.Quad({0, 548.8f, 0}, {556, 548.8f, 0}, {556, 548.8f, 559.2f}, {0, 548.8f, 559.2f},
             kWhite);  // ceiling
  scene.Quad({0, 0, 559.2f}, {0, 548.8f, 559.2f}, {556, 548.8f, 559.2f}, {556, 0, 559.2f},
             kWhite);  // back
  scene.Quad({556, 0, 0}, {556, 0, 559.2f}, {556, 548.8f, 559.2f}, {556, 548.8f, 0}, kRed);
  scene.Quad({0, 0, 0}, {0, 548.8f, 0}, {0, 548.8f, 559.2f}, {0, 0, 559.2f}, kGreen);
  scene.Box(185, 169, 82.5f, 165, 0.956f, -0.292f, kWhite);  // short box
  scene.Box(368, 351, 82.5f, 330, 0.956f, 0.292f, kMirror);  // tall box
  Light light;
  light.corner = make_float3(343.0f, 548.6f, 227.0f);
  light.v1 = make_float3(0.0f, 0.0f, 105.0f);
  light.v2 = make_float3(-130.0f, 0.0f, 0.0f);
  light.normal = normalize(cross(light.v1, light.v2));
  light.emission = make_float3(15.0f, 15.0f, 5.0f);
  scene.Quad(light.corner, light.corner + light.v1, light.corner + light.v1 + light.v2,
             light.corner + light.v2, kLight);

  CUdeviceptr d_vertices = sample::Upload(scene.vertices);
  CUdeviceptr d_material = sample::Upload(scene.material);
  uint32_t flags[kMaterialCount];
  for (uint32_t& f : flags) f = OPTIX_GEOMETRY_FLAG_DISABLE_ANYHIT;
  OptixBuildInput input = {};
  input.type = OPTIX_BUILD_INPUT_TYPE_TRIANGLES;
  input.triangleArray.vertexFormat = OPTIX_VERTEX_FORMAT_FLOAT3;
  input.triangleArray.vertexStrideInBytes = sizeof(float3);
  input.triangleArray.numVertices = static_cast<unsigned>(scene.vertices.size());
  input.triangleArray.vertexBuffers = &d_vertices;
  input.triangleArray.flags = flags;
  input.triangleArray.numSbtRecords = kMaterialCount;
  input.triangleArray.sbtIndexOffsetBuffer = d_material;
  input.triangleArray.sbtIndexOffsetSizeInBytes = sizeof(uint32_t);
  input.triangleArray.sbtIndexOffsetStrideInBytes = sizeof(uint32_t);
  CUdeviceptr gas_storage = 0;
  const OptixTraversableHandle gas = sample::BuildAccel(context, &input, 1, 0, &gas_storage);

  OptixModuleCompileOptions module_options = {};
  OptixPipelineCompileOptions pipeline_options = {};
  pipeline_options.traversableGraphFlags = OPTIX_TRAVERSABLE_GRAPH_FLAG_ALLOW_SINGLE_GAS;
  pipeline_options.numPayloadValues = 2;
  pipeline_options.numAttributeValues = 2;
  pipeline_options.pipelineLaunchParamsVariableName = "params";
  OptixModule module =
      sample::CreateModule(context, module_options, pipeline_options, path_tracer_programs);

  enum {
    kRaygen,
    kMissRadiance,
    kMissOcclusion,
    kHitRadiance,
    kHitOcclusion,
    kLambertDC,
    kGlossyDC,
    kGroupCount
  };
  OptixProgramGroupDesc descs[kGroupCount] = {};
  descs[kRaygen].kind = OPTIX_PROGRAM_GROUP_KIND_RAYGEN;
  descs[kRaygen].raygen = {module, "__raygen__rg"};
  descs[kMissRadiance].kind = OPTIX_PROGRAM_GROUP_KIND_MISS;
  descs[kMissRadiance].miss = {module, "__miss__radiance"};
  descs[kMissOcclusion].kind = OPTIX_PROGRAM_GROUP_KIND_MISS;
  descs[kMissOcclusion].miss = {module, "__miss__occlusion"};
  descs[kHitRadiance].kind = OPTIX_PROGRAM_GROUP_KIND_HITGROUP;
  descs[kHitRadiance].hitgroup.moduleCH = module;
  descs[kHitRadiance].hitgroup.entryFunctionNameCH = "__closesthit__radiance";
  descs[kHitOcclusion].kind = OPTIX_PROGRAM_GROUP_KIND_HITGROUP;  // no programs: any hit occludes
  descs[kLambertDC].kind = OPTIX_PROGRAM_GROUP_KIND_CALLABLES;
  descs[kLambertDC].callables.moduleDC = module;
  descs[kLambertDC].callables.entryFunctionNameDC = "__direct_callable__lambert";
  descs[kGlossyDC].kind = OPTIX_PROGRAM_GROUP_KIND_CALLABLES;
  descs[kGlossyDC].callables.moduleDC = module;
  descs[kGlossyDC].callables.entryFunctionNameDC = "__direct_callable__glossy";
  OptixProgramGroupOptions group_options = {};
  OptixProgramGroup groups[kGroupCount] = {};
  OPTIX_CHECK(optixProgramGroupCreate(context, descs, kGroupCount, &group_options, nullptr, nullptr,
                                      groups));
  OptixPipelineLinkOptions link_options = {};
  link_options.maxTraceDepth = 2;
  OptixPipeline pipeline = nullptr;
  OPTIX_CHECK(optixPipelineCreate(context, &pipeline_options, &link_options, groups, kGroupCount,
                                  nullptr, nullptr, &pipeline));
  OPTIX_CHECK(optixPipelineSetStackSize(pipeline, 0, 1024, 2048, 1));

  // Hit records: per material, radiance then occlusion (sbtStride 2).
  const float3 albedo[kMaterialCount] = {{0.80f, 0.80f, 0.80f},
                                         {0.80f, 0.05f, 0.05f},
                                         {0.05f, 0.80f, 0.05f},
                                         {0.50f, 0.50f, 0.50f},
                                         {0.90f, 0.90f, 0.90f}};
  std::vector<SbtRecord<HitData>> hits(2 * kMaterialCount);
  for (int m = 0; m < kMaterialCount; ++m) {
    for (int r = 0; r < 2; ++r) {
      SbtRecord<HitData>& rec = hits[2 * m + r];
      OPTIX_CHECK(optixSbtRecordPackHeader(groups[r == 0 ? kHitRadiance : kHitOcclusion], &rec));
      rec.data.albedo = albedo[m];
      rec.data.emission = m == kLight ? light.emission : make_float3(0.0f, 0.0f, 0.0f);
      rec.data.bsdf = m == kMirror ? kGlossy : kLambert;
      rec.data.vertices = reinterpret_cast<const float3*>(d_vertices);
    }
  }
  SbtRecord<EmptyData> miss[2], callables[2];
  OPTIX_CHECK(optixSbtRecordPackHeader(groups[kMissRadiance], &miss[0]));
  OPTIX_CHECK(optixSbtRecordPackHeader(groups[kMissOcclusion], &miss[1]));
  OPTIX_CHECK(optixSbtRecordPackHeader(groups[kLambertDC], &callables[kLambert]));
  OPTIX_CHECK(optixSbtRecordPackHeader(groups[kGlossyDC], &callables[kGlossy]));
  OptixShaderBindingTable sbt = {};
  sbt.raygenRecord = sample::UploadRecord(groups[kRaygen], EmptyData{});
  sbt.missRecordBase = sample::Upload(miss, sizeof(miss));
  sbt.missRecordStrideInBytes = sizeof(miss[0]);
  sbt.missRecordCount = 2;
  sbt.hitgroupRecordBase = sample::Upload(hits);
  sbt.hitgroupRecordStrideInBytes = sizeof(hits[0]);
  sbt.hitgroupRecordCount = static_cast<unsigned>(hits.size());
  sbt.callablesRecordBase = sample::Upload(callables, sizeof(callables));
  sbt.callablesRecordStrideInBytes = sizeof(callables[0]);
  sbt.callablesRecordCount = 2;

  void *accum = nullptr, *image = nullptr;
  CUDA_CHECK(cudaMalloc(&accum, sizeof(float4) * width * height));
  CUDA_CHECK(cudaMalloc(&image, sizeof(uchar4) * width * height));
  Params params = {};
  params.samples_per_launch = spp;
  params.max_depth = 4;
  params.accum = static_cast<float4*>(accum);
  params.image = static_cast<uchar4*>(image);
  params.width = width;
  params.height = height;
  params.eye = make_float3(278.0f, 273.0f, -900.0f);
  params.w = make_float3(0.0f, 0.0f, 1.0f) * 1.4f;
  params.u = make_float3(-0.5f, 0.0f, 0.0f);  // the box's x grows to the left of the camera
  params.v = make_float3(0.0f, 0.5f, 0.0f);
  params.light = light;
  params.handle = gas;
  void* d_params = nullptr;
  CUDA_CHECK(cudaMalloc(&d_params, sizeof(Params)));
  cudaStream_t stream = nullptr;
  CUDA_CHECK(cudaStreamCreate(&stream));
  for (unsigned i = 0; i < launches; ++i) {
    params.subframe_index = i;
    CUDA_CHECK(cudaMemcpyAsync(d_params, &params, sizeof(Params), cudaMemcpyHostToDevice, stream));
    OPTIX_CHECK(optixLaunch(pipeline, stream, reinterpret_cast<CUdeviceptr>(d_params),
                            sizeof(Params), &sbt, width, height, 1));
  }
  CUDA_CHECK(cudaStreamSynchronize(stream));
  sample::WriteImage(
      out, width, height,
      sample::Download<uchar4>(reinterpret_cast<CUdeviceptr>(image), size_t(width) * height));
  std::printf("wrote %s (%u launches of %u samples per pixel)\n", out.c_str(), launches, spp);
  CUDA_CHECK(cudaStreamDestroy(stream));
  OPTIX_CHECK(optixPipelineDestroy(pipeline));
  for (OptixProgramGroup g : groups) OPTIX_CHECK(optixProgramGroupDestroy(g));
  OPTIX_CHECK(optixModuleDestroy(module));
  OPTIX_CHECK(optixDeviceContextDestroy(context));
  return 0;
}

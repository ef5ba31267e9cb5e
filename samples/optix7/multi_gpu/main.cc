// The multi-GPU sample, written as an application for several GPUs is (in the spirit of the
// OptiX SDK's optixMultiGPU): one CUDA context, OptixDeviceContext, scene, pipeline and SBT per
// device; each device renders its band of rows into a buffer of its own, on a host thread of its
// own; cudaMemcpyPeer assembles the bands in device 0's memory, and a gather launch on device 0
// assembles them again by reading the other devices' buffers through peer access. Both must equal,
// bit for bit, device 0 rendering the whole image alone. On Tessera, TESSERA_CUDA_DEVICES=each
// makes each device of TESSERA_DEVICES a CUDA device (docs/optix7.md, "Devices"). Writes the
// assembled image (--out FILE); --devices N uses the first N devices.
#include <cuda.h>
#include <cuda_runtime.h>
#include <optix.h>
#include <optix_function_table_definition.h>
#include <optix_stubs.h>
#include <tessera/optix7_ext.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

#include "../common/sample_util.h"
#include "../common/vec_math.h"
#include "multi_gpu.h"

extern "C" const char multi_gpu_programs[];

namespace {

constexpr int kWidth = 320, kHeight = 240;

void LogCallback(unsigned int level, const char* tag, const char* message, void*) {
  std::fprintf(stderr, "[optix %u][%s] %s\n", level, tag, message);
}

// Everything one device holds: its contexts, its copy of the scene, its pipeline and its band.
struct PerDevice {
  int device = 0;
  CUcontext cu_context = nullptr;
  OptixDeviceContext context = nullptr;
  cudaStream_t stream = nullptr;
  CUdeviceptr gas_storage = 0;
  OptixTraversableHandle gas = 0;
  OptixModule module = nullptr;
  OptixProgramGroup groups[5] = {};
  OptixPipeline pipeline = nullptr;
  OptixShaderBindingTable sbt = {};         // renders a band
  OptixShaderBindingTable gather_sbt = {};  // device 0: assembles the bands
  unsigned first_row = 0, rows = 0;
  uchar4* band = nullptr;
  Params params = {};
  CUdeviceptr d_params = 0;
};

// The scene: a ground quad and three coloured triangles standing on it, as triangles with
// per-triangle colours and normals.
struct Scene {
  std::vector<float3> vertices;
  std::vector<float3> colors;
  std::vector<float3> normals;
  void Add(float3 a, float3 b, float3 c, float3 color) {
    vertices.insert(vertices.end(), {a, b, c});
    colors.push_back(color);
    normals.push_back(normalize(cross(b - a, c - a)));
  }
};

Scene MakeScene() {
  Scene s;
  const float3 grey = make_float3(0.7f, 0.7f, 0.65f);
  s.Add(make_float3(-4, 0, -4), make_float3(4, 0, 4), make_float3(4, 0, -4), grey);
  s.Add(make_float3(-4, 0, -4), make_float3(-4, 0, 4), make_float3(4, 0, 4), grey);
  s.Add(make_float3(-1.6f, 0, -0.5f), make_float3(-0.4f, 0, -0.5f), make_float3(-1.0f, 1.4f, -0.5f),
        make_float3(0.9f, 0.2f, 0.15f));
  s.Add(make_float3(-0.5f, 0, -1.2f), make_float3(0.7f, 0, -1.2f), make_float3(0.1f, 1.9f, -1.4f),
        make_float3(0.2f, 0.8f, 0.25f));
  s.Add(make_float3(0.6f, 0, 0.2f), make_float3(1.8f, 0, 0.4f), make_float3(1.2f, 1.1f, 0.3f),
        make_float3(0.2f, 0.35f, 0.9f));
  return s;
}

// Makes `d.device` current and builds its context, scene, pipeline and SBTs there: every
// allocation belongs to the device that was current when it was made, as in CUDA.
void SetUp(PerDevice& d, const Scene& scene) {
  CUDA_CHECK(cudaSetDevice(d.device));
  CUDA_CHECK(cudaFree(nullptr));  // makes the device's primary context current
  if (cuCtxGetCurrent(&d.cu_context) != CUDA_SUCCESS || d.cu_context == nullptr) {
    std::fprintf(stderr, "cuCtxGetCurrent failed on device %d\n", d.device);
    std::exit(1);
  }
  OptixDeviceContextOptions options = {};
  options.logCallbackFunction = &LogCallback;
  options.logCallbackLevel = 3;
  OPTIX_CHECK(optixDeviceContextCreate(d.cu_context, &options, &d.context));
  CUDA_CHECK(cudaStreamCreate(&d.stream));

  CUdeviceptr d_vertices = sample::Upload(scene.vertices);
  const uint32_t flags[1] = {OPTIX_GEOMETRY_FLAG_DISABLE_ANYHIT};
  OptixBuildInput input = {};
  input.type = OPTIX_BUILD_INPUT_TYPE_TRIANGLES;
  input.triangleArray.vertexFormat = OPTIX_VERTEX_FORMAT_FLOAT3;
  input.triangleArray.vertexStrideInBytes = sizeof(float3);
  input.triangleArray.numVertices = static_cast<unsigned>(scene.vertices.size());
  input.triangleArray.vertexBuffers = &d_vertices;
  input.triangleArray.flags = flags;
  input.triangleArray.numSbtRecords = 1;
  d.gas =
      sample::BuildAccel(d.context, &input, 1, OPTIX_BUILD_FLAG_PREFER_FAST_TRACE, &d.gas_storage);
  CUDA_CHECK(cudaFree(reinterpret_cast<void*>(d_vertices)));  // the GAS keeps what it needs

  OptixModuleCompileOptions module_options = {};
  OptixPipelineCompileOptions pipeline_options = {};
  pipeline_options.traversableGraphFlags = OPTIX_TRAVERSABLE_GRAPH_FLAG_ALLOW_SINGLE_GAS;
  pipeline_options.numPayloadValues = 3;
  pipeline_options.numAttributeValues = 2;
  pipeline_options.pipelineLaunchParamsVariableName = "params";
  pipeline_options.usesPrimitiveTypeFlags = OPTIX_PRIMITIVE_TYPE_FLAGS_TRIANGLE;
  d.module = sample::CreateModule(d.context, module_options, pipeline_options, multi_gpu_programs);
  OptixProgramGroupDesc descs[5] = {};
  descs[0].kind = OPTIX_PROGRAM_GROUP_KIND_RAYGEN;
  descs[0].raygen = {d.module, "__raygen__band"};
  descs[1].kind = OPTIX_PROGRAM_GROUP_KIND_RAYGEN;
  descs[1].raygen = {d.module, "__raygen__gather"};
  descs[2].kind = OPTIX_PROGRAM_GROUP_KIND_MISS;
  descs[2].miss = {d.module, "__miss__sky"};
  descs[3].kind = OPTIX_PROGRAM_GROUP_KIND_MISS;
  descs[3].miss = {d.module, "__miss__shadow"};
  descs[4].kind = OPTIX_PROGRAM_GROUP_KIND_HITGROUP;
  descs[4].hitgroup.moduleCH = d.module;
  descs[4].hitgroup.entryFunctionNameCH = "__closesthit__shade";
  OptixProgramGroupOptions group_options = {};
  OPTIX_CHECK(
      optixProgramGroupCreate(d.context, descs, 5, &group_options, nullptr, nullptr, d.groups));
  OptixPipelineLinkOptions link_options = {};
  link_options.maxTraceDepth = 2;
  OPTIX_CHECK(optixPipelineCreate(d.context, &pipeline_options, &link_options, d.groups, 5, nullptr,
                                  nullptr, &d.pipeline));

  SbtRecord<MissData> miss[2];
  OPTIX_CHECK(optixSbtRecordPackHeader(d.groups[2], &miss[0]));
  OPTIX_CHECK(optixSbtRecordPackHeader(d.groups[3], &miss[1]));
  miss[0].data.sky = miss[1].data.sky = make_float3(0.45f, 0.65f, 1.0f);
  HitData hit_data;
  hit_data.colors = reinterpret_cast<const float3*>(sample::Upload(scene.colors));
  hit_data.normals = reinterpret_cast<const float3*>(sample::Upload(scene.normals));
  SbtRecord<HitData> hits[2];  // radiance and shadow rays share the record's data
  OPTIX_CHECK(optixSbtRecordPackHeader(d.groups[4], &hits[0]));
  OPTIX_CHECK(optixSbtRecordPackHeader(d.groups[4], &hits[1]));
  hits[0].data = hits[1].data = hit_data;
  d.sbt.raygenRecord = sample::UploadRecord(d.groups[0], EmptyData{});
  d.sbt.missRecordBase = sample::Upload(miss, sizeof(miss));
  d.sbt.missRecordStrideInBytes = sizeof(miss[0]);
  d.sbt.missRecordCount = 2;
  d.sbt.hitgroupRecordBase = sample::Upload(hits, sizeof(hits));
  d.sbt.hitgroupRecordStrideInBytes = sizeof(hits[0]);
  d.sbt.hitgroupRecordCount = 2;
  d.gather_sbt = d.sbt;
  d.gather_sbt.raygenRecord = sample::UploadRecord(d.groups[1], EmptyData{});

  CUDA_CHECK(cudaMalloc(reinterpret_cast<void**>(&d.band),
                        sizeof(uchar4) * kWidth * std::max(1u, d.rows)));
  d.params.image = d.band;
  d.params.width = kWidth;
  d.params.height = kHeight;
  d.params.row_offset = d.first_row;
  d.params.eye = make_float3(0.0f, 1.6f, 4.5f);
  d.params.w = normalize(make_float3(0.0f, -1.0f, -4.5f));
  d.params.u =
      normalize(cross(d.params.w, make_float3(0.0f, 1.0f, 0.0f))) * (0.5f * kWidth / kHeight);
  d.params.v = normalize(cross(d.params.u, d.params.w)) * 0.5f;
  d.params.light_direction = normalize(make_float3(-1.0f, 2.0f, 1.5f));
  d.params.handle = d.gas;
  d.d_params = sample::Upload(&d.params, sizeof(Params));
}

// Launches `sbt` of `d` over `rows` rows from `first_row`, writing into `image`.
void Launch(PerDevice& d, const OptixShaderBindingTable& sbt, uchar4* image, unsigned first_row,
            unsigned rows) {
  CUDA_CHECK(cudaSetDevice(d.device));
  Params p = d.params;
  p.image = image;
  p.row_offset = first_row;
  CUDA_CHECK(cudaMemcpyAsync(reinterpret_cast<void*>(d.d_params), &p, sizeof(p),
                             cudaMemcpyHostToDevice, d.stream));
  OPTIX_CHECK(optixLaunch(d.pipeline, d.stream, d.d_params, sizeof(Params), &sbt, kWidth, rows, 1));
  CUDA_CHECK(cudaStreamSynchronize(d.stream));
}

}  // namespace

int main(int argc, char** argv) {
  const std::string out = sample::Option(argc, argv, "--out", "multi_gpu.png");
  OPTIX_CHECK(optixInit());
  int count = 0;
  CUDA_CHECK(cudaGetDeviceCount(&count));
  const int wanted = std::stoi(sample::Option(argc, argv, "--devices", std::to_string(count)));
  if (wanted < 1 || wanted > count || wanted > static_cast<int>(kMaxDevices)) {
    std::fprintf(stderr, "--devices %d: there are %d devices (at most %u used)\n", wanted, count,
                 kMaxDevices);
    return 2;
  }
  // An ordinal past the last device is refused, as CUDA refuses it.
  if (cudaSetDevice(count) != cudaErrorInvalidDevice ||
      cudaGetLastError() != cudaErrorInvalidDevice) {
    std::fprintf(stderr, "cudaSetDevice(%d) was not cudaErrorInvalidDevice\n", count);
    return 1;
  }

  const Scene scene = MakeScene();
  std::vector<PerDevice> devices(wanted);
  for (int i = 0; i < wanted; ++i) {
    PerDevice& d = devices[i];
    d.device = i;
    d.first_row = kHeight * i / wanted;
    d.rows = kHeight * (i + 1) / wanted - d.first_row;
    cudaDeviceProp prop;
    CUDA_CHECK(cudaGetDeviceProperties(&prop, i));
    std::printf("device %d: %s, %d threads, rows %u-%u\n", i, prop.name, prop.multiProcessorCount,
                d.first_row, d.first_row + d.rows - 1);
    SetUp(d, scene);
  }

  // Each device renders its band on a host thread of its own: launches return when done, so
  // one thread per device is what lets them overlap (the current device is per thread).
  std::vector<std::thread> threads;
  for (PerDevice& d : devices) {
    threads.emplace_back([&d] { Launch(d, d.sbt, d.band, d.first_row, d.rows); });
  }
  for (std::thread& t : threads) t.join();

  // Device 0 assembles the bands: copied with cudaMemcpyPeer, and gathered by a launch that
  // reads the other devices' memory (peer access, enabled first as CUDA requires).
  PerDevice& d0 = devices[0];
  CUDA_CHECK(cudaSetDevice(0));
  uchar4* copied = nullptr;
  uchar4* gathered = nullptr;
  uchar4* alone = nullptr;
  const size_t pixels = size_t{kWidth} * kHeight;
  CUDA_CHECK(cudaMalloc(reinterpret_cast<void**>(&copied), sizeof(uchar4) * pixels));
  CUDA_CHECK(cudaMalloc(reinterpret_cast<void**>(&gathered), sizeof(uchar4) * pixels));
  CUDA_CHECK(cudaMalloc(reinterpret_cast<void**>(&alone), sizeof(uchar4) * pixels));
  for (PerDevice& d : devices) {
    CUDA_CHECK(cudaMemcpyPeer(copied + size_t{d.first_row} * kWidth, 0, d.band, d.device,
                              sizeof(uchar4) * kWidth * d.rows));
    d0.params.share[d.device] = d.band;
    d0.params.share_row[d.device] = d.first_row;
    if (d.device == 0) continue;
    int can = 0;
    CUDA_CHECK(cudaDeviceCanAccessPeer(&can, 0, d.device));
    if (can != 1) {
      std::fprintf(stderr, "device 0 cannot access device %d's memory\n", d.device);
      return 1;
    }
    CUDA_CHECK(cudaDeviceEnablePeerAccess(d.device, 0));
  }
  d0.params.shares = static_cast<unsigned>(wanted);
  d0.params.share_row[wanted] = kHeight;
  Launch(d0, d0.gather_sbt, gathered, 0, kHeight);
  // The reference: device 0 renders the whole image alone.
  Launch(d0, d0.sbt, alone, 0, kHeight);

  const auto c = sample::Download<uchar4>(reinterpret_cast<CUdeviceptr>(copied), pixels);
  const auto g = sample::Download<uchar4>(reinterpret_cast<CUdeviceptr>(gathered), pixels);
  const auto a = sample::Download<uchar4>(reinterpret_cast<CUdeviceptr>(alone), pixels);
  const bool copies_equal = std::memcmp(c.data(), a.data(), sizeof(uchar4) * pixels) == 0;
  const bool gather_equal = std::memcmp(g.data(), a.data(), sizeof(uchar4) * pixels) == 0;
  for (const PerDevice& d : devices) {
    unsigned long long sent = 0, received = 0;
    OPTIX_CHECK(tesseraOptixDeviceContextGetTransferStats(d.context, &sent, &received));
    std::printf("device %d: %llu bytes sent to its devices, %llu received\n", d.device, sent,
                received);
  }
  std::printf(
      "%d devices: bands copied with cudaMemcpyPeer %s, gathered through peer access %s "
      "the single-device render\n",
      wanted, copies_equal ? "equal" : "DIFFER FROM", gather_equal ? "equal" : "DIFFER FROM");
  sample::WriteImage(out, kWidth, kHeight, c);
  std::printf("wrote %s\n", out.c_str());

  for (PerDevice& d : devices) {
    CUDA_CHECK(cudaSetDevice(d.device));
    OPTIX_CHECK(optixPipelineDestroy(d.pipeline));
    for (OptixProgramGroup group : d.groups) OPTIX_CHECK(optixProgramGroupDestroy(group));
    OPTIX_CHECK(optixModuleDestroy(d.module));
    CUDA_CHECK(cudaStreamDestroy(d.stream));
    OPTIX_CHECK(optixDeviceContextDestroy(d.context));
  }
  return copies_equal && gather_equal ? 0 : 1;
}

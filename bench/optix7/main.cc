// tessera-bench-optix7: the OptiX 7 layer's figures (issue 25, point 7), each printed as
// key=value lines.
//  --mode eyelight: Embree viewer's eyelight shader on a model through the OptiX 7 API (built-in
//    triangles, one in-process device on every core by default), timed against Embree's own
//    `viewer --benchmark` in the same run: eyelight_optix7_ratio_vs_embree=<ours/theirs>.
//  --mode flags: the same frame under a pipeline whose compile options allow everything (any
//    graph, custom primitives, motion blur, every exception) against one that allows what the
//    scene needs, on a GAS and on a single-level IAS: optix7_flags_<scene>_ratio.
//  --mode batching: the same frame traced in blocks of 16 lanes with Embree packets
//    (TESSERA_BATCHING=1) against one ray at a time: optix7_batching_ratio.
//  --mode bytes: what launches ship and gather on worker devices (local:2 by default): an
//    unchanged launch, one after a 4 KiB cudaMemcpy into a 64 MiB buffer, one whose programs
//    write 1% of that buffer (the bytes gathered, and what the next launch ships for them).
#include <cuda_runtime.h>
#include <optix.h>
#include <optix_function_table_definition.h>
#include <optix_stubs.h>
#include <tessera/optix7_ext.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string>
#include <vector>

#include "common/embree_viewer.h"
#include "eyelight/camera.h"
#include "eyelight/mesh.h"
#include "eyelight/timing.h"
#include "eyelight7.h"

extern "C" const char eyelight7_programs[];

namespace tessera::bench {
namespace {

#define CHECK_CUDA(call)                                        \
  do {                                                          \
    cudaError_t e_ = (call);                                    \
    if (e_ != cudaSuccess) Fail(#call, cudaGetErrorString(e_)); \
  } while (0)
#define CHECK_OPTIX(call)                                          \
  do {                                                             \
    OptixResult r_ = (call);                                       \
    if (r_ != OPTIX_SUCCESS) Fail(#call, optixGetErrorString(r_)); \
  } while (0)

[[noreturn]] void Fail(const char* call, const char* why) {
  std::fprintf(stderr, "%s failed: %s\n", call, why);
  std::exit(1);
}

template <typename T>
struct Record {
  __align__(OPTIX_SBT_RECORD_ALIGNMENT) char header[OPTIX_SBT_RECORD_HEADER_SIZE];
  T data;
};
struct Empty {};

CUdeviceptr Upload(const void* data, size_t bytes) {
  void* p = nullptr;
  CHECK_CUDA(cudaMalloc(&p, bytes));
  CHECK_CUDA(cudaMemcpy(p, data, bytes, cudaMemcpyHostToDevice));
  return reinterpret_cast<CUdeviceptr>(p);
}

template <typename T>
CUdeviceptr UploadRecord(OptixProgramGroup group, const T& data) {
  Record<T> r;
  CHECK_OPTIX(optixSbtRecordPackHeader(group, &r));
  r.data = data;
  return Upload(&r, sizeof(r));
}

// The context and one module of the bench's programs, with a pipeline per raygen program.
struct Pipelines {
  OptixDeviceContext context = nullptr;
  OptixModule module = nullptr;

  Pipelines() {
    CHECK_CUDA(cudaFree(nullptr));
    CHECK_OPTIX(optixInit());
    OptixDeviceContextOptions options = {};
    CHECK_OPTIX(optixDeviceContextCreate(nullptr, &options, &context));
  }
  ~Pipelines() { optixDeviceContextDestroy(context); }

  // A pipeline of raygen `raygen`, the eyelight miss and hit programs, launch parameters in
  // `params`; its SBT in *sbt (hit and miss records without data). `compile` gives the
  // pipeline's graph, primitive, motion and exception options (default: a single GAS of
  // triangles, no motion, no exceptions).
  OptixPipeline Make(const char* raygen, const char* params, OptixShaderBindingTable* sbt,
                     const OptixPipelineCompileOptions* compile = nullptr) {
    OptixModuleCompileOptions module_options = {};
    OptixPipelineCompileOptions pipeline_options = {};
    if (compile != nullptr) pipeline_options = *compile;
    if (compile == nullptr) {
      pipeline_options.traversableGraphFlags = OPTIX_TRAVERSABLE_GRAPH_FLAG_ALLOW_SINGLE_GAS;
    }
    pipeline_options.numPayloadValues = 2;
    pipeline_options.numAttributeValues = 2;
    pipeline_options.pipelineLaunchParamsVariableName = params;
    const std::string input = eyelight7_programs;
    CHECK_OPTIX(optixModuleCreate(context, &module_options, &pipeline_options, input.c_str(),
                                  input.size(), nullptr, nullptr, &module));
    OptixProgramGroupDesc descs[3] = {};
    descs[0].kind = OPTIX_PROGRAM_GROUP_KIND_RAYGEN;
    descs[0].raygen = {module, raygen};
    descs[1].kind = OPTIX_PROGRAM_GROUP_KIND_MISS;
    descs[1].miss = {module, "__miss__none"};
    descs[2].kind = OPTIX_PROGRAM_GROUP_KIND_HITGROUP;
    descs[2].hitgroup.moduleCH = module;
    descs[2].hitgroup.entryFunctionNameCH = "__closesthit__eyelight";
    OptixProgramGroupOptions group_options = {};
    OptixProgramGroup groups[3] = {};
    CHECK_OPTIX(
        optixProgramGroupCreate(context, descs, 3, &group_options, nullptr, nullptr, groups));
    OptixPipelineLinkOptions link = {};
    link.maxTraceDepth = 1;
    OptixPipeline pipeline = nullptr;
    CHECK_OPTIX(optixPipelineCreate(context, &pipeline_options, &link, groups, 3, nullptr, nullptr,
                                    &pipeline));
    *sbt = {};
    sbt->raygenRecord = UploadRecord(groups[0], Empty{});
    sbt->missRecordBase = UploadRecord(groups[1], Empty{});
    sbt->missRecordStrideInBytes = sizeof(Record<Empty>);
    sbt->missRecordCount = 1;
    sbt->hitgroupRecordBase = UploadRecord(groups[2], Empty{});
    sbt->hitgroupRecordStrideInBytes = sizeof(Record<Empty>);
    sbt->hitgroupRecordCount = 1;
    return pipeline;
  }

  struct Stats {
    unsigned long long sent = 0, received = 0;
  };
  Stats Transfers() const {
    Stats s;
    CHECK_OPTIX(tesseraOptixDeviceContextGetTransferStats(context, &s.sent, &s.received));
    return s;
  }
};

// Builds one acceleration of `input` into fresh device memory.
OptixTraversableHandle Build(const Pipelines& p, const OptixBuildInput& input, unsigned flags) {
  OptixAccelBuildOptions build = {};
  build.buildFlags = flags;
  build.operation = OPTIX_BUILD_OPERATION_BUILD;
  OptixAccelBufferSizes sizes;
  CHECK_OPTIX(optixAccelComputeMemoryUsage(p.context, &build, &input, 1, &sizes));
  void *temp = nullptr, *out = nullptr;
  CHECK_CUDA(cudaMalloc(&temp, sizes.tempSizeInBytes));
  CHECK_CUDA(cudaMalloc(&out, sizes.outputSizeInBytes));
  OptixTraversableHandle handle = 0;
  CHECK_OPTIX(optixAccelBuild(p.context, nullptr, &build, &input, 1,
                              reinterpret_cast<CUdeviceptr>(temp), sizes.tempSizeInBytes,
                              reinterpret_cast<CUdeviceptr>(out), sizes.outputSizeInBytes, &handle,
                              nullptr, 0));
  return handle;
}

// A GAS of `mesh`'s triangles (any-hit disabled, fast trace), its vertex and index buffers.
struct Gas {
  CUdeviceptr vertices = 0, indices = 0;
  OptixTraversableHandle handle = 0;
};

Gas BuildGas(const Pipelines& p, const Mesh& mesh) {
  Gas gas;
  CUdeviceptr vertices = Upload(mesh.positions.data(), mesh.positions.size() * sizeof(float));
  CUdeviceptr indices = Upload(mesh.indices.data(), mesh.indices.size() * sizeof(int));
  const uint32_t flags[1] = {OPTIX_GEOMETRY_FLAG_DISABLE_ANYHIT};
  OptixBuildInput input = {};
  input.type = OPTIX_BUILD_INPUT_TYPE_TRIANGLES;
  input.triangleArray.vertexFormat = OPTIX_VERTEX_FORMAT_FLOAT3;
  input.triangleArray.numVertices = static_cast<unsigned>(mesh.VertexCount());
  input.triangleArray.vertexBuffers = &vertices;
  input.triangleArray.indexFormat = OPTIX_INDICES_FORMAT_UNSIGNED_INT3;
  input.triangleArray.numIndexTriplets = static_cast<unsigned>(mesh.TriangleCount());
  input.triangleArray.indexBuffer = indices;
  input.triangleArray.flags = flags;
  input.triangleArray.numSbtRecords = 1;
  gas.handle = Build(p, input, OPTIX_BUILD_FLAG_PREFER_FAST_TRACE);
  gas.vertices = vertices;
  gas.indices = indices;
  return gas;
}

// An IAS of one instance of `child` under the identity: single-level instancing.
OptixTraversableHandle BuildIas(const Pipelines& p, OptixTraversableHandle child) {
  OptixInstance instance = {};
  const float identity[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
  std::copy(identity, identity + 12, instance.transform);
  instance.visibilityMask = 255;
  instance.traversableHandle = child;
  const CUdeviceptr instances = Upload(&instance, sizeof(instance));
  OptixBuildInput input = {};
  input.type = OPTIX_BUILD_INPUT_TYPE_INSTANCES;
  input.instanceArray.instances = instances;
  input.instanceArray.numInstances = 1;
  return Build(p, input, OPTIX_BUILD_FLAG_NONE);
}

// The eyelight launch parameters: the OptiX SDK pinhole for Embree viewer's camera
// (bench/eyelight/camera.h) over `handle`, the image in device memory.
EyelightParams MakeParams(unsigned width, unsigned height, OptixTraversableHandle handle,
                          const Gas& gas) {
  const Pinhole pinhole = MakePinhole(Camera(), width, height);
  auto vec = [](const float a[3]) { return make_float3(a[0], a[1], a[2]); };
  const float3 eye = vec(pinhole.eye), u = vec(pinhole.u), v = vec(pinhole.v), w = vec(pinhole.w);
  void* image = nullptr;
  CHECK_CUDA(cudaMalloc(&image, size_t(width) * height * sizeof(uchar4)));
  return {static_cast<uchar4*>(image),
          width,
          height,
          eye,
          u,
          v,
          w,
          handle,
          reinterpret_cast<const float3*>(gas.vertices),
          reinterpret_cast<const int3*>(gas.indices)};
}

int RunEyelight(const std::string& model, unsigned width, unsigned height, int warmup, int runs,
                const std::string& viewer_name) {
  std::optional<std::string> viewer = FindExecutable(viewer_name);
  if (!viewer) {
    std::fprintf(stderr, "Embree's viewer ('%s') was not found; install embree-tools.\n",
                 viewer_name.c_str());
    return 2;
  }
  const Mesh mesh = LoadObjMesh(model);
  Pipelines p;
  const Gas gas = BuildGas(p, mesh);
  OptixShaderBindingTable sbt;
  OptixPipeline pipeline = p.Make("__raygen__pinhole", "params", &sbt);
  const Camera camera;
  const EyelightParams params = MakeParams(width, height, gas.handle, gas);
  const CUdeviceptr d_params = Upload(&params, sizeof(params));
  const LaunchTimes times = TimeLaunches(
      [&] {
        CHECK_OPTIX(
            optixLaunch(pipeline, nullptr, d_params, sizeof(params), &sbt, width, height, 1));
      },
      warmup, runs);
  const double rays = double(width) * height;
  const double ours = rays / times.Median() / 1e6;
  std::printf("tessera optix7: median %.3f ms per launch (min %.3f, max %.3f), %.2f cores used\n",
              1e3 * times.Median(), 1e3 * times.Min(), 1e3 * times.Max(), times.Utilization());
  ViewerRun run;
  run.viewer = *viewer;
  run.model = model;
  run.width = width;
  run.height = height;
  run.warmup = warmup;
  run.runs = runs;
  run.camera_flags = camera.ViewerFlags();
  std::string command;
  const double theirs = RunEmbreeViewer(run, &command);
  std::printf("embree: %s\n", command.c_str());
  std::printf("embree_mrays_per_s=%.3f\n", theirs);
  std::printf("tessera_optix7_mrays_per_s=%.3f\n", ours);
  std::printf("eyelight_optix7_ratio_vs_embree=%.3f\n", ours / theirs);
  return 0;
}

// The pipeline compile options OptiX specializes programs for (guide 6.3): what a pipeline that
// allows everything says, against what the eyelight scene needs.
OptixPipelineCompileOptions GenericOptions() {
  OptixPipelineCompileOptions o = {};
  o.traversableGraphFlags = OPTIX_TRAVERSABLE_GRAPH_FLAG_ALLOW_ANY;
  o.usesPrimitiveTypeFlags = 0;  // custom and triangles
  o.usesMotionBlur = 1;
  o.exceptionFlags = OPTIX_EXCEPTION_FLAG_STACK_OVERFLOW | OPTIX_EXCEPTION_FLAG_TRACE_DEPTH |
                     OPTIX_EXCEPTION_FLAG_USER | OPTIX_EXCEPTION_FLAG_DEBUG;
  return o;
}

OptixPipelineCompileOptions SpecializedOptions(bool instances) {
  OptixPipelineCompileOptions o = {};
  o.traversableGraphFlags = instances ? OPTIX_TRAVERSABLE_GRAPH_FLAG_ALLOW_SINGLE_LEVEL_INSTANCING
                                      : OPTIX_TRAVERSABLE_GRAPH_FLAG_ALLOW_SINGLE_GAS;
  o.usesPrimitiveTypeFlags = OPTIX_PRIMITIVE_TYPE_FLAGS_TRIANGLE;
  o.usesMotionBlur = 0;
  o.exceptionFlags = OPTIX_EXCEPTION_FLAG_NONE;
  return o;
}

// The eyelight frame under generic and specialized pipeline compile options, on a GAS and on an
// IAS of one instance, rounds alternating so that both see the same machine:
// optix7_flags_<scene>_ratio=<specialized time / generic time> (below 1: the flags pay).
int RunFlags(const std::string& model, unsigned width, unsigned height, int warmup, int runs) {
  const Mesh mesh = LoadObjMesh(model);
  Pipelines p;
  const Gas gas = BuildGas(p, mesh);
  const OptixTraversableHandle ias = BuildIas(p, gas.handle);
  constexpr int kRounds = 5;
  for (const bool instances : {false, true}) {
    const char* scene = instances ? "ias" : "gas";
    const EyelightParams params = MakeParams(width, height, instances ? ias : gas.handle, gas);
    const CUdeviceptr d_params = Upload(&params, sizeof(params));
    const OptixPipelineCompileOptions options[2] = {GenericOptions(),
                                                    SpecializedOptions(instances)};
    OptixShaderBindingTable sbt[2];
    OptixPipeline pipelines[2];
    for (int k = 0; k < 2; ++k) {
      pipelines[k] = p.Make("__raygen__pinhole", "params", &sbt[k], &options[k]);
    }
    std::vector<double> medians[2];
    for (int round = 0; round < kRounds; ++round) {
      for (int k = 0; k < 2; ++k) {
        const LaunchTimes t = TimeLaunches(
            [&] {
              CHECK_OPTIX(optixLaunch(pipelines[k], nullptr, d_params, sizeof(params), &sbt[k],
                                      width, height, 1));
            },
            round == 0 ? warmup : 1, runs);
        medians[k].push_back(t.Median());
      }
    }
    double ratio[kRounds];
    for (int r = 0; r < kRounds; ++r) ratio[r] = medians[1][r] / medians[0][r];
    std::sort(ratio, ratio + kRounds);
    std::sort(medians[0].begin(), medians[0].end());
    std::sort(medians[1].begin(), medians[1].end());
    std::printf("%s: generic %.3f ms, specialized %.3f ms per launch (medians of %d rounds)\n",
                scene, 1e3 * medians[0][kRounds / 2], 1e3 * medians[1][kRounds / 2], kRounds);
    std::printf("optix7_flags_%s_ratio=%.3f (rounds %.3f..%.3f)\n", scene, ratio[kRounds / 2],
                ratio[0], ratio[kRounds - 1]);
  }
  return 0;
}

// The eyelight frame traced in blocks of lanes with 16-wide packets (TESSERA_BATCHING=1) against
// one ray at a time (the default), alternating rounds, and whether the images agree:
// optix7_batching_ratio=<batched time / single-ray time>.
int RunBatching(const std::string& model, unsigned width, unsigned height, int warmup, int runs) {
  const Mesh mesh = LoadObjMesh(model);
  Pipelines p;
  const Gas gas = BuildGas(p, mesh);
  OptixShaderBindingTable sbt;
  OptixPipeline pipeline = p.Make("__raygen__pinhole", "params", &sbt);
  const EyelightParams params = MakeParams(width, height, gas.handle, gas);
  const CUdeviceptr d_params = Upload(&params, sizeof(params));
  const size_t pixels = size_t{width} * height;
  std::vector<uchar4> images[2];
  std::vector<double> medians[2];
  constexpr int kRounds = 5;
  for (int round = 0; round < kRounds; ++round) {
    for (int k = 0; k < 2; ++k) {  // 0: single rays, 1: batched
      setenv("TESSERA_BATCHING", k == 0 ? "0" : "1", 1);
      const LaunchTimes t = TimeLaunches(
          [&] {
            CHECK_OPTIX(
                optixLaunch(pipeline, nullptr, d_params, sizeof(params), &sbt, width, height, 1));
          },
          round == 0 ? warmup : 1, runs);
      medians[k].push_back(t.Median());
      if (round == 0) {
        images[k].resize(pixels);
        CHECK_CUDA(cudaMemcpy(images[k].data(), params.image, pixels * sizeof(uchar4),
                              cudaMemcpyDeviceToHost));
      }
    }
  }
  unsetenv("TESSERA_BATCHING");
  size_t differ = 0;
  for (size_t i = 0; i < pixels; ++i) {
    const uchar4 a = images[0][i], b = images[1][i];
    differ += a.x != b.x || a.y != b.y || a.z != b.z || a.w != b.w;
  }
  double ratio[kRounds];
  for (int r = 0; r < kRounds; ++r) ratio[r] = medians[1][r] / medians[0][r];
  std::sort(ratio, ratio + kRounds);
  std::sort(medians[0].begin(), medians[0].end());
  std::sort(medians[1].begin(), medians[1].end());
  std::printf(
      "single rays %.3f ms, batched %.3f ms per launch (medians of %d rounds); %zu of %zu "
      "pixels differ\n",
      1e3 * medians[0][kRounds / 2], 1e3 * medians[1][kRounds / 2], kRounds, differ, pixels);
  std::printf("optix7_batching_ratio=%.3f (rounds %.3f..%.3f)\n", ratio[kRounds / 2], ratio[0],
              ratio[kRounds - 1]);
  return 0;
}

int RunBytes() {
  constexpr size_t kBuffer = size_t{64} << 20;
  constexpr unsigned kStride = 100;  // every 100th word: 1% of the buffer
  const unsigned words = static_cast<unsigned>(kBuffer / sizeof(unsigned) / kStride);
  Pipelines p;
  OptixShaderBindingTable sbt;
  OptixPipeline pipeline = p.Make("__raygen__write", "write_params", &sbt);
  void* buffer = nullptr;
  CHECK_CUDA(cudaMalloc(&buffer, kBuffer));
  CHECK_CUDA(cudaMemset(buffer, 0, kBuffer));
  WriteParams params = {static_cast<unsigned*>(buffer), kStride, 1};
  void* d_params = nullptr;
  CHECK_CUDA(cudaMalloc(&d_params, sizeof(params)));
  auto launch = [&](const char* what) {
    CHECK_CUDA(cudaMemcpy(d_params, &params, sizeof(params), cudaMemcpyHostToDevice));
    const Pipelines::Stats before = p.Transfers();
    CHECK_OPTIX(optixLaunch(pipeline, nullptr, reinterpret_cast<CUdeviceptr>(d_params),
                            sizeof(params), &sbt, words, 1, 1));
    const Pipelines::Stats after = p.Transfers();
    std::printf("%s: sent %llu bytes, received %llu bytes\n", what, after.sent - before.sent,
                after.received - before.received);
    return Pipelines::Stats{after.sent - before.sent, after.received - before.received};
  };
  launch("first launch (everything ships)");
  launch("a launch writing what it wrote before");
  const Pipelines::Stats unchanged = launch("the same launch again");
  std::vector<unsigned char> four_k(4096, 7);
  CHECK_CUDA(cudaMemcpy(static_cast<char*>(buffer) + kBuffer / 2 + 100, four_k.data(),
                        four_k.size(), cudaMemcpyHostToDevice));
  const Pipelines::Stats after_memcpy = launch("after a 4 KiB cudaMemcpy");
  params.value = 1000;
  const Pipelines::Stats writes = launch("programs write 1% of the buffer anew");
  params.value = 1000;
  const Pipelines::Stats next = launch("the next launch (other devices take those bytes)");
  const char* devices = std::getenv("TESSERA_DEVICES");
  std::printf("devices=%s buffer_bytes=%zu\n", devices ? devices : "", kBuffer);
  std::printf("optix7_unchanged_launch_bytes_sent=%llu\n", unchanged.sent);
  std::printf("optix7_4k_memcpy_launch_bytes_sent=%llu\n", after_memcpy.sent);
  std::printf("optix7_1pct_write_bytes_gathered=%llu (%.4f of the buffer)\n", writes.received,
              double(writes.received) / kBuffer);
  std::printf("optix7_1pct_write_next_launch_bytes_sent=%llu (%.4f of the buffer)\n", next.sent,
              double(next.sent) / kBuffer);
  return 0;
}

}  // namespace
}  // namespace tessera::bench

int main(int argc, char** argv) {
  CLI::App app{"tessera-bench-optix7: the OptiX 7 layer against Embree's viewer, and its bytes"};
  std::string mode = "all", model = TESSERA_BENCH_DEFAULT_MODEL, viewer = "viewer";
  std::string devices;
  unsigned width = 1024, height = 1024;
  int warmup = 5, runs = 20;
  app.add_option("--mode", mode, "eyelight, flags, batching, bytes or all")
      ->check(CLI::IsMember({"eyelight", "flags", "batching", "bytes", "all"}));
  app.add_option("--model", model, "OBJ model for eyelight");
  app.add_option("--viewer", viewer, "Embree's viewer executable");
  app.add_option("--devices", devices,
                 "device spec (default: inproc for eyelight, local:2 for bytes)");
  app.add_option("--width", width);
  app.add_option("--height", height);
  app.add_option("--warmup", warmup);
  app.add_option("--runs", runs);
  CLI11_PARSE(app, argc, argv);
  int status = 0;
  if (mode == "eyelight" || mode == "all") {
    setenv("TESSERA_DEVICES", devices.empty() ? "inproc" : devices.c_str(), 1);
    status = tessera::bench::RunEyelight(model, width, height, warmup, runs, viewer);
  }
  if (status == 0 && (mode == "flags" || mode == "all")) {
    setenv("TESSERA_DEVICES", devices.empty() ? "inproc" : devices.c_str(), 1);
    status = tessera::bench::RunFlags(model, width, height, warmup, runs);
  }
  if (status == 0 && (mode == "batching" || mode == "all")) {
    setenv("TESSERA_DEVICES", devices.empty() ? "inproc" : devices.c_str(), 1);
    status = tessera::bench::RunBatching(model, width, height, warmup, runs);
  }
  if (status == 0 && (mode == "bytes" || mode == "all")) {
    setenv("TESSERA_DEVICES", devices.empty() ? "local:2" : devices.c_str(), 1);
    status = tessera::bench::RunBytes();
  }
  return status;
}

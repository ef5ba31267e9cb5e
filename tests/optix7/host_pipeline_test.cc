// Pipelines (link options, option consistency, contexts), SBT header packing, optixLaunch's
// argument checks, and a program that crashes its worker named in the launch's error.
#include <cuda_runtime.h>

#include <cstdlib>
#include <cstring>
#include <string>

#include "host_api_fixture.h"

namespace tessera_test {
namespace {

using PipelineTest = OptixHostTest;

TEST_F(PipelineTest, LinkOptionsAndOptionConsistency) {
  OptixModule m = CompileModule();
  OptixProgramGroupDesc desc = Raygen(m, "__raygen__rg");
  OptixProgramGroup raygen = nullptr;
  ASSERT_EQ(optixProgramGroupCreate(context_, &desc, 1, nullptr, nullptr, nullptr, &raygen),
            OPTIX_SUCCESS);
  OptixPipelineLinkOptions link{};
  link.maxTraceDepth = 32;
  OptixPipeline pipeline = nullptr;
  EXPECT_EQ(optixPipelineCreate(context_, &pipeline_options_, &link, &raygen, 1, nullptr, nullptr,
                                &pipeline),
            OPTIX_ERROR_INVALID_VALUE);
  EXPECT_TRUE(Logged(2, "pipelineLinkOptions->maxTraceDepth is 32; OptiX allows at most 31"));
  link.maxTraceDepth = 1;
  EXPECT_EQ(optixPipelineCreate(context_, &pipeline_options_, &link, &raygen, 0, nullptr, nullptr,
                                &pipeline),
            OPTIX_ERROR_INVALID_VALUE);

  // Options that differ from the module's: a warning, or an error in validation mode.
  OptixPipelineCompileOptions other = pipeline_options_;
  other.numPayloadValues = 4;
  char log[1024];
  size_t log_size = sizeof(log);
  ASSERT_EQ(optixPipelineCreate(context_, &other, &link, &raygen, 1, log, &log_size, &pipeline),
            OPTIX_SUCCESS);
  EXPECT_NE(std::string(log).find("numPayloadValues (4 here, 3 there)"), std::string::npos) << log;
  EXPECT_TRUE(Logged(3, "numPayloadValues (4 here, 3 there)"));

  OptixDeviceContext validating = CreateContext(true);
  OptixModule vm = CompileModule(kAllKindsSource, validating);
  desc = Raygen(vm, "__raygen__rg");
  OptixProgramGroup vraygen = nullptr;
  ASSERT_EQ(optixProgramGroupCreate(validating, &desc, 1, nullptr, nullptr, nullptr, &vraygen),
            OPTIX_SUCCESS);
  OptixPipeline strict = nullptr;
  EXPECT_EQ(optixPipelineCreate(validating, &other, &link, &vraygen, 1, nullptr, nullptr, &strict),
            OPTIX_ERROR_INVALID_VALUE);
  // Groups of one context in a pipeline of another.
  EXPECT_EQ(optixPipelineCreate(validating, &pipeline_options_, &link, &raygen, 1, nullptr, nullptr,
                                &strict),
            OPTIX_ERROR_INVALID_VALUE);
  EXPECT_TRUE(Logged(2, "programGroups[0] belongs to another device context"));
  // Destroying a context ends its objects' handles.
  ASSERT_EQ(optixDeviceContextDestroy(validating), OPTIX_SUCCESS);
  contexts_.pop_back();
  OptixStackSizes sizes{};
  EXPECT_EQ(optixProgramGroupGetStackSize(vraygen, &sizes, nullptr), OPTIX_ERROR_INVALID_VALUE);
}

TEST_F(PipelineTest, SbtHeaderPackingAndLaunchArgumentChecks) {
  OptixModule m = CompileModule();
  OptixProgramGroupDesc d[2] = {Raygen(m, "__raygen__rg"), {}};
  d[1].kind = OPTIX_PROGRAM_GROUP_KIND_MISS;
  d[1].miss = {m, "__miss__ms"};
  OptixProgramGroup g[2] = {};
  ASSERT_EQ(optixProgramGroupCreate(context_, d, 2, nullptr, nullptr, nullptr, g), OPTIX_SUCCESS);

  struct alignas(OPTIX_SBT_RECORD_ALIGNMENT) Record {
    unsigned char header[OPTIX_SBT_RECORD_HEADER_SIZE];
    float data[4];
  };
  Record records[2];
  std::memset(records, 0xab, sizeof(records));
  ASSERT_EQ(optixSbtRecordPackHeader(g[0], records[0].header), OPTIX_SUCCESS);
  ASSERT_EQ(optixSbtRecordPackHeader(g[1], records[1].header), OPTIX_SUCCESS);
  // worker/memory/sbt_header.h: kSbtHeaderMagic, the group's id, zeros.
  unsigned long long magic = 0, id0 = 0, id1 = 0, reserved[2] = {1, 1};
  std::memcpy(&magic, records[0].header, 8);
  EXPECT_EQ(magic, 0x3152485453455354ull);
  std::memcpy(&id0, records[0].header + 8, 8);
  std::memcpy(&id1, records[1].header + 8, 8);
  std::memcpy(reserved, records[0].header + 16, 16);
  EXPECT_NE(id0, 0u);
  EXPECT_NE(id0, id1);
  EXPECT_EQ(reserved[0], 0u);
  EXPECT_EQ(reserved[1], 0u);
  EXPECT_EQ(records[0].data[0], records[1].data[0]);  // the data is not touched
  EXPECT_EQ(optixSbtRecordPackHeader(g[0], nullptr), OPTIX_ERROR_INVALID_VALUE);

  void* device = nullptr;
  ASSERT_EQ(cudaMalloc(&device, sizeof(records)), cudaSuccess);
  EXPECT_EQ(optixSbtRecordPackHeader(g[0], device), OPTIX_ERROR_INVALID_VALUE);
  EXPECT_TRUE(Logged(2, "sbtRecordHeaderHostPointer is device memory"));
  ASSERT_EQ(cudaMemcpy(device, records, sizeof(records), cudaMemcpyHostToDevice), cudaSuccess);
  const CUdeviceptr base = reinterpret_cast<CUdeviceptr>(device);
  void* params = nullptr;
  ASSERT_EQ(cudaMalloc(&params, 64), cudaSuccess);

  OptixPipelineLinkOptions link{};
  link.maxTraceDepth = 1;
  OptixPipeline pipeline = nullptr;
  ASSERT_EQ(
      optixPipelineCreate(context_, &pipeline_options_, &link, g, 2, nullptr, nullptr, &pipeline),
      OPTIX_SUCCESS);
  OptixShaderBindingTable sbt{};
  sbt.raygenRecord = base;
  sbt.missRecordBase = base + sizeof(Record);
  sbt.missRecordStrideInBytes = sizeof(Record);
  sbt.missRecordCount = 1;
  const CUdeviceptr p = reinterpret_cast<CUdeviceptr>(params);

  EXPECT_EQ(optixLaunch(nullptr, 0, p, 64, &sbt, 4, 4, 1), OPTIX_ERROR_INVALID_VALUE);
  EXPECT_EQ(optixLaunch(pipeline, 0, p, 64, nullptr, 4, 4, 1), OPTIX_ERROR_INVALID_VALUE);
  EXPECT_TRUE(Logged(2, "optixLaunch: sbt is null"));
  OptixShaderBindingTable bad = sbt;
  bad.raygenRecord = reinterpret_cast<CUdeviceptr>(&records[0]);
  EXPECT_EQ(optixLaunch(pipeline, 0, p, 64, &bad, 4, 4, 1), OPTIX_ERROR_INVALID_VALUE);
  EXPECT_TRUE(Logged(2, "is not device memory"));
  bad = sbt;
  bad.missRecordStrideInBytes = 24;
  EXPECT_EQ(optixLaunch(pipeline, 0, p, 64, &bad, 4, 4, 1), OPTIX_ERROR_INVALID_VALUE);
  EXPECT_TRUE(Logged(2, "sbt->missRecordStrideInBytes is 24, not a multiple of"));
  bad = sbt;
  bad.missRecordCount = 2;  // past the allocation
  EXPECT_EQ(optixLaunch(pipeline, 0, p, 64, &bad, 4, 4, 1), OPTIX_ERROR_INVALID_VALUE);
  EXPECT_TRUE(Logged(2, "are not in one cudaMalloc allocation"));
  EXPECT_EQ(optixLaunch(pipeline, 0, p, 128, &sbt, 4, 4, 1), OPTIX_ERROR_INVALID_VALUE);
  EXPECT_TRUE(Logged(2, "(128 bytes) is not in one cudaMalloc allocation"));
  EXPECT_EQ(optixLaunch(pipeline, 0, p, 64, &sbt, 0, 4, 1), OPTIX_ERROR_INVALID_VALUE);
  EXPECT_EQ(optixLaunch(pipeline, 0, p, 64, &sbt, 1u << 16, 1u << 15, 1),
            OPTIX_ERROR_INVALID_VALUE);
  EXPECT_TRUE(Logged(2, "at most 2^30"));
  // Valid arguments launch: raygen writes params.out[x] = 1 (the parameters are the module's
  // 8-byte `params`).
  void* out = nullptr;
  ASSERT_EQ(cudaMalloc(&out, 4 * sizeof(unsigned)), cudaSuccess);
  ASSERT_EQ(cudaMemset(out, 0, 4 * sizeof(unsigned)), cudaSuccess);
  ASSERT_EQ(cudaMemcpy(params, &out, sizeof(out), cudaMemcpyHostToDevice), cudaSuccess);
  EXPECT_EQ(optixLaunch(pipeline, 0, p, sizeof(out), &sbt, 4, 4, 1), OPTIX_SUCCESS)
      << (log_.empty() ? std::string() : log_.back().message);
  unsigned written[4] = {};
  ASSERT_EQ(cudaMemcpy(written, out, sizeof(written), cudaMemcpyDeviceToHost), cudaSuccess);
  for (unsigned w : written) EXPECT_EQ(w, 1u);

  // Validation mode reads the records' headers: one never packed is refused.
  OptixDeviceContext validating = CreateContext(true);
  OptixModule vm = CompileModule(kAllKindsSource, validating);
  OptixProgramGroupDesc vd = Raygen(vm, "__raygen__rg");
  OptixProgramGroup vg = nullptr;
  ASSERT_EQ(optixProgramGroupCreate(validating, &vd, 1, nullptr, nullptr, nullptr, &vg),
            OPTIX_SUCCESS);
  OptixPipeline vp = nullptr;
  ASSERT_EQ(
      optixPipelineCreate(validating, &pipeline_options_, &link, &vg, 1, nullptr, nullptr, &vp),
      OPTIX_SUCCESS);
  OptixShaderBindingTable vsbt{};
  vsbt.raygenRecord = base;  // packed by g[0], which is not in vp
  EXPECT_EQ(optixLaunch(vp, 0, p, 64, &vsbt, 4, 4, 1), OPTIX_ERROR_VALIDATION_FAILURE);
  EXPECT_TRUE(Logged(2, "was packed by a program group not in the pipeline"));
  ASSERT_EQ(cudaMemset(device, 0, sizeof(Record)), cudaSuccess);
  EXPECT_EQ(optixLaunch(vp, 0, p, 64, &vsbt, 4, 4, 1), OPTIX_ERROR_VALIDATION_FAILURE);
  EXPECT_TRUE(Logged(2, "has no header packed by optixSbtRecordPackHeader"));
  EXPECT_EQ(cudaFree(device), cudaSuccess);
  EXPECT_EQ(cudaFree(params), cudaSuccess);
}

// A program that crashes the worker process running it: the launch fails (a crash is not run
// again elsewhere, it would crash there too) and its error names the program, as OptiX 3's do.
TEST_F(PipelineTest, ACrashingProgramIsNamedInTheLaunchError) {
  const char* saved = std::getenv("TESSERA_DEVICES");
  const std::string restore = saved != nullptr ? saved : "";
  setenv("TESSERA_DEVICES", "local:1", 1);  // read when the context first launches
  OptixDeviceContext context = CreateContext(false);
  OptixModule m = CompileModule(R"(
#include <optix.h>
struct Params { unsigned int* out; };
extern "C" { __constant__ Params params; }
extern "C" __global__ void __raygen__crash() {
  volatile unsigned int* nowhere = nullptr;
  *nowhere = optixGetLaunchIndex().x;
}
)",
                                context);
  OptixProgramGroupDesc d = Raygen(m, "__raygen__crash");
  OptixProgramGroup g = nullptr;
  ASSERT_EQ(optixProgramGroupCreate(context, &d, 1, nullptr, nullptr, nullptr, &g), OPTIX_SUCCESS);
  OptixPipelineLinkOptions link{};
  link.maxTraceDepth = 1;
  OptixPipeline pipeline = nullptr;
  ASSERT_EQ(
      optixPipelineCreate(context, &pipeline_options_, &link, &g, 1, nullptr, nullptr, &pipeline),
      OPTIX_SUCCESS);
  struct alignas(OPTIX_SBT_RECORD_ALIGNMENT) Record {
    unsigned char header[OPTIX_SBT_RECORD_HEADER_SIZE];
  } record;
  ASSERT_EQ(optixSbtRecordPackHeader(g, record.header), OPTIX_SUCCESS);
  void* device = nullptr;
  ASSERT_EQ(cudaMalloc(&device, sizeof(record)), cudaSuccess);
  ASSERT_EQ(cudaMemcpy(device, &record, sizeof(record), cudaMemcpyHostToDevice), cudaSuccess);
  OptixShaderBindingTable sbt{};
  sbt.raygenRecord = reinterpret_cast<CUdeviceptr>(device);
  EXPECT_EQ(optixLaunch(pipeline, 0, 0, 0, &sbt, 2, 2, 1), OPTIX_ERROR_LAUNCH_FAILURE);
  EXPECT_TRUE(Logged(2, "SIGSEGV) in OptiX 7 raygen program __raygen__crash in "))
      << (log_.empty() ? std::string() : log_.back().message);
  // The same from a lane's stack (batched tracing), on the worker started in its place.
  log_.clear();
  setenv("TESSERA_BATCHING", "1", 1);
  EXPECT_EQ(optixLaunch(pipeline, 0, 0, 0, &sbt, 4, 4, 1), OPTIX_ERROR_LAUNCH_FAILURE);
  unsetenv("TESSERA_BATCHING");
  EXPECT_TRUE(Logged(2, "SIGSEGV) in OptiX 7 raygen program __raygen__crash in "))
      << (log_.empty() ? std::string() : log_.back().message);
  if (restore.empty()) {
    unsetenv("TESSERA_DEVICES");
  } else {
    setenv("TESSERA_DEVICES", restore.c_str(), 1);
  }
}

// cudaMallocManaged memory is written and read by the host through its pointers, without
// cudaMemcpy: launches on worker processes still see the host's writes and the host theirs.
TEST_F(PipelineTest, ManagedMemoryIsSharedWithWorkersWithoutCopies) {
  const char* saved = std::getenv("TESSERA_DEVICES");
  const std::string restore = saved != nullptr ? saved : "";
  setenv("TESSERA_DEVICES", "local:2", 1);
  OptixDeviceContext context = CreateContext(false);
  OptixModule m = CompileModule(kAllKindsSource, context);
  OptixProgramGroupDesc d = Raygen(m, "__raygen__rg");
  OptixProgramGroup g = nullptr;
  ASSERT_EQ(optixProgramGroupCreate(context, &d, 1, nullptr, nullptr, nullptr, &g), OPTIX_SUCCESS);
  OptixPipelineLinkOptions link{};
  link.maxTraceDepth = 1;
  OptixPipeline pipeline = nullptr;
  ASSERT_EQ(
      optixPipelineCreate(context, &pipeline_options_, &link, &g, 1, nullptr, nullptr, &pipeline),
      OPTIX_SUCCESS);
  struct alignas(OPTIX_SBT_RECORD_ALIGNMENT) Record {
    unsigned char header[OPTIX_SBT_RECORD_HEADER_SIZE];
  };
  Record* record = nullptr;
  unsigned** params = nullptr;  // struct Params { unsigned int* out; }
  unsigned* out = nullptr;
  EXPECT_EQ(cudaMallocManaged(&out, 0), cudaErrorInvalidValue);
  EXPECT_EQ(cudaMallocManaged(&out, 64, 7), cudaErrorInvalidValue);
  (void)cudaGetLastError();
  ASSERT_EQ(cudaMallocManaged(&record, sizeof(Record)), cudaSuccess);
  ASSERT_EQ(cudaMallocManaged(&params, sizeof(unsigned*)), cudaSuccess);
  ASSERT_EQ(cudaMallocManaged(&out, 64 * sizeof(unsigned)), cudaSuccess);
  Record host_record;
  ASSERT_EQ(optixSbtRecordPackHeader(g, host_record.header), OPTIX_SUCCESS);
  *record = host_record;  // plain stores, no cudaMemcpy
  *params = out;
  for (int i = 0; i < 64; ++i) out[i] = 7;
  OptixShaderBindingTable sbt{};
  sbt.raygenRecord = reinterpret_cast<CUdeviceptr>(record);
  ASSERT_EQ(optixLaunch(pipeline, 0, reinterpret_cast<CUdeviceptr>(params), sizeof(unsigned*), &sbt,
                        32, 1, 1),
            OPTIX_SUCCESS)
      << (log_.empty() ? std::string() : log_.back().message);
  for (int i = 0; i < 64; ++i) EXPECT_EQ(out[i], i < 32 ? 1u : 7u) << i;  // read in place
  // The host rewrites part of it; the next launch's programs see it (they overwrite indices
  // 0..47, the host's 48..63 stay).
  for (int i = 0; i < 64; ++i) out[i] = 9;
  ASSERT_EQ(optixLaunch(pipeline, 0, reinterpret_cast<CUdeviceptr>(params), sizeof(unsigned*), &sbt,
                        48, 1, 1),
            OPTIX_SUCCESS);
  for (int i = 0; i < 64; ++i) EXPECT_EQ(out[i], i < 48 ? 1u : 9u) << i;
  EXPECT_EQ(cudaFree(out), cudaSuccess);
  if (restore.empty()) {
    unsetenv("TESSERA_DEVICES");
  } else {
    setenv("TESSERA_DEVICES", restore.c_str(), 1);
  }
}

}  // namespace
}  // namespace tessera_test

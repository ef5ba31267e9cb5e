// Fast-math program modules on the OptiX 7 layer (docs/fast_math.md), on the devices
// TESSERA_DEVICES names (tests/fast_math runs it on inproc and local:2): modules built with
// FAST_MATH (tessera_add_optix7_program_module, tessera_embed_program) or compiled by a context
// with TESSERA_ACCURACY_FAST_MATH flush denormals to zero and still see NaN and infinity (their
// tests, and OPTIX_EXCEPTION_CODE_INVALID_RAY for the rays they compute); default modules keep
// IEEE denormals, bit for bit, also after a fast-math launch.
#include <cuda_runtime.h>
#include <gtest/gtest.h>
#include <optix.h>
#include <optix_function_table_definition.h>
#include <optix_stubs.h>

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "fast_math7_params.h"
#include "float_mode.h"  // worker/core: the control word the engine sets
#include "tessera/optix7_ext.h"

extern "C" const char fast_math7_embedded[];  // tessera_embed_program(... FAST_MATH)

namespace {

constexpr unsigned kW = 64;  // enough launch indices for every thread of a device to take some

// The calling thread's floating-point mode, without the sticky exception flags that its own
// arithmetic sets.
uint64_t ControlWord() { return tessera::worker::FloatMode() & ~tessera::worker::kFloatStatusBits; }

uint32_t Bits(float f) {
  uint32_t u;
  std::memcpy(&u, &f, sizeof u);
  return u;
}

// What __raygen__denormals computes without fast math, here where denormals are on.
struct Expected {
  float product, scaled;
};
Expected IeeeDenormals() {
  volatile float tiny = 1e-20f, denormal = 1e-40f, big = 1e10f;
  return {tiny * tiny, denormal * big};
}

struct alignas(OPTIX_SBT_RECORD_ALIGNMENT) Record {
  char header[OPTIX_SBT_RECORD_HEADER_SIZE];
};

class FastMath7Test : public ::testing::Test {
 protected:
  void SetUp() override {
    setenv("TESSERA_CACHE_DIR", TESSERA_FAST_MATH_CACHE_DIR, 1);
    mode_before_ = ControlWord();
    ASSERT_FALSE(tessera::worker::FlushesDenormals())
        << "the test thread must start with IEEE denormals";
    ASSERT_EQ(cudaFree(nullptr), cudaSuccess);
    ASSERT_EQ(optixInit(), OPTIX_SUCCESS);
    OptixDeviceContextOptions options = {};
    ASSERT_EQ(optixDeviceContextCreate(nullptr, &options, &context_), OPTIX_SUCCESS);
    ASSERT_EQ(cudaMalloc(&d_out_, kW * sizeof(float4)), cudaSuccess);
    ASSERT_EQ(cudaMalloc(&d_params_, sizeof(FastMathParams)), cudaSuccess);
    params_.out = static_cast<float4*>(d_out_);
    params_.tiny = 1e-20f;
    params_.denormal_in = 1e-40f;
    params_.big = 1e10f;
    params_.zero = 0.f;
    params_.one = 1.f;
  }
  void TearDown() override {
    for (void* p : allocations_) cudaFree(p);
    cudaFree(d_out_);
    cudaFree(d_params_);
    optixDeviceContextDestroy(context_);
    // An in-process device runs pieces and loads modules on this thread: it keeps its own mode.
    EXPECT_EQ(ControlWord(), mode_before_);
  }

  void SetAccuracy(unsigned flags) {
    ASSERT_EQ(tesseraOptixDeviceContextSetAccuracy(context_, flags), OPTIX_SUCCESS);
  }

  // A module from `input` (a path, or embedded module text), as optixModuleCreate takes it.
  OptixModule Module(const std::string& input) {
    OptixModuleCompileOptions module_options = {};
    OptixPipelineCompileOptions pipeline_options = PipelineOptions();
    char log[4096];
    size_t log_size = sizeof(log);
    OptixModule m = nullptr;
    const OptixResult r = optixModuleCreate(context_, &module_options, &pipeline_options,
                                            input.c_str(), input.size(), log, &log_size, &m);
    EXPECT_EQ(r, OPTIX_SUCCESS) << optixGetErrorName(r) << ": " << log;
    return m;
  }

  // Launches `raygen` of `m` (with a miss and an exception program of the same module) over kW
  // indices and returns what they wrote.
  std::vector<float4> Launch(OptixModule m, const char* raygen) {
    OptixProgramGroupDesc desc[3] = {};
    desc[0].kind = OPTIX_PROGRAM_GROUP_KIND_RAYGEN;
    desc[0].raygen = {m, raygen};
    desc[1].kind = OPTIX_PROGRAM_GROUP_KIND_MISS;
    desc[1].miss = {m, "__miss__none"};
    desc[2].kind = OPTIX_PROGRAM_GROUP_KIND_EXCEPTION;
    desc[2].exception = {m, "__exception__record"};
    OptixProgramGroupOptions group_options = {};
    OptixProgramGroup groups[3] = {};
    char log[4096];
    size_t log_size = sizeof(log);
    std::vector<float4> out(kW, make_float4(-1.f, -1.f, -1.f, -1.f));
    OptixResult r =
        optixProgramGroupCreate(context_, desc, 3, &group_options, log, &log_size, groups);
    EXPECT_EQ(r, OPTIX_SUCCESS) << optixGetErrorName(r) << ": " << log;
    if (r != OPTIX_SUCCESS) return out;
    OptixPipelineCompileOptions pipeline_options = PipelineOptions();
    OptixPipelineLinkOptions link_options = {};
    link_options.maxTraceDepth = 1;
    OptixPipeline pipeline = nullptr;
    log_size = sizeof(log);
    r = optixPipelineCreate(context_, &pipeline_options, &link_options, groups, 3, log, &log_size,
                            &pipeline);
    EXPECT_EQ(r, OPTIX_SUCCESS) << optixGetErrorName(r) << ": " << log;
    if (r != OPTIX_SUCCESS) return out;
    Record records[3];
    for (int i = 0; i < 3; ++i) EXPECT_EQ(optixSbtRecordPackHeader(groups[i], &records[i]), 0);
    void* d_records = nullptr;
    EXPECT_EQ(cudaMalloc(&d_records, sizeof records), cudaSuccess);
    allocations_.push_back(d_records);
    EXPECT_EQ(cudaMemcpy(d_records, records, sizeof records, cudaMemcpyHostToDevice), cudaSuccess);
    const auto base = reinterpret_cast<CUdeviceptr>(d_records);
    OptixShaderBindingTable sbt = {};
    sbt.raygenRecord = base;
    sbt.missRecordBase = base + sizeof(Record);
    sbt.missRecordStrideInBytes = sizeof(Record);
    sbt.missRecordCount = 1;
    sbt.exceptionRecord = base + 2 * sizeof(Record);
    EXPECT_EQ(cudaMemcpy(d_params_, &params_, sizeof params_, cudaMemcpyHostToDevice), cudaSuccess);
    r = optixLaunch(pipeline, nullptr, reinterpret_cast<CUdeviceptr>(d_params_), sizeof params_,
                    &sbt, kW, 1, 1);
    EXPECT_EQ(r, OPTIX_SUCCESS) << optixGetErrorName(r);
    EXPECT_EQ(cudaDeviceSynchronize(), cudaSuccess);
    EXPECT_EQ(cudaMemcpy(out.data(), d_out_, kW * sizeof(float4), cudaMemcpyDeviceToHost),
              cudaSuccess);
    optixPipelineDestroy(pipeline);
    for (OptixProgramGroup g : groups) optixProgramGroupDestroy(g);
    return out;
  }

  void ExpectFlushed(const std::vector<float4>& r, const char* what) {
    ASSERT_EQ(r.size(), kW);
    for (unsigned x = 0; x < kW; ++x) {
      EXPECT_EQ(Bits(r[x].x), 0u) << what << ": index " << x << " product " << r[x].x;
      EXPECT_EQ(Bits(r[x].y), 0u) << what << ": index " << x << " scaled " << r[x].y;
    }
  }
  void ExpectIeee(const std::vector<float4>& r, const char* what) {
    ASSERT_EQ(r.size(), kW);
    const Expected e = IeeeDenormals();
    ASSERT_NE(e.product, 0.f);
    for (unsigned x = 0; x < kW; ++x) {
      EXPECT_EQ(Bits(r[x].x), Bits(e.product)) << what << ": index " << x;
      EXPECT_EQ(Bits(r[x].y), Bits(e.scaled)) << what << ": index " << x;
    }
  }

  static OptixPipelineCompileOptions PipelineOptions() {
    OptixPipelineCompileOptions p = {};
    p.pipelineLaunchParamsVariableName = "params";
    p.exceptionFlags = OPTIX_EXCEPTION_FLAG_DEBUG;  // invalid rays raise
    return p;
  }

  OptixDeviceContext context_ = nullptr;
  FastMathParams params_ = {};
  void* d_out_ = nullptr;
  void* d_params_ = nullptr;
  std::vector<void*> allocations_;
  uint64_t mode_before_ = 0;
};

TEST_F(FastMath7Test, FastMathModuleFlushesDenormals) {
  ExpectFlushed(Launch(Module(TESSERA_FAST_MATH7_FAST), "__raygen__denormals"), "FAST_MATH");
}

TEST_F(FastMath7Test, EmbeddedFastMathModuleFlushesDenormals) {
  ExpectFlushed(Launch(Module(fast_math7_embedded), "__raygen__denormals"), "embedded FAST_MATH");
}

TEST_F(FastMath7Test, DefaultModuleKeepsIeeeDenormals) {
  ExpectIeee(Launch(Module(TESSERA_FAST_MATH7_DEFAULT), "__raygen__denormals"), "default");
}

TEST_F(FastMath7Test, DefaultLaunchAfterFastMathLaunchIsUnchanged) {
  OptixModule fast = Module(TESSERA_FAST_MATH7_FAST);
  OptixModule plain = Module(TESSERA_FAST_MATH7_DEFAULT);
  for (int round = 0; round < 3; ++round) {
    ExpectFlushed(Launch(fast, "__raygen__denormals"), "FAST_MATH");
    ExpectIeee(Launch(plain, "__raygen__denormals"), "default after a FAST_MATH launch");
  }
}

TEST_F(FastMath7Test, NanAndInfinityTestsWorkInFastMathModules) {
  for (const char* path : {TESSERA_FAST_MATH7_FAST, TESSERA_FAST_MATH7_DEFAULT}) {
    const std::vector<float4> r = Launch(Module(path), "__raygen__checks");
    for (unsigned x = 0; x < kW; ++x) {
      EXPECT_EQ(r[x].x, 1.f) << path << ": isnan(0/0) at index " << x;
      EXPECT_EQ(r[x].y, 1.f) << path << ": isinf(1/0) at index " << x;
      EXPECT_EQ(r[x].z, 0.f) << path << ": isfinite(1/0) at index " << x;
      EXPECT_EQ(r[x].w, 1.f) << path << ": NaN != NaN at index " << x;
    }
  }
}

TEST_F(FastMath7Test, InvalidRaysOfFastMathProgramsRaiseTheException) {
  OptixModule fast = Module(TESSERA_FAST_MATH7_FAST);
  for (int mode : {0, 1}) {
    params_.mode = mode;
    const std::vector<float4> r = Launch(fast, "__raygen__invalid_ray");
    for (unsigned x = 0; x < kW; ++x) {
      EXPECT_EQ(r[x].x, float(OPTIX_EXCEPTION_CODE_INVALID_RAY))
          << "mode " << mode << " index " << x;
    }
  }
}

// TESSERA_ACCURACY_FAST_MATH: source the context compiles gets fast math (NaN tests kept); the
// compile cache keeps the two compiles of one source apart.
TEST_F(FastMath7Test, ContextFlagCompilesSourceWithFastMath) {
  ExpectIeee(Launch(Module(TESSERA_FAST_MATH7_SOURCE), "__raygen__denormals"), "source, no flag");
  SetAccuracy(TESSERA_ACCURACY_FAST_MATH);
  OptixModule fast = Module(TESSERA_FAST_MATH7_SOURCE);
  ExpectFlushed(Launch(fast, "__raygen__denormals"), "source compiled with the flag");
  const std::vector<float4> checks = Launch(fast, "__raygen__checks");
  EXPECT_EQ(checks[0].x, 1.f) << "isnan(0/0)";
  EXPECT_EQ(checks[0].y, 1.f) << "isinf(1/0)";
  SetAccuracy(0);
  ExpectIeee(Launch(Module(TESSERA_FAST_MATH7_SOURCE), "__raygen__denormals"),
             "source, flag cleared");
  // A module compiled while the flag was set stays a fast-math one.
  ExpectFlushed(Launch(fast, "__raygen__denormals"), "module compiled with the flag, flag cleared");
}

}  // namespace

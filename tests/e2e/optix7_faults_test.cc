// Faults under OptiX 7 launches, as under OptiX 3 ones (docs/devices.md, "Faults"): a worker
// killed in the middle of an optixLaunch tiled over local:3 costs time, not output (its tiles run
// again on the others); a worker killed between launches is replaced, and its new session gets
// the whole of device memory again.
#include <cuda_runtime.h>
#include <gtest/gtest.h>
#include <optix.h>
#include <optix_function_table_definition.h>
#include <optix_stubs.h>
#include <signal.h>
#include <stdlib.h>
#include <tessera/optix7_ext.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

#include "optix7_fault_params.h"
#include "process_util.h"

extern "C" const char optix7_fault_programs[];

namespace tessera::e2e {
namespace {

constexpr char kWorker[] = "tessera-worker";
constexpr unsigned kW = 96, kH = 64;
constexpr unsigned kNoiseWords = 1u << 19;  // 2 MiB that every launch index reads from

#define CUDA_OK(call) ASSERT_EQ((call), cudaSuccess) << #call
#define OPTIX_OK(call) ASSERT_EQ((call), OPTIX_SUCCESS) << #call

struct alignas(OPTIX_SBT_RECORD_ALIGNMENT) RaygenRecord {
  char header[OPTIX_SBT_RECORD_HEADER_SIZE];
};

// An application with its own OptixDeviceContext: the devices are TESSERA_DEVICES as it was at
// the context's first launch.
class App {
 public:
  ~App() {
    if (pipeline_ != nullptr) optixPipelineDestroy(pipeline_);
    if (group_ != nullptr) optixProgramGroupDestroy(group_);
    if (module_ != nullptr) optixModuleDestroy(module_);
    if (context_ != nullptr) optixDeviceContextDestroy(context_);
    for (void* p : allocations_) cudaFree(p);
  }

  void Create(const std::vector<unsigned>& noise) {
    OPTIX_OK(optixInit());
    OPTIX_OK(optixDeviceContextCreate(nullptr, nullptr, &context_));
    OptixModuleCompileOptions module_options = {};
    OptixPipelineCompileOptions pipeline_options = {};
    pipeline_options.numPayloadValues = 0;
    pipeline_options.pipelineLaunchParamsVariableName = "params";
    const std::string text = optix7_fault_programs;
    OPTIX_OK(optixModuleCreate(context_, &module_options, &pipeline_options, text.c_str(),
                               text.size(), nullptr, nullptr, &module_));
    OptixProgramGroupDesc desc = {};
    desc.kind = OPTIX_PROGRAM_GROUP_KIND_RAYGEN;
    desc.raygen = {module_, "__raygen__slow"};
    OptixProgramGroupOptions group_options = {};
    OPTIX_OK(
        optixProgramGroupCreate(context_, &desc, 1, &group_options, nullptr, nullptr, &group_));
    OptixPipelineLinkOptions link_options = {};
    link_options.maxTraceDepth = 1;
    OPTIX_OK(optixPipelineCreate(context_, &pipeline_options, &link_options, &group_, 1, nullptr,
                                 nullptr, &pipeline_));
    RaygenRecord record;
    OPTIX_OK(optixSbtRecordPackHeader(group_, &record));
    sbt_.raygenRecord = Upload(&record, sizeof(record));
    params_.noise =
        reinterpret_cast<const unsigned*>(Upload(noise.data(), noise.size() * sizeof(unsigned)));
    params_.noise_words = static_cast<unsigned>(noise.size());
    params_.image = reinterpret_cast<uchar4*>(Allocate(sizeof(uchar4) * kW * kH));
    params_.width = kW;
    d_params_ = Allocate(sizeof(FaultParams));
  }

  // Launches with `seed` and `iterations` per launch index; the image, or empty on failure.
  std::vector<uchar4> Launch(unsigned seed, unsigned iterations, OptixResult* result = nullptr) {
    params_.seed = seed;
    params_.iterations = iterations;
    EXPECT_EQ(cudaMemcpy(reinterpret_cast<void*>(d_params_), &params_, sizeof(params_),
                         cudaMemcpyHostToDevice),
              cudaSuccess);
    const OptixResult r =
        optixLaunch(pipeline_, nullptr, d_params_, sizeof(FaultParams), &sbt_, kW, kH, 1);
    if (result != nullptr) *result = r;
    if (r != OPTIX_SUCCESS) return {};
    std::vector<uchar4> image(kW * kH);
    EXPECT_EQ(cudaMemcpy(image.data(), params_.image, sizeof(uchar4) * image.size(),
                         cudaMemcpyDeviceToHost),
              cudaSuccess);
    return image;
  }

  unsigned long long BytesSent() const {
    unsigned long long sent = 0, received = 0;
    EXPECT_EQ(tesseraOptixDeviceContextGetTransferStats(context_, &sent, &received), OPTIX_SUCCESS);
    return sent;
  }

 private:
  CUdeviceptr Allocate(size_t bytes) {
    void* p = nullptr;
    EXPECT_EQ(cudaMalloc(&p, bytes), cudaSuccess);
    allocations_.push_back(p);
    return reinterpret_cast<CUdeviceptr>(p);
  }
  CUdeviceptr Upload(const void* data, size_t bytes) {
    const CUdeviceptr p = Allocate(bytes);
    EXPECT_EQ(cudaMemcpy(reinterpret_cast<void*>(p), data, bytes, cudaMemcpyHostToDevice),
              cudaSuccess);
    return p;
  }

  OptixDeviceContext context_ = nullptr;
  OptixModule module_ = nullptr;
  OptixProgramGroup group_ = nullptr;
  OptixPipeline pipeline_ = nullptr;
  OptixShaderBindingTable sbt_ = {};
  FaultParams params_ = {};
  CUdeviceptr d_params_ = 0;
  std::vector<void*> allocations_;
};

bool Same(const std::vector<uchar4>& a, const std::vector<uchar4>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(uchar4)) == 0;
}

// CPU time (clock ticks) a process has used, 0 once it is gone.
long CpuTicks(pid_t pid) {
  const std::string stat = ReadProcFile("/proc/" + std::to_string(pid) + "/stat");
  const size_t paren = stat.rfind(')');
  if (paren == std::string::npos) return 0;
  std::istringstream fields(stat.substr(paren + 2));
  std::string field;
  long utime = 0, stime = 0;
  for (int i = 3; i <= 15 && fields >> field; ++i) {
    if (i == 14) utime = std::stol(field);
    if (i == 15) stime = std::stol(field);
  }
  return utime + stime;
}

class Optix7FaultTest : public ::testing::Test {
 protected:
  void SetUp() override {
    unsigned h = 12345;
    noise_.resize(kNoiseWords);
    for (unsigned& w : noise_) w = h = h * 1103515245u + 12345u;
  }
  void TearDown() override { unsetenv("TESSERA_DEVICES"); }

  // What one in-process device renders: what every run with faults must give.
  std::vector<uchar4> Reference(unsigned seed, unsigned iterations) {
    setenv("TESSERA_DEVICES", "inproc", 1);
    App app;
    app.Create(noise_);
    return app.Launch(seed, iterations);
  }

  std::vector<unsigned> noise_;
};

// A launch during which one of local:3's workers is killed (once it has run tiles of it for a
// while) still succeeds with the fault-free image, and the next launch has three workers again.
TEST_F(Optix7FaultTest, WorkerKilledMidLaunchCostsTimeNotOutput) {
  constexpr unsigned kIterations = 40000;  // about a second of tracing on two cores
  const std::vector<uchar4> reference = Reference(7, kIterations);
  const std::vector<uchar4> warm_up = Reference(1, 10);
  ASSERT_FALSE(reference.empty());
  setenv("TESSERA_DEVICES", "local:3", 1);
  App app;
  app.Create(noise_);
  ASSERT_TRUE(Same(app.Launch(1, 10), warm_up));  // workers up, memory shipped
  std::vector<pid_t> workers = ChildrenNamed(getpid(), kWorker);
  ASSERT_EQ(workers.size(), 3u);
  const pid_t victim = workers.front();
  const long before = CpuTicks(victim);

  std::atomic<bool> done{false};
  OptixResult result = OPTIX_ERROR_UNKNOWN;
  std::vector<uchar4> image;
  testing::internal::CaptureStderr();
  std::thread launch([&] {
    image = app.Launch(7, kIterations, &result);
    done = true;
  });
  // Killed once it has spent a tenth of a second on this launch's tiles: in the middle of it.
  bool killed_mid_launch = false;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (!done && std::chrono::steady_clock::now() < deadline) {
    if (CpuTicks(victim) - before >= sysconf(_SC_CLK_TCK) / 10) {
      killed_mid_launch = !done && kill(victim, SIGKILL) == 0;
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  launch.join();
  const std::string warning = testing::internal::GetCapturedStderr();
  ASSERT_TRUE(killed_mid_launch) << "the launch ended before the worker could be killed";
  ASSERT_EQ(result, OPTIX_SUCCESS) << warning;
  EXPECT_TRUE(Same(image, reference)) << "the image differs from a fault-free run";
  EXPECT_NE(warning.find("was lost"), std::string::npos) << warning;
  EXPECT_NE(warning.find("killed by signal 9"), std::string::npos) << warning;

  // The next launch runs on a respawned third worker.
  EXPECT_TRUE(Same(app.Launch(7, kIterations), reference));
  EXPECT_EQ(ChildrenNamed(getpid(), kWorker).size(), 3u);
}

// A worker killed between launches costs the next launch nothing but time: that launch finds it
// gone while shipping its state and runs on the other two (as OptiX 3 launches do,
// docs/devices.md), and the launch after it has a new worker whose session receives the whole of
// device memory (here 2 MiB of noise that every launch index reads), where a launch that changed
// only its parameters ships what programs wrote on the other devices and the parameters.
TEST_F(Optix7FaultTest, WorkerKilledBetweenLaunchesIsReplacedWithTheWholeMemory) {
  constexpr unsigned kIterations = 200;
  const std::vector<uchar4> reference2 = Reference(2, kIterations);
  const std::vector<uchar4> reference3 = Reference(3, kIterations);
  ASSERT_FALSE(reference2.empty());
  ASSERT_FALSE(Same(reference2, reference3));
  setenv("TESSERA_DEVICES", "local:3", 1);
  App app;
  app.Create(noise_);
  ASSERT_FALSE(app.Launch(1, kIterations).empty());
  const unsigned long long first = app.BytesSent();
  EXPECT_GE(first, 3 * sizeof(unsigned) * kNoiseWords);  // each worker took the noise
  EXPECT_TRUE(Same(app.Launch(2, kIterations), reference2));
  const unsigned long long unchanged = app.BytesSent() - first;
  constexpr unsigned long long kNoiseBytes = sizeof(unsigned) * kNoiseWords;
  EXPECT_LT(unchanged, kNoiseBytes / 8) << "a launch that changed its parameters only";

  std::vector<pid_t> workers = ChildrenNamed(getpid(), kWorker);
  ASSERT_EQ(workers.size(), 3u);
  ASSERT_EQ(kill(workers.front(), SIGKILL), 0);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (ChildrenNamed(getpid(), kWorker).size() == 3u &&
         std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  ASSERT_EQ(ChildrenNamed(getpid(), kWorker).size(), 2u);

  testing::internal::CaptureStderr();
  OptixResult result = OPTIX_ERROR_UNKNOWN;
  const std::vector<uchar4> image = app.Launch(3, kIterations, &result);
  const std::string warning = testing::internal::GetCapturedStderr();
  ASSERT_EQ(result, OPTIX_SUCCESS) << warning;
  EXPECT_TRUE(Same(image, reference3));
  EXPECT_NE(warning.find("was lost"), std::string::npos) << warning;

  const unsigned long long before = app.BytesSent();
  EXPECT_TRUE(Same(app.Launch(2, kIterations), reference2));
  EXPECT_EQ(ChildrenNamed(getpid(), kWorker).size(), 3u);
  EXPECT_GE(app.BytesSent() - before, kNoiseBytes) << "the new worker's session";
  // And the launch after that is back to shipping a few bytes.
  const unsigned long long replaced = app.BytesSent();
  EXPECT_TRUE(Same(app.Launch(3, kIterations), reference3));
  EXPECT_LT(app.BytesSent() - replaced, kNoiseBytes / 8);
}

}  // namespace
}  // namespace tessera::e2e

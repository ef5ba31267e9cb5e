// tessera-optix7-atomics: CUDA atomics in OptiX 7 programs, on whatever devices TESSERA_DEVICES
// names (tests/optix7_atomics runs it on inproc, local:1, local:3 and inproc,local:2).
//
//   count       every launch index of a 512x128 launch adds, subtracts, takes minima and maxima,
//               ands, ors, xors and wraps counters (counters.h) on device memory; two launches,
//               the second starting from the first's results. Every counter must equal what one
//               thread doing the same operations in order reaches: what one GPU would.
//   semantics   one launch index: every atomic function's return value and stored value, against
//               CUDA's documented results (kSemantics).
//   append      a counter whose old values are slots: the count is exact; slots are unique
//               within a device only (docs/device_memory.md, "Atomics across devices").
//   --bench N   N atomicAdds per index of a 1000x1000 launch, on 1 or 4096 counters; prints each
//               launch's time (TESSERA_LAUNCH_TIMING=1 shows the device's own time).
#include <cuda_runtime.h>
#include <optix.h>
#include <optix_function_table_definition.h>
#include <optix_stubs.h>

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

// The host's reference: the same atomic functions as programs get, on one thread, noting nothing.
#include "tessera/detail/cuda_atomics.h"
// clang-format off: after the functions it calls
#include "params.h"
// clang-format on

#define CHECK_CUDA(call)                                                                          \
  do {                                                                                            \
    const cudaError_t e_ = (call);                                                                \
    if (e_ != cudaSuccess) {                                                                      \
      std::fprintf(stderr, "%s:%d: %s: %s\n", __FILE__, __LINE__, #call, cudaGetErrorString(e_)); \
      std::exit(1);                                                                               \
    }                                                                                             \
  } while (0)
#define CHECK_OPTIX(call)                                                                        \
  do {                                                                                           \
    const OptixResult r_ = (call);                                                               \
    if (r_ != OPTIX_SUCCESS) {                                                                   \
      std::fprintf(stderr, "%s:%d: %s: %s\n", __FILE__, __LINE__, #call, optixGetErrorName(r_)); \
      std::exit(1);                                                                              \
    }                                                                                            \
  } while (0)

namespace {

constexpr unsigned kWidth = 512;
constexpr unsigned kHeight = 128;

// CUDA's documented results of __raygen__semantics's checks, by check number.
struct Expected {
  unsigned long long check;
  unsigned long long value;
};
constexpr unsigned long long M(long long v) { return static_cast<unsigned long long>(v); }
// clang-format off
constexpr Expected kSemantics[] = {
  {1, 10}, {2, 15}, {3, 0xFFFFFFFFu}, {4, 1}, {5, 1ull << 40}, {6, (1ull << 40) + (1ull << 33)},
  {7, 0x40200000u /* 2.5f */}, {8, 0x40400000u /* 3.0f */}, {9, 1}, {10, 1},
  {11, 3}, {12, M(-2)}, {13, 1}, {14, 0xFFFFFFFFu},
  {15, 4}, {16, M(-9)}, {17, 6}, {18, 8}, {19, 1ull << 50}, {20, 3},
  {21, 0x3FA00000u /* 1.25f */}, {22, 0xC0800000u /* -4.0f */},
  {23, M(-3)}, {24, M(-7)}, {25, M(-7)}, {26, M(-3)}, {27, 2},
  {28, 5}, {29, 0x80000000u}, {30, 0x80000000u}, {31, 7},
  {32, M(-1)}, {33, M(-(1ll << 50))}, {34, M(-(1ll << 50))}, {35, 1ull << 45},
  {36, 1ull << 63}, {37, 5}, {38, 1ull << 62},
  {39, 9}, {40, 0}, {41, 0}, {42, 1}, {43, 20}, {44, 0},
  {45, 0}, {46, 6}, {47, 3}, {48, 2}, {49, 20}, {50, 6},
  {51, 5}, {52, 5}, {53, 5}, {54, 9}, {55, 1}, {56, 2}, {57, 1ull << 40}, {58, 7},
  {59, 7}, {60, 300}, {61, 300}, {62, 300},
  {63, 0xF0F0}, {64, 0xF000}, {65, 0xF000}, {66, 0xF00F}, {67, 0xF00F}, {68, 0x0FF0},
  {69, M(-1)}, {70, 0x70}, {71, 0x70}, {72, M(-144)}, {73, M(-144)}, {74, 143},
  {75, 0xFFFF000000000000ull}, {76, 0x0FF0000000000000ull}, {77, 0x0FF0000000000001ull}, {78, 0},
  {79, 3}, {80, 5}, {81, 8}, {82, 1}, {83, 4}, {84, 6}, {85, 0},
};
// clang-format on

struct Program {
  OptixProgramGroup group = nullptr;
  OptixPipeline pipeline = nullptr;
  OptixShaderBindingTable sbt = {};
};

class Harness {
 public:
  Harness() {
    CHECK_CUDA(cudaFree(nullptr));
    CHECK_OPTIX(optixInit());
    OptixDeviceContextOptions context_options = {};
    CHECK_OPTIX(optixDeviceContextCreate(nullptr, &context_options, &context_));
    pipeline_options_.pipelineLaunchParamsVariableName = "params";
    const std::string input = TESSERA_ATOMICS_MODULE;  // a module's path
    char log[2048];
    size_t log_size = sizeof(log);
    OptixModuleCompileOptions module_options = {};
    CHECK_OPTIX(optixModuleCreate(context_, &module_options, &pipeline_options_, input.c_str(),
                                  input.size(), log, &log_size, &module_));
    CHECK_CUDA(cudaMalloc(&d_params_, sizeof(Params)));
  }

  Program Make(const char* entry) {
    Program p;
    OptixProgramGroupDesc desc = {};
    desc.kind = OPTIX_PROGRAM_GROUP_KIND_RAYGEN;
    desc.raygen.module = module_;
    desc.raygen.entryFunctionName = entry;
    OptixProgramGroupOptions group_options = {};
    char log[2048];
    size_t log_size = sizeof(log);
    CHECK_OPTIX(
        optixProgramGroupCreate(context_, &desc, 1, &group_options, log, &log_size, &p.group));
    OptixPipelineLinkOptions link_options = {};
    link_options.maxTraceDepth = 1;
    log_size = sizeof(log);
    CHECK_OPTIX(optixPipelineCreate(context_, &pipeline_options_, &link_options, &p.group, 1, log,
                                    &log_size, &p.pipeline));
    struct alignas(OPTIX_SBT_RECORD_ALIGNMENT) Record {
      char header[OPTIX_SBT_RECORD_HEADER_SIZE];
    } record;
    CHECK_OPTIX(optixSbtRecordPackHeader(p.group, &record));
    void* d_record = nullptr;
    CHECK_CUDA(cudaMalloc(&d_record, sizeof record));
    CHECK_CUDA(cudaMemcpy(d_record, &record, sizeof record, cudaMemcpyHostToDevice));
    p.sbt.raygenRecord = reinterpret_cast<CUdeviceptr>(d_record);
    return p;
  }

  void Launch(const Program& p, const Params& params, unsigned w, unsigned h) {
    CHECK_CUDA(cudaMemcpy(d_params_, &params, sizeof params, cudaMemcpyHostToDevice));
    CHECK_OPTIX(optixLaunch(p.pipeline, nullptr, reinterpret_cast<CUdeviceptr>(d_params_),
                            sizeof params, &p.sbt, w, h, 1));
    CHECK_CUDA(cudaDeviceSynchronize());
  }

 private:
  OptixDeviceContext context_ = nullptr;
  OptixPipelineCompileOptions pipeline_options_ = {};
  OptixModule module_ = nullptr;
  void* d_params_ = nullptr;
};

template <typename T>
T* DeviceCopy(const T* host, size_t count) {
  T* d = nullptr;
  CHECK_CUDA(cudaMalloc(reinterpret_cast<void**>(&d), count * sizeof(T)));
  CHECK_CUDA(cudaMemcpy(d, host, count * sizeof(T), cudaMemcpyHostToDevice));
  return d;
}

template <typename T>
T HostCopy(const T* device) {
  T t;
  CHECK_CUDA(cudaMemcpy(&t, device, sizeof t, cudaMemcpyDeviceToHost));
  return t;
}

int failures = 0;

void Require(bool ok, const char* what, unsigned long long got, unsigned long long want) {
  if (ok) return;
  ++failures;
  std::fprintf(stderr, "%s: got %llu (0x%llx), one GPU would have %llu (0x%llx)\n", what, got, got,
               want, want);
}

void CompareCounters(const Counters& got, const Counters& want, const char* label) {
  char name[64];
  for (unsigned b = 0; b < kBins; ++b) {
    std::snprintf(name, sizeof name, "%shistogram[%u]", label, b);
    Require(got.histogram[b] == want.histogram[b], name, got.histogram[b], want.histogram[b]);
  }
  for (unsigned b = 0; b < 4; ++b) {
    std::snprintf(name, sizeof name, "%sor_bits[%u]", label, b);
    Require(got.or_bits[b] == want.or_bits[b], name, got.or_bits[b], want.or_bits[b]);
  }
  std::string prefix = label;
  auto field = [&](const char* f, const void* g, const void* w, size_t size) {
    unsigned long long gv = 0, wv = 0;
    std::memcpy(&gv, g, size);
    std::memcpy(&wv, w, size);
    Require(std::memcmp(g, w, size) == 0, (prefix + f).c_str(), gv, wv);
  };
#define FIELD(f) field(#f, &got.f, &want.f, sizeof got.f)
  FIELD(count);
  FIELD(signed_sum);
  FIELD(down);
  FIELD(down_signed);
  FIELD(wide_sum);
  FIELD(float_sum);
  FIELD(double_sum);
  FIELD(min_s);
  FIELD(max_s);
  FIELD(min_u);
  FIELD(max_u);
  FIELD(min_ll);
  FIELD(max_ll);
  FIELD(min_ull);
  FIELD(max_ull);
  FIELD(and_bits);
  FIELD(xor_bits);
  FIELD(xor_signed);
  FIELD(or_wide);
  FIELD(and_wide);
  FIELD(xor_wide);
  FIELD(ring);
  FIELD(ring_down);
  FIELD(scoped);
#undef FIELD
}

void TestCount(Harness& h) {
  const Program count = h.Make("__raygen__count");
  Counters want = InitialCounters();
  Params params = {};
  params.counters = DeviceCopy(&want, 1);
  for (int launch = 1; launch <= 2; ++launch) {
    h.Launch(count, params, kWidth, kHeight);
    for (unsigned i = 0; i < kWidth * kHeight; ++i) CountIndex(&want, i);
    const Counters got = HostCopy(params.counters);
    CompareCounters(got, want, launch == 1 ? "launch 1: " : "launch 2: ");
  }
  const Counters got = HostCopy(params.counters);
  std::printf("count: %u launch indices twice: count %u, float sum %g, ring %u\n", kWidth * kHeight,
              got.count, static_cast<double>(got.float_sum), got.ring);
}

void TestSemantics(Harness& h) {
  const Program semantics = h.Make("__raygen__semantics");
  std::vector<Seen> none(kMaxSeen, Seen{0, 0});
  const unsigned zero = 0;
  Params params = {};
  params.seen = DeviceCopy(none.data(), none.size());
  params.seen_count = DeviceCopy(&zero, 1);
  h.Launch(semantics, params, 1, 1);
  std::vector<Seen> seen(kMaxSeen);
  CHECK_CUDA(
      cudaMemcpy(seen.data(), params.seen, seen.size() * sizeof(Seen), cudaMemcpyDeviceToHost));
  const unsigned n = HostCopy(params.seen_count);
  const unsigned checks = sizeof kSemantics / sizeof kSemantics[0];
  Require(n == checks, "semantics: checks seen", n, checks);
  for (unsigned k = 0; k < checks && k < n; ++k) {
    char name[64];
    std::snprintf(name, sizeof name, "semantics check %llu", kSemantics[k].check);
    Require(seen[k].check == kSemantics[k].check, "semantics: check order", seen[k].check,
            kSemantics[k].check);
    Require(seen[k].value == kSemantics[k].value, name, seen[k].value, kSemantics[k].value);
  }
  std::printf("semantics: %u checks\n", n);
}

void TestAppend(Harness& h) {
  const Program append = h.Make("__raygen__append");
  const unsigned start = 5;
  const unsigned slots = kWidth * kHeight * 2;
  std::vector<unsigned> empty(slots, 0);
  Params params = {};
  params.append = DeviceCopy(&start, 1);
  params.slots = DeviceCopy(empty.data(), empty.size());
  params.slot_count = slots;
  h.Launch(append, params, kWidth, kHeight);
  const unsigned got = HostCopy(params.append);
  Require(got == start + kWidth * kHeight, "append: count", got, start + kWidth * kHeight);
  std::vector<unsigned> filled(slots);
  CHECK_CUDA(
      cudaMemcpy(filled.data(), params.slots, slots * sizeof(unsigned), cudaMemcpyDeviceToHost));
  unsigned used = 0;
  for (unsigned s : filled) used += s != 0;
  // One device fills every slot from `start` on; several devices fill the same slots, each its
  // own (the last writer's value stays), so fewer.
  std::printf("append: count %u, %u of %u slots filled (%s)\n", got, used, kWidth * kHeight,
              used == kWidth * kHeight ? "unique: one device" : "slots collided across devices");
}

void Bench(Harness& h, unsigned adds) {
  const Program bench = h.Make("__raygen__bench");
  for (unsigned bins : {1u, 4096u}) {
    std::vector<unsigned> zeros(bins, 0);
    Params params = {};
    params.bench = DeviceCopy(zeros.data(), zeros.size());
    params.bench_bins = bins;
    params.bench_adds = adds;
    for (int run = 0; run < 3; ++run) {
      const auto t0 = std::chrono::steady_clock::now();
      h.Launch(bench, params, 1000, 1000);
      const double ms =
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
      std::printf("bench: %u bins, %u atomicAdds: launch %.1f ms (%.2f ns per atomicAdd)\n", bins,
                  1000000 * adds, ms, ms * 1e6 / (1e6 * adds));
    }
    std::vector<unsigned> got(bins);
    CHECK_CUDA(
        cudaMemcpy(got.data(), params.bench, bins * sizeof(unsigned), cudaMemcpyDeviceToHost));
    unsigned long long total = 0;
    for (unsigned g : got) total += g;
    Require(total == 3ull * 1000000 * adds, "bench: total", total, 3ull * 1000000 * adds);
  }
}

}  // namespace

int main(int argc, char** argv) {
  Harness h;
  if (argc == 3 && std::strcmp(argv[1], "--bench") == 0) {
    Bench(h, static_cast<unsigned>(std::atoi(argv[2])));
  } else {
    TestCount(h);
    TestSemantics(h);
    TestAppend(h);
  }
  if (failures != 0) std::fprintf(stderr, "%d failures\n", failures);
  return failures == 0 ? 0 : 1;
}

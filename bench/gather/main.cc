// tessera-bench-gather: how fast a launch's output comes back from worker processes, against
// memcpy of the same bytes on the same machine. A ray generation program that traces nothing
// fills a float4 OUTPUT buffer (4096x4096 = 256 MiB by default); the wire rate is the bytes the
// host received (tesseraContextGetTransferStats) over the launch's wall time, median of
// --repeats. The last line is gather_vs_memcpy=<wire GiB/s / memcpy GiB/s> for the first
// --devices entry (local:1). --check runs 256x256 and exits 1 when the bytes or values that came
// back are wrong.
//
// What the ratio includes: everything between rtContextLaunch2D and its return, namely the
// dispatch of tiles, the program writing the worker's replica (trivial here), the worker
// serializing each tile's written region into a protobuf message, gRPC over a Unix socket
// (kernel copies on both sides), the host parsing the messages and applying each region to its
// copy of the buffer, plus the launch's fixed cost (the write_nothing line shows it). memcpy is a
// single thread copying into a destination whose pages are already resident, so the ratio says
// how many plain copies' worth of time the whole path costs.
#include <tessera/rt.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <memory>
#include <string>
#include <vector>

#include "common/rt_util.h"
#include "tessera/cli_checks.h"

namespace tessera::bench {
namespace {

constexpr double kGiB = 1024.0 * 1024.0 * 1024.0;

struct Options {
  unsigned width = 4096, height = 4096;
  std::vector<std::string> devices = {"local:1", "local:2"};
  int repeats = 5;
  std::string module = TESSERA_BENCH_MODULE_DIR "/bench_gather.so";
  bool check = false;
};

struct GatherResult {
  double seconds = 0;        // median launch of write_output
  double empty_seconds = 0;  // median launch of write_nothing
  uint64_t bytes = 0;        // received per write_output launch
};

class GatherContext {
 public:
  GatherContext(const Options& o, const std::string& devices) : width_(o.width), height_(o.height) {
    Check(nullptr, rtContextCreate(&context_), "rtContextCreate");
    try {
      Build(o, devices);
    } catch (...) {
      rtContextDestroy(context_);
      throw;
    }
  }
  ~GatherContext() { rtContextDestroy(context_); }
  GatherContext(const GatherContext&) = delete;
  GatherContext& operator=(const GatherContext&) = delete;

  // Launches `entry` (0: write_output, 1: write_nothing); returns its wall time and the bytes
  // gathered.
  double Launch(unsigned entry, uint64_t* received) {
    const TransferStats before = GetTransferStats(context_);
    const double start = NowSeconds();
    Check(context_, rtContextLaunch2D(context_, entry, width_, height_), "rtContextLaunch2D");
    const double seconds = NowSeconds() - start;
    *received = (GetTransferStats(context_) - before).received;
    return seconds;
  }

  // Elements whose value is not what write_output writes.
  size_t WrongElements() {
    void* mapped = nullptr;
    Check(context_, rtBufferMap(output_, &mapped), "rtBufferMap(output)");
    const float* f = static_cast<const float*>(mapped);
    size_t wrong = 0;
    for (unsigned y = 0; y < height_; ++y) {
      for (unsigned x = 0; x < width_; ++x, f += 4) {
        wrong += f[0] != static_cast<float>(x) || f[1] != static_cast<float>(y) || f[2] != 0.5f ||
                 f[3] != 1.f;
      }
    }
    Check(context_, rtBufferUnmap(output_), "rtBufferUnmap(output)");
    return wrong;
  }

 private:
  void Build(const Options& o, const std::string& devices) {
    RTcontext c = context_;
    UseDevices(c, devices);
    Check(c, rtContextSetRayTypeCount(c, 1), "rtContextSetRayTypeCount");
    Check(c, rtContextSetEntryPointCount(c, 2), "rtContextSetEntryPointCount");
    const char* programs[] = {"write_output", "write_nothing"};
    for (unsigned entry = 0; entry < 2; ++entry) {
      RTprogram program = nullptr;
      Check(c, rtProgramCreateFromPTXFile(c, o.module.c_str(), programs[entry], &program),
            std::string("rtProgramCreateFromPTXFile(") + o.module + ", " + programs[entry] + ")");
      Check(c, rtContextSetRayGenerationProgram(c, entry, program),
            "rtContextSetRayGenerationProgram");
    }
    Check(c, rtBufferCreate(c, RT_BUFFER_OUTPUT, &output_), "rtBufferCreate(output)");
    Check(c, rtBufferSetFormat(output_, RT_FORMAT_FLOAT4), "rtBufferSetFormat(output)");
    Check(c, rtBufferSetSize2D(output_, width_, height_), "rtBufferSetSize2D(output)");
    RTvariable v = nullptr;
    Check(c, rtContextDeclareVariable(c, "output_buffer", &v), "rtContextDeclareVariable");
    Check(c, rtVariableSetObject(v, output_), "rtVariableSetObject(output_buffer)");
    Check(c, rtContextValidate(c), "rtContextValidate");
    Check(c, rtContextCompile(c), "rtContextCompile");
  }

  RTcontext context_ = nullptr;
  RTbuffer output_ = nullptr;
  unsigned width_, height_;
};

GatherResult MeasureGather(const Options& o, const std::string& devices, bool* ok) {
  GatherContext context(o, devices);
  const uint64_t expected = uint64_t{o.width} * o.height * 4 * sizeof(float);
  uint64_t received = 0;
  // Warm-up: spawns the workers, ships the state, sizes the replicas and the host buffer.
  context.Launch(0, &received);
  context.Launch(1, &received);
  std::vector<double> full, empty;
  for (int i = 0; i < o.repeats; ++i) {
    full.push_back(context.Launch(0, &received));
    if (received != expected) {
      std::printf("FAILED: %s: a launch gathered %llu bytes, not %llu\n", devices.c_str(),
                  static_cast<unsigned long long>(received),
                  static_cast<unsigned long long>(expected));
      *ok = false;
    }
    empty.push_back(context.Launch(1, &received));
    if (received != 0) {
      std::printf("FAILED: %s: a launch that writes nothing gathered %llu bytes\n", devices.c_str(),
                  static_cast<unsigned long long>(received));
      *ok = false;
    }
  }
  if (size_t wrong = context.WrongElements(); wrong != 0) {
    std::printf("FAILED: %s: %zu elements hold other values than the program wrote\n",
                devices.c_str(), wrong);
    *ok = false;
  }
  return GatherResult{Median(full), Median(empty), expected};
}

// memcpy of `bytes`: median seconds into a destination that was touched beforehand (pages
// resident, the pure copy), and into a freshly allocated one (page faults included).
void MeasureMemcpy(size_t bytes, int repeats, double* resident, double* first_touch) {
  std::vector<char> source(bytes);
  for (size_t i = 0; i < bytes; ++i) source[i] = static_cast<char>(i * 131);
  std::vector<double> warm, cold;
  std::unique_ptr<char[]> destination(new char[bytes]);
  std::memset(destination.get(), 1, bytes);
  for (int i = 0; i < repeats; ++i) {
    double start = NowSeconds();
    std::memcpy(destination.get(), source.data(), bytes);
    warm.push_back(NowSeconds() - start);
    // malloc of this size maps new pages; the copy faults them in.
    std::unique_ptr<char[]> fresh(new char[bytes]);
    start = NowSeconds();
    std::memcpy(fresh.get(), source.data(), bytes);
    cold.push_back(NowSeconds() - start);
    if (std::memcmp(fresh.get() + bytes / 2, destination.get() + bytes / 2, 64) != 0) {
      throw BenchError("memcpy copied something else");  // also keeps the copies observable
    }
  }
  *resident = Median(warm);
  *first_touch = Median(cold);
}

int Run(const Options& o) {
  const size_t bytes = size_t{o.width} * o.height * 4 * sizeof(float);
  std::printf(
      "float4 OUTPUT buffer %ux%u = %.1f MiB, median of %d launches after a warm-up, "
      "load average before: %.2f\n",
      o.width, o.height, bytes / 1048576.0, o.repeats, LoadAverage());
  double memcpy_seconds = 0, first_touch_seconds = 0;
  MeasureMemcpy(bytes, o.repeats, &memcpy_seconds, &first_touch_seconds);
  const double memcpy_rate = bytes / memcpy_seconds / kGiB;
  std::printf("%-36s %8.4f s %8.2f GiB/s\n", "memcpy, resident destination:", memcpy_seconds,
              memcpy_rate);
  std::printf("%-36s %8.4f s %8.2f GiB/s\n",
              "memcpy, freshly mapped destination:", first_touch_seconds,
              bytes / first_touch_seconds / kGiB);

  bool ok = true;
  double headline = 0;
  std::printf("%-10s %10s %10s %12s %10s %16s\n", "devices", "launch s", "empty s", "wire GiB/s",
              "vs memcpy", "GiB/s w/o empty");
  for (const std::string& devices : o.devices) {
    const GatherResult r = MeasureGather(o, devices, &ok);
    const double rate = r.bytes / r.seconds / kGiB;
    const double marginal =
        r.seconds > r.empty_seconds ? r.bytes / (r.seconds - r.empty_seconds) / kGiB : 0.0;
    std::printf("%-10s %10.4f %10.4f %12.3f %10.3f %16.3f\n", devices.c_str(), r.seconds,
                r.empty_seconds, rate, rate / memcpy_rate, marginal);
    if (&devices == &o.devices.front()) headline = rate / memcpy_rate;
  }
  std::printf(
      "wire GiB/s: bytes gathered / launch wall time; empty: the same launch running "
      "write_nothing (the fixed cost); vs memcpy: against the resident destination\n");
  if (!(headline > 0)) {
    std::printf("FAILED: no gather rate\n");
    ok = false;
  }
  std::printf("gather_vs_memcpy=%.3f\n", headline);
  return ok ? 0 : 1;
}

}  // namespace
}  // namespace tessera::bench

int main(int argc, char** argv) {
  using namespace tessera::bench;
  Options o;
  CLI::App app{"Output bytes per second from worker processes vs memcpy"};
  app.add_option("--width", o.width, "buffer width (float4 elements)")
      ->capture_default_str()
      ->check(tessera::cli::kPositive);
  app.add_option("--height", o.height, "buffer height")
      ->capture_default_str()
      ->check(tessera::cli::kPositive);
  app.add_option("--devices", o.devices, "device specs to measure; the first gives the headline")
      ->capture_default_str();
  app.add_option("--repeats", o.repeats, "timed launches (median)")
      ->capture_default_str()
      ->check(tessera::cli::kPositive);
  app.add_option("--module", o.module, "program module built from gather.cu")
      ->capture_default_str();
  app.add_flag("--check", o.check,
               "256x256, two launches each; exit 1 unless the gathered bytes and values are right");
  CLI11_PARSE(app, argc, argv);
  if (o.check) {
    o.width = o.height = 256;
    o.repeats = 2;
  }
  try {
    return Run(o);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "tessera-bench-gather: %s\n", e.what());
    return 1;
  }
}

// Runs Embree's own `viewer` (Debian package embree-tools) in benchmark mode and reads its Mrays/s:
// the yardstick on one machine (tessera-bench-eyelight compares rays, tessera-bench-scaling
// compares how both scale over the cores).
#ifndef TESSERA_BENCH_COMMON_EMBREE_VIEWER_H_
#define TESSERA_BENCH_COMMON_EMBREE_VIEWER_H_

#include <optional>
#include <string>
#include <vector>

namespace tessera::bench {

struct ViewerRun {
  std::string viewer;  // a path, or a name looked up in PATH
  std::string model;
  unsigned width = 0, height = 0;
  int warmup = 5, runs = 20;
  std::vector<std::string> camera_flags;  // e.g. Camera::ViewerFlags() of the eyelight bench
  int threads = 0;                        // --threads N; 0: viewer's default (every core)
};

// The executable `name` resolves to (itself if it holds a '/'), or nullopt if there is none.
std::optional<std::string> FindExecutable(const std::string& name);

// The number on the line `BENCHMARK_RENDER_MRAYPS_AVG <x>` of viewer's output, if any.
std::optional<double> ParseMraysAverage(const std::string& output);

// The number on the line `<key> <x>` of an Embree tutorial's benchmark output, if any.
std::optional<double> ParseBenchmarkValue(const std::string& output, const std::string& key);

// Runs a shell command line, returning what it wrote to stdout and stderr; throws
// std::runtime_error with that output when it does not exit 0. `what` names it in the message.
std::string RunCommand(const std::string& command, const std::string& what);

// `s` quoted for a POSIX shell.
std::string ShellQuote(const std::string& s);

// Runs `viewer -i MODEL --size W H --shader eyelight --benchmark WARMUP RUNS [--threads N]
// <camera flags>` and returns BENCHMARK_RENDER_MRAYPS_AVG. Throws std::runtime_error (with viewer's
// output) when it fails or prints no such line. `command_out` receives the command line as run.
double RunEmbreeViewer(const ViewerRun& run, std::string* command_out);

}  // namespace tessera::bench

#endif  // TESSERA_BENCH_COMMON_EMBREE_VIEWER_H_

// tessera-bench-render: the render command against its yardsticks, as a user runs them.
//
//   --mode pathtrace: `tessera render` and Embree's `pathtracer --benchmark` on the same scene
//     (Embree's Cornell box and its own point light and camera), size, samples per pixel and path
//     depth, alternating in each round. Embree's figure is its benchmark frames per second (one
//     sample per pixel per frame, after its warm-up frames); Tessera's is the samples of its
//     passes after the first (the warm-up: workers, shipping, builds) over their time, read from
//     `--log-level debug`. The headline is pathtrace_ratio_vs_embree=<Tessera / Embree samples per
//     second> on every core (one in-process device, like the pathtracer's one process), then the
//     same with one thread and with the default devices (local worker processes).
//   --mode sequence: a 30-frame sequence of the animated built-in scene rendered on local:N
//     (N = cores) and by one process with one thread; frames per minute of the whole command and
//     sequence_parallel_efficiency=<speedup / N>. Every frame's image must be the same bits
//     whatever the devices (FAILED otherwise).
//   --check: the sequence mode on 3 tiny frames and local:2, for ctest: exits 1 when a frame's bits
//     differ between the device sets (correctness only; no timing is judged).
#include <sys/stat.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "common/embree_viewer.h"

namespace tessera::bench {
namespace {

struct Options {
  std::string mode = "all";
  std::string tessera = TESSERA_BENCH_TESSERA_CLI;
  std::string pathtracer = "pathtracer";
  std::string model = TESSERA_BENCH_DEFAULT_MODEL;
  int size = 512;
  int spp = 32;
  int depth = 8;
  int rounds = 3;
  int frames = 30;
  int sequence_spp = 16;
  int sequence_width = 320, sequence_height = 180;
  int cores = 0;  // 0: the machine's
  std::string work_dir = "/tmp/tessera-bench-render";
  bool check = false;
};

// Embree's Cornell box as its cornell_box.ecs sets it up: camera and one point light.
constexpr const char* kEmbreeView = "--vp 278 273 -800 --vi 278 273 0 --vu 0 1 0 --fov 37";
constexpr const char* kEmbreeLight = "--pointlight 213 300 227 100000 100000 100000";
constexpr const char* kTesseraView =
    "--look-from 278,273,-800 --look-at 278,273,0 --fov 37 "
    "--point-light 213,300,227,100000,100000,100000";

double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n == 0 ? 0.0 : (n % 2 == 1 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]));
}

double Seconds(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

std::string ReadFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// Samples per second of Embree's pathtracer: its benchmark frames per second (one sample per
// pixel each) times the pixels.
double EmbreeSamplesPerSecond(const Options& o, const std::string& pathtracer, int threads) {
  std::string cmd = ShellQuote(pathtracer) + " -i " + ShellQuote(o.model) + " " + kEmbreeView +
                    " " + kEmbreeLight + " --size " + std::to_string(o.size) + " " +
                    std::to_string(o.size) + " --spp 1 --max-path-length " +
                    std::to_string(o.depth) + " --benchmark 2 " + std::to_string(o.spp);
  if (threads > 0) cmd += " --threads " + std::to_string(threads);
  const std::string output = RunCommand(cmd, "Embree's pathtracer");
  const std::optional<double> fps = ParseBenchmarkValue(output, "BENCHMARK_RENDER_AVG");
  if (!fps) throw std::runtime_error("pathtracer printed no BENCHMARK_RENDER_AVG:\n" + output);
  return *fps * o.size * o.size;
}

// Samples per second of `tessera render` over its passes after the first, from its debug lines
// "pass done: N samples in T s, ...".
double TesseraSamplesPerSecond(const Options& o, const std::string& devices, int threads) {
  std::string cmd = ShellQuote(o.tessera) + " render " + ShellQuote(o.model) + " -o " +
                    ShellQuote(o.work_dir + "/pathtrace.png") + " --width " +
                    std::to_string(o.size) + " --height " + std::to_string(o.size) + " --spp " +
                    std::to_string(o.spp) + " --max-depth " + std::to_string(o.depth) + " " +
                    kTesseraView + " --devices " + devices + " --log-level debug";
  if (threads > 0) cmd += " --threads " + std::to_string(threads);
  const std::string output = RunCommand(cmd, "tessera render");
  std::stringstream lines(output);
  std::string line;
  int passes = 0;
  double samples = 0.0, seconds = 0.0;
  while (std::getline(lines, line)) {
    unsigned n = 0;
    double t = 0.0;
    const size_t at = line.find("pass done: ");
    if (at == std::string::npos) continue;
    if (std::sscanf(line.c_str() + at, "pass done: %u samples in %lf s", &n, &t) != 2) continue;
    if (passes++ == 0) continue;  // the warm-up pass
    samples += n;
    seconds += t;
  }
  if (seconds <= 0.0) {
    throw std::runtime_error("tessera render gave fewer than two timed passes (raise --spp):\n" +
                             output);
  }
  return samples * o.size * o.size / seconds;
}

int RunPathtrace(const Options& o, int cores) {
  const std::optional<std::string> pathtracer = FindExecutable(o.pathtracer);
  if (!pathtracer || access(o.model.c_str(), R_OK) != 0) {
    std::printf("pathtrace: skipped: %s not found (install embree-tools)\n",
                pathtracer ? o.model.c_str() : ("'" + o.pathtracer + "'").c_str());
    return 0;
  }
  std::printf(
      "pathtrace: %s, %dx%d, %d spp, depth %d, Embree's camera and point light; %d rounds\n",
      o.model.c_str(), o.size, o.size, o.spp, o.depth, o.rounds);
  struct Row {
    const char* name;
    const char* devices;
    int threads;  // 0: every core
    std::vector<double> embree, tessera;
  };
  const std::string local = "local:" + std::to_string(cores);
  std::vector<Row> rows = {{"all cores, inproc", "inproc", 0, {}, {}},
                           {"one thread, inproc", "inproc", 1, {}, {}},
                           {"default devices", local.c_str(), 0, {}, {}}};
  for (int round = 0; round < o.rounds; ++round) {
    for (Row& row : rows) {
      row.embree.push_back(EmbreeSamplesPerSecond(o, *pathtracer, row.threads));
      row.tessera.push_back(TesseraSamplesPerSecond(o, row.devices, row.threads));
      std::printf("  round %d %-20s Embree %8.3f Msamples/s, Tessera %8.3f, ratio %.3f\n", round,
                  row.name, row.embree.back() * 1e-6, row.tessera.back() * 1e-6,
                  row.tessera.back() / row.embree.back());
      std::fflush(stdout);
    }
  }
  const char* keys[] = {"pathtrace_ratio_vs_embree", "pathtrace_ratio_vs_embree_1thread",
                        "pathtrace_ratio_vs_embree_local"};
  for (size_t i = 0; i < rows.size(); ++i) {
    std::printf("%s=%.3f  (median Msamples/s: Tessera %.3f on %s, Embree %.3f)\n", keys[i],
                Median(rows[i].tessera) / Median(rows[i].embree), Median(rows[i].tessera) * 1e-6,
                rows[i].devices, Median(rows[i].embree) * 1e-6);
  }
  return 0;
}

// Renders the sequence into `dir`; returns the command's wall-clock seconds.
double RenderSequence(const Options& o, const std::string& devices, int threads,
                      const std::string& dir) {
  std::string cmd = "rm -rf " + ShellQuote(dir) + " && mkdir -p " + ShellQuote(dir) + " && ";
  cmd += ShellQuote(o.tessera) + " render builtin:cornell -o " + ShellQuote(dir + "/f.####.png") +
         " --frames 1-" + std::to_string(o.frames) + " --spp " + std::to_string(o.sequence_spp) +
         " --width " + std::to_string(o.sequence_width) + " --height " +
         std::to_string(o.sequence_height) + " --devices " + devices + " --log-level warn";
  if (threads > 0) cmd += " --threads " + std::to_string(threads);
  const auto start = std::chrono::steady_clock::now();
  RunCommand(cmd, "tessera render --frames");
  return Seconds(start);
}

// The frames of `dir` that differ from those of `baseline` (by bytes).
int DifferingFrames(const Options& o, const std::string& baseline, const std::string& dir) {
  int differing = 0;
  for (int f = 1; f <= o.frames; ++f) {
    char name[32];
    std::snprintf(name, sizeof(name), "/f.%04d.png", f);
    const std::string a = ReadFile(baseline + name), b = ReadFile(dir + name);
    if (a.empty() || a != b) ++differing;
  }
  return differing;
}

int RunSequence(const Options& o, int cores) {
  std::printf("sequence: builtin:cornell, %d frames, %dx%d, %d spp; %d rounds\n", o.frames,
              o.sequence_width, o.sequence_height, o.sequence_spp, o.rounds);
  const std::string local = "local:" + std::to_string(cores);
  const std::string one_dir = o.work_dir + "/one", local_dir = o.work_dir + "/local",
                    inproc_dir = o.work_dir + "/inproc";
  std::vector<double> one, many, inproc, local_efficiency, inproc_efficiency;
  int failures = 0;
  for (int round = 0; round < o.rounds; ++round) {
    one.push_back(RenderSequence(o, "inproc", 1, one_dir));
    many.push_back(RenderSequence(o, local, 0, local_dir));
    inproc.push_back(RenderSequence(o, "inproc", 0, inproc_dir));
    const int differing =
        DifferingFrames(o, one_dir, local_dir) + DifferingFrames(o, one_dir, inproc_dir);
    if (differing > 0) {
      std::printf("FAILED: %d frames differ from the one-thread render's bits\n", differing);
      ++failures;
    }
    local_efficiency.push_back(one.back() / many.back() / cores);
    inproc_efficiency.push_back(one.back() / inproc.back() / cores);
    std::printf(
        "  round %d: one thread %.2f s, %s %.2f s (efficiency %.3f), inproc on %d threads %.2f s "
        "(%.3f)\n",
        round, one.back(), local.c_str(), many.back(), local_efficiency.back(), cores,
        inproc.back(), inproc_efficiency.back());
    std::fflush(stdout);
  }
  const double per_minute = 60.0 * o.frames;
  std::printf("frames per minute: one thread %.1f, %s %.1f, inproc %d threads %.1f\n",
              per_minute / Median(one), local.c_str(), per_minute / Median(many), cores,
              per_minute / Median(inproc));
  // The median of each round's ratio: the runs of a round are adjacent, so they share its load.
  std::printf(
      "sequence_parallel_efficiency=%.3f  (%s against one process with one thread, median of "
      "the rounds)\n",
      Median(local_efficiency), local.c_str());
  std::printf("sequence_inproc_efficiency=%.3f  (one process, %d threads)\n",
              Median(inproc_efficiency), cores);
  return failures == 0 ? 0 : 1;
}

}  // namespace
}  // namespace tessera::bench

int main(int argc, char** argv) {
  using tessera::bench::Options;
  Options o;
  CLI::App app{"tessera render against Embree's pathtracer, and frames per minute over cores"};
  app.add_option("--mode", o.mode, "pathtrace, sequence or all")
      ->check(CLI::IsMember({"pathtrace", "sequence", "all"}))
      ->capture_default_str();
  app.add_option("--tessera", o.tessera, "the tessera executable")->capture_default_str();
  app.add_option("--pathtracer", o.pathtracer, "Embree's pathtracer")->capture_default_str();
  app.add_option("--model", o.model, "the OBJ both render")->capture_default_str();
  app.add_option("--size", o.size, "image width and height")->capture_default_str();
  app.add_option("--spp", o.spp, "samples per pixel (pathtrace)")->capture_default_str();
  app.add_option("--depth", o.depth, "path depth (pathtrace)")->capture_default_str();
  app.add_option("--rounds", o.rounds, "rounds, alternating the two")->capture_default_str();
  app.add_option("--frames", o.frames, "frames of the sequence")->capture_default_str();
  app.add_option("--sequence-spp", o.sequence_spp, "spp of each frame")->capture_default_str();
  app.add_option("--cores", o.cores, "N of local:N (default: the machine's cores)");
  app.add_option("--work-dir", o.work_dir, "where images go")->capture_default_str();
  app.add_flag("--check", o.check, "3 tiny frames on local:2 and one thread: same bits or exit 1");
  CLI11_PARSE(app, argc, argv);
  if (o.check) {
    o.mode = "sequence";
    o.frames = 3;
    o.rounds = 1;
    o.sequence_spp = 2;
    o.sequence_width = 32;
    o.sequence_height = 18;
    o.cores = 2;
    o.work_dir += "-check-" + std::to_string(getpid());
  }
  const int cores =
      o.cores > 0 ? o.cores : std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  mkdir(o.work_dir.c_str(), 0755);
  try {
    int status = 0;
    if (o.mode != "sequence") status |= tessera::bench::RunPathtrace(o, cores);
    if (o.mode != "pathtrace") status |= tessera::bench::RunSequence(o, cores);
    if (o.check) std::filesystem::remove_all(o.work_dir);
    return status;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "tessera-bench-render: %s\n", e.what());
    return 1;
  }
}

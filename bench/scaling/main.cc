// tessera-bench-scaling: the tutorial's last step rendered by local:1, local:2, local:4, … worker
// processes up to the core count, against one in-process device with one thread. Each
// configuration gets a warm-up launch (spawning workers, shipping the state, building the
// accelerations), then the median of --repeats timed launches. Every image must be bit-identical
// to the baseline's (tiles land on different devices, pixels must not care). The last line is
// parallel_efficiency=<speedup / N at N = cores>. --check renders a tiny image with N up to 2 and
// exits 1 when an image differs. When Embree's `viewer` is installed, each round of timed launches
// also times it on one thread and on every core: the same machine's yardstick, measured under the
// same load.
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <exception>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "common/embree_viewer.h"
#include "common/rt_util.h"
#include "common/tutorial_context.h"
#include "tessera/cli_checks.h"

namespace tessera::bench {
namespace {

struct Options {
  int width = 1920, height = 1080;
  int repeats = 3;
  int step = tutorial::kLastStep;  // the headline figure is for the last step
  int max_devices = 0;             // 0: the core count
  bool thread_sweep = false;       // inproc rows for 2, 4, 8 … threads too
  std::vector<std::string> only;   // --devices: just these specs after the baseline
  std::string module_dir;
  bool check = false;
  std::string viewer = "viewer";  // Embree's, for the reference rows; "none" skips them
  std::string viewer_model = TESSERA_BENCH_DEFAULT_MODEL;
  bool loaded_baseline = false;  // also time one thread while every other core spins
};

// Threads that keep every other core busy with arithmetic that touches no memory, while they
// live: what one thread of a fully loaded machine gets, without sharing anything with it.
class BusyCores {
 public:
  explicit BusyCores(int count) {
    for (int i = 0; i < count; ++i) {
      threads_.emplace_back([this] {
        // Eight independent chains of adds, shifts and xors keep a core's integer ports as busy
        // as a tracer keeps them (a single dependent chain barely warms the core, and slowed its
        // neighbours by 7% where a shell's busy loop slowed them by half).
        uint64_t x[8] = {1, 2, 3, 4, 5, 6, 7, 8};
        while (!stop_.load(std::memory_order_relaxed)) {
          for (int k = 0; k < 4096; ++k) {
#pragma GCC unroll 8
            for (int c = 0; c < 8; ++c) {
              x[c] = ((x[c] + 0x9e3779b97f4a7c15ull) ^ (x[c] >> 7)) + (x[c] << 3);
              asm volatile("" : "+r"(x[c]));
            }
          }
        }
      });
    }
    // Let the spinning threads reach their cores before anything is timed.
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  ~BusyCores() {
    stop_ = true;
    for (std::thread& t : threads_) t.join();
  }

 private:
  std::atomic<bool> stop_{false};
  std::vector<std::thread> threads_;
};

// Embree's viewer on one thread and on every core, timed once per round between Tessera's
// launches (eyelight primary rays, 1024x1024): how far this machine lets ray tracing scale now.
class EmbreeReference {
 public:
  EmbreeReference(const Options& o, int cores) : cores_(cores), loaded_(o.loaded_baseline) {
    if (o.check || o.viewer == "none") return;
    std::optional<std::string> viewer = FindExecutable(o.viewer);
    if (!viewer || access(o.viewer_model.c_str(), R_OK) != 0) {
      std::printf("no Embree reference: %s not found (install embree-tools)\n",
                  viewer ? o.viewer_model.c_str() : ("'" + o.viewer + "'").c_str());
      return;
    }
    run_.viewer = *viewer;
    run_.model = o.viewer_model;
    run_.width = run_.height = 1024;
    run_.warmup = 2;
    run_.runs = 10;
    enabled_ = true;
  }
  // One round: both thread counts once. A failing viewer ends the reference, not the benchmark.
  void Round() {
    if (!enabled_) return;
    try {
      run_.threads = 1;
      one_.push_back(RunEmbreeViewer(run_, nullptr));
      run_.threads = cores_;
      all_.push_back(RunEmbreeViewer(run_, nullptr));
      if (loaded_) {
        run_.threads = 1;
        BusyCores busy(cores_ - 1);
        one_loaded_.push_back(RunEmbreeViewer(run_, nullptr));
      }
    } catch (const std::exception& e) {
      std::printf("no Embree reference: %s\n", e.what());
      enabled_ = false;
      one_.clear();
      all_.clear();
      one_loaded_.clear();
    }
  }
  // The line with both medians and Embree's efficiency on every core, when measured.
  void Report(double tessera_efficiency) const {
    if (one_.empty() || all_.empty()) return;
    const double one = Median(one_), all = Median(all_);
    const double efficiency = all / one / cores_;
    std::printf(
        "Embree's viewer, same rounds (%s, 1024x1024, eyelight): 1 thread %.1f Mrays/s, %d threads "
        "%.1f Mrays/s, speedup %.2f, efficiency %.2f; Tessera's headline is %.2f of it\n",
        run_.model.c_str(), one, cores_, all, all / one, efficiency,
        tessera_efficiency / efficiency);
    if (!one_loaded_.empty()) {
      const double loaded = Median(one_loaded_);
      std::printf(
          "Embree's viewer on 1 thread with the other %d cores busy: %.1f Mrays/s (x%.2f the time "
          "of a lone thread); %d threads against it: efficiency %.2f\n",
          cores_ - 1, loaded, one / loaded, cores_, all / loaded / cores_);
    }
  }

 private:
  const int cores_;
  const bool loaded_;
  bool enabled_ = false;
  ViewerRun run_;
  std::vector<double> one_, all_, one_loaded_;
};

struct Config {
  std::string devices;
  int num_threads = 0;  // CPU_NUM_THREADS to set, 0 for the devices' default
  int threads = 0;      // threads tracing, summed over devices
  std::unique_ptr<TutorialContext> scene;
  double warmup_seconds = 0;
  std::vector<double> seconds;
  size_t differing_floats = 0;
};

Config MakeConfig(std::string devices, int num_threads, int threads) {
  Config c;
  c.devices = std::move(devices);
  c.num_threads = num_threads;
  c.threads = threads;
  return c;
}

// local:N worker counts: powers of two below `max`, then `max` itself.
std::vector<int> WorkerCounts(int max) {
  std::vector<int> counts;
  for (int n = 1; n < max; n *= 2) counts.push_back(n);
  counts.push_back(max);
  return counts;
}

double TimeLaunch(TutorialContext& scene) {
  const double start = NowSeconds();
  scene.Launch();
  return NowSeconds() - start;
}

// Floats whose bits differ: NaN pixels must match too, and -0 must stay -0.
size_t DifferingFloats(const std::vector<float>& a, const std::vector<float>& b) {
  size_t n = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    uint32_t x, y;
    std::memcpy(&x, &a[i], sizeof(x));
    std::memcpy(&y, &b[i], sizeof(y));
    n += x != y;
  }
  return n;
}

int Run(const Options& o) {
  const int cores = std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  const int max_devices = o.check ? 2 : (o.max_devices > 0 ? o.max_devices : cores);
  const double pixels = static_cast<double>(o.width) * o.height;
  std::printf(
      "tutorial step %d at %dx%d, %d cores, median of %d launches after one warm-up, "
      "load average before: %.2f\n",
      o.step, o.width, o.height, cores, o.repeats, LoadAverage());

  std::vector<Config> configs;
  configs.push_back(MakeConfig("inproc", 1, 1));
  // A reference, not part of the headline: threads without processes or the wire, which also
  // shows how much parallelism the machine gives right now (other load takes cores away).
  if (o.thread_sweep) {
    // How one process scales with threads alone, to tell the engine's limits from the wire's.
    for (int t = 2; t < cores; t *= 2) configs.push_back(MakeConfig("inproc", t, t));
  }
  if (!o.only.empty()) {
    // A look at chosen configurations (say local:16 with TESSERA_LAUNCH_TIMING=1).
    for (const std::string& spec : o.only) configs.push_back(MakeConfig(spec, 0, cores));
  } else {
    configs.push_back(MakeConfig("inproc", cores, cores));
    for (int n : WorkerCounts(max_devices)) {
      // Each local worker gets its share of the cores, at least one thread (worker_factory.cc).
      configs.push_back(MakeConfig("local:" + std::to_string(n), 0, n * std::max(1, cores / n)));
    }
  }

  for (Config& c : configs) {
    TutorialOptions scene_options;
    scene_options.devices = c.devices;
    scene_options.num_threads = c.num_threads;
    scene_options.step = o.step;
    scene_options.width = o.width;
    scene_options.height = o.height;
    scene_options.module_dir = o.module_dir;
    c.scene = std::make_unique<TutorialContext>(scene_options);
    c.warmup_seconds = TimeLaunch(*c.scene);
  }
  // Rounds of one launch per configuration rather than one configuration after another: on a
  // machine shared with other work, a change of load then skews every configuration alike.
  // Idle workers of the other contexts wait in gRPC and take no CPU.
  EmbreeReference embree(o, cores);
  std::vector<double> loaded_seconds;  // --loaded-baseline: the baseline, every other core busy
  for (int round = 0; round < o.repeats; ++round) {
    for (Config& c : configs) c.seconds.push_back(TimeLaunch(*c.scene));
    if (o.loaded_baseline) {
      BusyCores busy(cores - 1);
      loaded_seconds.push_back(TimeLaunch(*configs.front().scene));
    }
    embree.Round();
  }
  const std::vector<float> baseline_image = configs.front().scene->ReadOutput();
  for (Config& c : configs) {
    c.differing_floats = DifferingFloats(baseline_image, c.scene->ReadOutput());
    c.scene.reset();  // stops its workers
  }

  const double base = Median(configs.front().seconds);
  std::printf("%-10s %7s %10s %10s %10s %8s %10s  %s\n", "devices", "threads", "warm-up s",
              "median s", "Mpixels/s", "speedup", "efficiency", "image");
  bool identical = true;
  double efficiency_at_cores = 0;
  for (const Config& c : configs) {
    const double seconds = Median(c.seconds);
    const double speedup = base / seconds;
    // Per thread tracing: at N = cores this is speedup / N.
    const double efficiency = speedup / c.threads;
    if (c.devices == "local:" + std::to_string(max_devices)) efficiency_at_cores = efficiency;
    identical = identical && c.differing_floats == 0;
    std::printf("%-10s %7d %10.3f %10.3f %10.3f %8.2f %10.2f  %s\n", c.devices.c_str(), c.threads,
                c.warmup_seconds, seconds, pixels / seconds / 1e6, speedup, efficiency,
                &c == &configs.front()    ? "baseline"
                : c.differing_floats == 0 ? "identical"
                                          : "DIFFERS");
    if (c.differing_floats != 0) {
      std::printf("FAILED: %s with %d threads: %zu of %zu floats differ from the baseline image\n",
                  c.devices.c_str(), c.threads, c.differing_floats, baseline_image.size());
    }
  }
  std::printf(
      "baseline: one inproc device, CPU_NUM_THREADS=1; second row: inproc with %d threads "
      "(reference); local:N: N tessera-worker processes with their default share of the "
      "%d cores. Timed launches alternate between configurations. Load average after: "
      "%.2f\n",
      cores, cores, LoadAverage());
  if (!loaded_seconds.empty()) {
    // The same one-thread frame on a fully loaded machine: how much of the headline's loss is
    // the machine's per-core speed under load rather than anything the threads share.
    const double loaded = Median(loaded_seconds);
    std::printf(
        "baseline with the other %d cores busy (arithmetic touching no memory): %.3f s (x%.2f the "
        "time of a lone thread)",
        cores - 1, loaded, loaded / base);
    if (efficiency_at_cores > 0) {
      const double at_cores = base / efficiency_at_cores / cores;  // seconds at N = cores
      std::printf("; local:%d against it: efficiency %.2f", max_devices, loaded / at_cores / cores);
    }
    std::printf("\n");
  }
  embree.Report(efficiency_at_cores);
  std::printf("parallel_efficiency=%.3f\n", efficiency_at_cores);
  return identical ? 0 : 1;
}

}  // namespace
}  // namespace tessera::bench

int main(int argc, char** argv) {
  using namespace tessera::bench;
  Options o;
  CLI::App app{"Scaling of the tutorial's last step over local worker processes"};
  app.add_option("--width", o.width, "image width")
      ->capture_default_str()
      ->check(tessera::cli::kPositive);
  app.add_option("--height", o.height, "image height")
      ->capture_default_str()
      ->check(tessera::cli::kPositive);
  app.add_option("--repeats", o.repeats, "timed launches per configuration (median)")
      ->capture_default_str()
      ->check(tessera::cli::kPositive);
  app.add_option("--step", o.step,
                 "tutorial step (the headline figure is for the last, the default; step 1 is "
                 "primary rays only)")
      ->capture_default_str()
      ->check(CLI::Range(0, tessera::tutorial::kLastStep));
  app.add_flag("--thread-sweep", o.thread_sweep,
               "also one inproc device with 2, 4, 8 … threads (reference rows)");
  app.add_option("--max-devices", o.max_devices,
                 "largest local:N (default: the core count, which the headline figure needs)")
      ->check(tessera::cli::kPositive);
  app.add_option("--devices", o.only,
                 "only these device specs after the baseline (repeatable; no headline figure)");
  app.add_option("--modules", o.module_dir, "directory of the tutorial_*.so modules");
  app.add_option("--viewer", o.viewer,
                 "Embree's viewer, timed each round as the machine's reference ('none': skip)")
      ->capture_default_str();
  app.add_option("--viewer-model", o.viewer_model, "the model the viewer renders")
      ->capture_default_str();
  app.add_flag("--loaded-baseline", o.loaded_baseline,
               "also time the baseline (and the viewer's one thread) while every other core "
               "spins on arithmetic: the machine's per-core slowdown under load, apart from "
               "anything Tessera's threads share");
  app.add_flag("--check", o.check,
               "96x64, local:1 and local:2, one timed launch; exit 1 unless images are identical");
  CLI11_PARSE(app, argc, argv);
  if (o.check) {
    o.width = 96;
    o.height = 64;
    o.repeats = 1;
  }
  try {
    return Run(o);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "tessera-bench-scaling: %s\n", e.what());
    return 1;
  }
}

// tessera-bench-eyelight: renders a model with Embree viewer's eyelight shader through the
// OptiX 3 API on Tessera, times it, runs Embree's own viewer on the same view, and prints
// eyelight_ratio_vs_embree=<ours/theirs> as its last line. --check renders 128x128 and verifies
// the image instead (exit 1 when it is wrong).
#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>
#include <optional>
#include <string>
#include <thread>

#include "common/embree_viewer.h"
#include "common/rt_util.h"  // LoadAverage
#include "image_check.h"
#include "mesh.h"
#include "scene.h"
#include "timing.h"

namespace tessera::bench {
namespace {

constexpr int kExitViewerMissing = 2;
constexpr unsigned kCheckSize = 128;

struct Options {
  std::string model = TESSERA_BENCH_DEFAULT_MODEL;
  std::string module = TESSERA_BENCH_MODULE_DIR "/bench_eyelight.so";
  std::string viewer = "viewer";
  std::string out;
  // One in-process device on every core is the like-for-like comparison with Embree's viewer.
  std::string devices = "inproc";
  unsigned width = 1024, height = 1024;
  int warmup = 5, runs = 20;
  int threads = 0;  // 0: every core, for Tessera and the viewer alike
  bool check = false;
};

int RunCheck(const Options& o, const Mesh& mesh, const Camera& camera) {
  EyelightScene scene(mesh, camera, kCheckSize, kCheckSize, o.module, o.devices);
  scene.Launch();
  Image image = scene.ReadImage();
  if (!o.out.empty()) WriteImage(image, o.out);
  CheckReport report = CheckImage(image, mesh, camera);
  std::printf("check %s: %s\n", report.ok ? "passed" : "FAILED", report.summary.c_str());
  return report.ok ? 0 : 1;
}

int RunBenchmark(const Options& o, const Mesh& mesh, const Camera& camera) {
  // Fail before timing anything when there is nothing to compare with.
  std::optional<std::string> viewer = FindExecutable(o.viewer);
  if (!viewer) {
    std::fprintf(stderr,
                 "Embree's viewer ('%s') was not found; install the embree-tools package or "
                 "pass --viewer PATH. No figures without it.\n",
                 o.viewer.c_str());
    return kExitViewerMissing;
  }

  const double rays = static_cast<double>(o.width) * o.height;
  const double load_before = LoadAverage();
  double ours = 0, utilization = 0;
  int threads = 0;
  {
    EyelightScene scene(mesh, camera, o.width, o.height, o.module, o.devices, o.threads);
    LaunchTimes times = TimeLaunches([&] { scene.Launch(); }, o.warmup, o.runs);
    ours = rays / times.Median() / 1e6;
    utilization = times.Utilization();
    threads = scene.ThreadCount();
    if (threads <= 0) threads = static_cast<int>(std::thread::hardware_concurrency());
    std::printf(
        "tessera: median %.3f ms per launch (min %.3f, max %.3f) over %d launches "
        "after %d warm-ups\n",
        1e3 * times.Median(), 1e3 * times.Min(), 1e3 * times.Max(), o.runs, o.warmup);
    std::printf("tessera launch times (ms):");
    for (double t : times.seconds) std::printf(" %.1f", 1e3 * t);
    std::printf("\n");
    std::printf("tessera launch CPU times (ms):");
    for (double t : times.cpu_seconds) std::printf(" %.1f", 1e3 * t);
    std::printf("\n");
    if (!o.out.empty()) {
      WriteImage(scene.ReadImage(), o.out);
      std::printf("image written to %s\n", o.out.c_str());
    }
  }

  ViewerRun run;
  run.viewer = *viewer;
  run.model = o.model;
  run.width = o.width;
  run.height = o.height;
  run.warmup = o.warmup;
  run.runs = o.runs;
  run.camera_flags = camera.ViewerFlags();
  run.threads = o.threads;
  std::string command;
  double theirs = RunEmbreeViewer(run, &command);
  std::printf("embree: %s\n", command.c_str());

  std::printf(
      "image: %ux%u (%.0f primary rays), threads: %d, load average before: %.2f, tessera used "
      "%.2f cores on average\n",
      o.width, o.height, rays, threads, load_before, utilization);
  std::printf("tessera_mrays_per_s=%.3f\n", ours);
  std::printf("embree_mrays_per_s=%.3f\n", theirs);
  std::printf("eyelight_ratio_vs_embree=%.3f\n", ours / theirs);
  return 0;
}

}  // namespace
}  // namespace tessera::bench

int main(int argc, char** argv) {
  using namespace tessera::bench;
  Options o;
  CLI::App app{"Eyelight primary rays on Tessera vs Embree's viewer"};
  app.add_option("--model", o.model, "Wavefront OBJ model")->capture_default_str();
  app.add_option("--width", o.width, "image width")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  app.add_option("--height", o.height, "image height")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  app.add_option("--warmup", o.warmup, "untimed launches first")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  app.add_option("--runs", o.runs, "timed launches")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  app.add_option("--threads", o.threads,
                 "tracing threads for Tessera (CPU_NUM_THREADS) and the viewer (--threads); "
                 "0: every core")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  app.add_option("--out", o.out, "write the image (e.g. eyelight.png)");
  app.add_option("--module", o.module, "program module built from eyelight.cu")
      ->capture_default_str();
  app.add_option("--viewer", o.viewer, "Embree's viewer executable")->capture_default_str();
  app.add_option("--devices", o.devices, "Tessera device spec (inproc, local:N, ...)")
      ->capture_default_str();
  app.add_flag("--check", o.check,
               "render 128x128 and verify the image (no timing); exit 1 when it is wrong");
  CLI11_PARSE(app, argc, argv);

  try {
    // Embree's cornell_box.ecs view; Embree's viewer gets the same flags.
    Camera camera;
    Mesh mesh = LoadObjMesh(o.model);
    std::printf("model: %s (%zu triangles, %zu vertices)\n", o.model.c_str(), mesh.TriangleCount(),
                mesh.VertexCount());
    return o.check ? RunCheck(o, mesh, camera) : RunBenchmark(o, mesh, camera);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "tessera-bench-eyelight: %s\n", e.what());
    return 1;
  }
}

// tessera-bench-eyelight: renders a model with Embree viewer's eyelight shader on Tessera, the
// mesh once as OptiX 3 geometry with an intersection program and once as OptiX 6 built-in
// triangles (GeometryTriangles) with an attribute program, times both, runs Embree's own viewer
// on the same view, and prints eyelight_ratio_vs_embree=<ours/theirs> for built-in triangles as
// its last line (the viewer's like: Embree's triangles, normal from the hit). --check renders
// 128x128 both ways and verifies the images instead (exit 1 when one is wrong).
#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>
#include <optional>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "common/embree_viewer.h"
#include "common/rt_util.h"  // LoadAverage
#include "image_check.h"
#include "mesh.h"
#include "scene.h"
#include "tessera/cli_checks.h"
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
  int threads = 0;                // 0: every core, for Tessera and the viewer alike
  std::string geometry = "both";  // programs, triangles or both
  bool check = false;

  std::vector<bool> Modes() const {  // builtin_triangles values to run
    if (geometry == "programs") return {false};
    if (geometry == "triangles") return {true};
    return {false, true};
  }
};

const char* ModeName(bool builtin_triangles) {
  return builtin_triangles ? "built-in triangles" : "intersection program";
}

int RunCheck(const Options& o, const Mesh& mesh, const Camera& camera) {
  bool ok = true;
  for (bool builtin : o.Modes()) {
    EyelightScene scene(mesh, camera, kCheckSize, kCheckSize, o.module, o.devices, 0, builtin);
    scene.Launch();
    Image image = scene.ReadImage();
    if (!o.out.empty()) WriteImage(image, o.out);
    CheckReport report = CheckImage(image, mesh, camera);
    std::printf("check %s (%s): %s\n", report.ok ? "passed" : "FAILED", ModeName(builtin),
                report.summary.c_str());
    ok = ok && report.ok;
  }
  return ok ? 0 : 1;
}

struct Measured {
  double mrays_per_s = 0, utilization = 0;
  int threads = 0;
};

Measured TimeTessera(const Options& o, const Mesh& mesh, const Camera& camera, bool builtin) {
  const double rays = static_cast<double>(o.width) * o.height;
  Measured m;
  EyelightScene scene(mesh, camera, o.width, o.height, o.module, o.devices, o.threads, builtin);
  LaunchTimes times = TimeLaunches([&] { scene.Launch(); }, o.warmup, o.runs);
  m.mrays_per_s = rays / times.Median() / 1e6;
  m.utilization = times.Utilization();
  m.threads = scene.ThreadCount();
  if (m.threads <= 0) m.threads = static_cast<int>(std::thread::hardware_concurrency());
  std::printf(
      "tessera, %s: median %.3f ms per launch (min %.3f, max %.3f) over %d launches after %d "
      "warm-ups, %.2f cores used on average\n",
      ModeName(builtin), 1e3 * times.Median(), 1e3 * times.Min(), 1e3 * times.Max(), o.runs,
      o.warmup, m.utilization);
  std::printf("  launch times (ms):");
  for (double t : times.seconds) std::printf(" %.1f", 1e3 * t);
  std::printf("\n  launch CPU times (ms):");
  for (double t : times.cpu_seconds) std::printf(" %.1f", 1e3 * t);
  std::printf("\n");
  if (!o.out.empty()) {
    WriteImage(scene.ReadImage(), o.out);
    std::printf("  image written to %s\n", o.out.c_str());
  }
  return m;
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
  std::vector<std::pair<bool, Measured>> ours;
  for (bool builtin : o.Modes()) ours.emplace_back(builtin, TimeTessera(o, mesh, camera, builtin));

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

  std::printf("image: %ux%u (%.0f primary rays), threads: %d, load average before: %.2f\n", o.width,
              o.height, rays, ours.front().second.threads, load_before);
  std::printf("embree_mrays_per_s=%.3f\n", theirs);
  for (const auto& [builtin, m] : ours) {
    const char* key = builtin ? "triangles" : "programs";
    std::printf("tessera_%s_mrays_per_s=%.3f\n", key, m.mrays_per_s);
    std::printf("eyelight_ratio_%s_vs_embree=%.3f\n", key, m.mrays_per_s / theirs);
  }
  // The headline: built-in triangles when measured (what the viewer traces), else programs.
  std::printf("eyelight_ratio_vs_embree=%.3f\n", ours.back().second.mrays_per_s / theirs);
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
      ->check(tessera::cli::kPositive);
  app.add_option("--height", o.height, "image height")
      ->capture_default_str()
      ->check(tessera::cli::kPositive);
  app.add_option("--warmup", o.warmup, "untimed launches first")
      ->capture_default_str()
      ->check(tessera::cli::kNonNegative);
  app.add_option("--runs", o.runs, "timed launches")
      ->capture_default_str()
      ->check(tessera::cli::kPositive);
  app.add_option("--threads", o.threads,
                 "tracing threads for Tessera (CPU_NUM_THREADS) and the viewer (--threads); "
                 "0: every core")
      ->capture_default_str()
      ->check(tessera::cli::kNonNegative);
  app.add_option("--out", o.out, "write the image as a binary PPM (e.g. eyelight.ppm)")
      ->check([](const std::string& path) {
        const std::string ext = ".ppm";
        return path.size() > ext.size() &&
                       path.compare(path.size() - ext.size(), ext.size(), ext) == 0
                   ? std::string()
                   : "--out writes a binary PPM: name the file *.ppm (got '" + path + "')";
      });
  app.add_option("--module", o.module, "program module built from eyelight.cu")
      ->capture_default_str();
  app.add_option("--viewer", o.viewer, "Embree's viewer executable")->capture_default_str();
  app.add_option("--devices", o.devices, "Tessera device spec (inproc, local:N, ...)")
      ->capture_default_str();
  app.add_option("--geometry", o.geometry,
                 "the mesh as OptiX 3 geometry with an intersection program (programs), as OptiX "
                 "6 built-in triangles (triangles), or both")
      ->capture_default_str()
      ->check(CLI::IsMember({"programs", "triangles", "both"}));
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

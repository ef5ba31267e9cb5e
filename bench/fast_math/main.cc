// tessera-bench-fastmath: what fast math costs and gains on a shading-heavy scene, the tutorial's
// last step (procedural noise, Phong, glass, shadows, reflections: docs/fast_math.md). Three
// configurations render the same image on the same devices:
//   default     the tutorial's modules as built (IEEE denormals on the tracing threads)
//   ftz         the same modules on a context with TESSERA_ACCURACY_FAST_MATH: only FTZ/DAZ
//   fast_math   the modules built with FAST_MATH (tessera_add_program_module), FTZ/DAZ on
// Each gets a warm-up launch, then timed launches alternate between them (a change of load skews
// all alike); per configuration the median time, its ratio to default's, and the fraction of
// pixels whose float4 differs in any bit from default's image (and the largest difference). The
// last line is fast_math_time_ratio=<fast_math median / default median>. --check renders a tiny
// image and exits 1 unless a second default context renders default's image bit for bit (the
// determinism fast math must not break when it is off), fast math on local:2 renders the same
// image as on --devices, and every image is finite.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <exception>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "common/rt_util.h"
#include "common/tutorial_context.h"
#include "tessera/accuracy.h"
#include "tessera/cli_checks.h"
#include "tessera/rt_ext.h"

namespace tessera::bench {
namespace {

struct Options {
  int width = 1024, height = 768;
  int repeats = 5;
  std::string devices = "inproc";
  int step = tutorial::kLastStep;
  std::string default_modules;  // empty: the build's tutorial modules
  std::string fast_modules = TESSERA_BENCH_FAST_MATH_MODULE_DIR;
  std::string other_devices = "local:2";  // --check: fast math renders the same there
  bool check = false;
};

struct Config {
  std::string name;
  std::string module_dir;
  unsigned accuracy = 0;  // TESSERA_ACCURACY_* set on the context
  std::string devices;
  int same_as = -1;  // --check: the configuration whose image this one must equal bit for bit
  std::unique_ptr<TutorialContext> scene;
  std::vector<double> seconds;
  std::vector<float> image;
};

Config MakeConfig(std::string name, std::string module_dir, unsigned accuracy, std::string devices,
                  int same_as = -1) {
  Config c;
  c.name = std::move(name);
  c.module_dir = std::move(module_dir);
  c.accuracy = accuracy;
  c.devices = std::move(devices);
  c.same_as = same_as;
  return c;
}

double TimeLaunch(TutorialContext& scene) {
  const double start = NowSeconds();
  scene.Launch();
  return NowSeconds() - start;
}

// Pixels (float4) of `b` that differ from `a` in any bit, and the largest difference of a
// channel.
struct Difference {
  size_t pixels = 0;
  double max_abs = 0;
};
Difference Compare(const std::vector<float>& a, const std::vector<float>& b) {
  Difference d;
  for (size_t p = 0; p + 3 < a.size(); p += 4) {
    d.pixels += std::memcmp(&a[p], &b[p], 4 * sizeof(float)) != 0;
    for (size_t i = p; i < p + 4; ++i) {
      d.max_abs = std::max(d.max_abs, std::fabs(static_cast<double>(a[i]) - b[i]));
    }
  }
  return d;
}

bool AllFinite(const std::vector<float>& image) {
  return std::all_of(image.begin(), image.end(), [](float f) { return std::isfinite(f); });
}

int Run(const Options& o) {
  std::printf(
      "tutorial step %d at %dx%d on '%s', median of %d launches after one warm-up, load average "
      "before: %.2f\n",
      o.step, o.width, o.height, o.devices.c_str(), o.repeats, LoadAverage());
  std::vector<Config> configs;
  configs.push_back(MakeConfig("default", o.default_modules, 0, o.devices));
  configs.push_back(MakeConfig("ftz", o.default_modules, TESSERA_ACCURACY_FAST_MATH, o.devices));
  configs.push_back(MakeConfig("fast_math", o.fast_modules, 0, o.devices));
  if (o.check) {
    // Default rendering is deterministic; fast math is too, across device sets (one module's
    // bytes on every device, the same FTZ/DAZ mode).
    configs.push_back(MakeConfig("default again", o.default_modules, 0, o.devices, 0));
    configs.push_back(
        MakeConfig("fast_math on " + o.other_devices, o.fast_modules, 0, o.other_devices, 2));
  }
  for (Config& c : configs) {
    TutorialOptions scene_options;
    scene_options.devices = c.devices;
    scene_options.step = o.step;
    scene_options.width = o.width;
    scene_options.height = o.height;
    scene_options.module_dir = c.module_dir;
    c.scene = std::make_unique<TutorialContext>(scene_options);
    Check(c.scene->context(), tesseraContextSetAccuracy(c.scene->context(), c.accuracy),
          "tesseraContextSetAccuracy");
    TimeLaunch(*c.scene);  // spawns workers, ships state, builds accelerations
  }
  for (int round = 0; round < o.repeats; ++round) {
    for (Config& c : configs) c.seconds.push_back(TimeLaunch(*c.scene));
  }
  for (Config& c : configs) {
    c.image = c.scene->ReadOutput();
    c.scene.reset();  // stops its workers
  }

  const Config& base = configs.front();
  const double base_seconds = Median(base.seconds);
  const size_t pixels = static_cast<size_t>(o.width) * o.height;
  std::printf("%-22s %10s %8s %16s %12s\n", "configuration", "median s", "ratio", "pixels differ",
              "max |diff|");
  bool ok = true;
  for (const Config& c : configs) {
    const Difference d = Compare(base.image, c.image);
    const double seconds = Median(c.seconds);
    std::printf("%-22s %10.4f %8.3f %8zu (%5.2f%%) %12.3g\n", c.name.c_str(), seconds,
                seconds / base_seconds, d.pixels, 100.0 * d.pixels / pixels, d.max_abs);
    if (!AllFinite(c.image)) {
      std::printf("FAILED: %s: the image holds NaN or infinite values\n", c.name.c_str());
      ok = false;
    }
    if (c.same_as >= 0) {
      const Config& reference = configs[static_cast<size_t>(c.same_as)];
      const Difference same = Compare(reference.image, c.image);
      if (same.pixels != 0) {
        std::printf("FAILED: %s differs from %s in %zu pixels\n", c.name.c_str(),
                    reference.name.c_str(), same.pixels);
        ok = false;
      }
    }
  }
  std::printf(
      "default: modules as built; ftz: the same on a context with TESSERA_ACCURACY_FAST_MATH "
      "(denormals flushed, no fast-math compile); fast_math: modules built with FAST_MATH. Load "
      "average after: %.2f\n",
      LoadAverage());
  std::printf("fast_math_time_ratio=%.3f\n", Median(configs[2].seconds) / base_seconds);
  return ok ? 0 : 1;
}

}  // namespace
}  // namespace tessera::bench

int main(int argc, char** argv) {
  using namespace tessera::bench;
  Options o;
  CLI::App app{
      "Fast-math program modules against default ones on the tutorial's last step\n"
      "  tessera-bench-fastmath --devices local:2 --width 640 --height 480"};
  app.add_option("--width", o.width, "image width")
      ->capture_default_str()
      ->check(tessera::cli::kPositive);
  app.add_option("--height", o.height, "image height")
      ->capture_default_str()
      ->check(tessera::cli::kPositive);
  app.add_option("--repeats", o.repeats, "timed launches per configuration (median)")
      ->capture_default_str()
      ->check(tessera::cli::kPositive);
  app.add_option("--devices", o.devices, "device spec (inproc, local:N, ...)")
      ->capture_default_str();
  app.add_option("--step", o.step, "tutorial step")
      ->capture_default_str()
      ->check(CLI::Range(0, tessera::tutorial::kLastStep));
  app.add_option("--modules", o.default_modules,
                 "directory of the default tutorial_*.so modules (default: the build's)");
  app.add_option("--fast-modules", o.fast_modules,
                 "directory of the tutorial_*.so modules built with FAST_MATH")
      ->capture_default_str();
  app.add_option("--check-devices", o.other_devices,
                 "--check: device spec whose fast-math image must equal --devices' one")
      ->capture_default_str();
  app.add_flag("--check", o.check,
               "tiny image; fails unless default and fast-math rendering are deterministic and "
               "images finite");
  CLI11_PARSE(app, argc, argv);
  if (o.check) {
    o.width = 64;
    o.height = 48;
    o.repeats = 1;
  }
  try {
    return Run(o);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "tessera-bench-fastmath: %s\n", e.what());
    return 1;
  }
}

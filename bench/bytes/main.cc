// tessera-bench-bytes: how many buffer bytes travel between the host and its devices per launch
// of the tutorial's last step, from tesseraContextGetTransferStats deltas: the first launch, an
// unchanged second launch, and launches after changing one small INPUT buffer or one variable.
// The last line is steady_state_buffer_bytes=<n>, the host → device buffer bytes of the unchanged
// launch (target 0: devices keep their replicas). --check runs a tiny image and exits 1 when a
// figure differs from what the buffer rules say it must be.
#include <tessera/rt.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <cstring>
#include <exception>
#include <string>
#include <vector>

#include "common/rt_util.h"
#include "common/tutorial_context.h"
#include "tessera/cli_checks.h"
#include "tutorial/programs/common_structs.h"

namespace tessera::bench {
namespace {

struct Options {
  TutorialOptions scene;
  bool check = false;
};

struct Row {
  const char* what;
  TransferStats bytes;
  uint64_t expected_sent;
  uint64_t expected_received;
};

// Every launch of the tutorial writes each output pixel exactly once, so each launch gathers the
// whole output buffer; written regions are exactly what programs touched, never more.
int Run(const Options& o) {
  TutorialContext scene(o.scene);
  RTcontext c = scene.context();
  unsigned device_count = 0;
  Check(c, rtContextGetDeviceCount(c, &device_count), "rtContextGetDeviceCount");
  RTsize host_bytes = 0;
  Check(c,
        rtContextGetAttribute(c, RT_CONTEXT_ATTRIBUTE_USED_HOST_MEMORY, sizeof(host_bytes),
                              &host_bytes),
        "rtContextGetAttribute(USED_HOST_MEMORY)");
  // Every buffer but the output is an INPUT buffer (the lights, the convex hull's planes).
  const uint64_t input_bytes = host_bytes - scene.OutputBytes();
  const uint64_t output_bytes = scene.OutputBytes();

  std::vector<Row> rows;
  auto launch = [&](const char* what, uint64_t expected_sent) {
    const TransferStats before = GetTransferStats(c);
    scene.Launch();
    rows.push_back(Row{what, GetTransferStats(c) - before, expected_sent, output_bytes});
  };

  launch("first launch", uint64_t{device_count} * input_bytes);
  const std::vector<float> first = scene.ReadOutput();
  launch("unchanged second launch", 0);
  const std::vector<float> second = scene.ReadOutput();
  // As bits: a NaN pixel would never equal itself as a float.
  const bool same_image =
      std::memcmp(second.data(), first.data(), first.size() * sizeof(float)) == 0;

  // A dimmer light: the lights buffer (one BasicLight) changes, nothing else.
  void* mapped = nullptr;
  Check(c, rtBufferMap(scene.lights(), &mapped), "rtBufferMap(lights)");
  static_cast<BasicLight*>(mapped)->color = make_float3(0.8f, 0.8f, 0.8f);
  Check(c, rtBufferUnmap(scene.lights()), "rtBufferUnmap(lights)");
  launch("after changing the lights buffer", uint64_t{device_count} * sizeof(BasicLight));

  // Variables travel in the state delta too, but they are not buffer contents.
  RTvariable ambient = nullptr;
  Check(c, rtContextQueryVariable(c, "ambient_light_color", &ambient),
        "rtContextQueryVariable(ambient_light_color)");
  Check(c, rtVariableSet3f(ambient, 0.2f, 0.2f, 0.2f), "rtVariableSet3f(ambient_light_color)");
  launch("after changing a context variable", 0);

  std::printf(
      "scene: tutorial step %d, %dx%d, devices '%s' (%u), INPUT buffers %llu bytes, "
      "OUTPUT buffer %llu bytes\n",
      o.scene.step, o.scene.width, o.scene.height, o.scene.devices.c_str(), device_count,
      static_cast<unsigned long long>(input_bytes), static_cast<unsigned long long>(output_bytes));
  std::printf("%-36s %16s %16s %10s\n", "launch", "host->devices", "devices->host", "expected");
  bool ok = same_image;
  for (const Row& r : rows) {
    const bool as_expected =
        r.bytes.sent == r.expected_sent && r.bytes.received == r.expected_received;
    ok = ok && as_expected;
    std::printf("%-36s %16llu %16llu %10s\n", r.what, static_cast<unsigned long long>(r.bytes.sent),
                static_cast<unsigned long long>(r.bytes.received), as_expected ? "yes" : "NO");
  }
  std::printf(
      "host->devices: INPUT buffer contents in state deltas, summed over devices (each device gets "
      "what it lacks: all of them at first, then only changed %llu-byte chunks). Variables, "
      "programs and the graph travel too but are not counted.\n"
      "devices->host: the regions of OUTPUT buffers that programs wrote, each element from the "
      "device that wrote it (%llu bytes = the whole output, every launch).\n",
      static_cast<unsigned long long>(uint64_t{4} << 20),
      static_cast<unsigned long long>(output_bytes));
  if (!same_image) std::printf("FAILED: the unchanged second launch rendered another image\n");
  if (!ok) std::printf("FAILED: a figure differs from what the buffer rules say\n");
  std::printf("steady_state_buffer_bytes=%llu\n",
              static_cast<unsigned long long>(rows[1].bytes.sent));
  // The full run reports its figures whatever they are; only a wrong image is a failure there.
  if (o.check) return ok ? 0 : 1;
  return same_image ? 0 : 1;
}

}  // namespace
}  // namespace tessera::bench

int main(int argc, char** argv) {
  using namespace tessera::bench;
  Options o;
  o.scene.devices = "local:2";
  CLI::App app{"Buffer bytes shipped per launch of the tutorial scene"};
  app.add_option("--devices", o.scene.devices, "device spec")->capture_default_str();
  app.add_option("--width", o.scene.width, "image width")
      ->capture_default_str()
      ->check(tessera::cli::kPositive);
  app.add_option("--height", o.scene.height, "image height")
      ->capture_default_str()
      ->check(tessera::cli::kPositive);
  app.add_option("--modules", o.scene.module_dir, "directory of the tutorial_*.so modules");
  app.add_flag("--check", o.check,
               "tiny image; exit 1 unless every figure is what the buffer rules say");
  CLI11_PARSE(app, argc, argv);
  if (o.check) {
    o.scene.width = 64;
    o.scene.height = 48;
  }
  try {
    return Run(o);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "tessera-bench-bytes: %s\n", e.what());
    return 1;
  }
}

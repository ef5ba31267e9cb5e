// tessera-bench-batching: what batched tracing (issue 28) can win, below the engine, one thread:
//  - Embree's kernels on the eyelight view's primary rays: rtcIntersect1 per pixel against
//    packets of 2x2, 4x2 and 4x4 pixels, with how many rays' hits differ from rtcIntersect1's
//    (batches must be formed from launch indices alone when they do: docs/programs.md);
//    `packet<N>_ratio=<packet time / single time>`.
//  - What a suspended program's round trip costs (scheduler -> program -> scheduler): Boost.Context
//    fibers, the engine's lane switch (worker/core/lane_switch.S), ucontext.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <string>

#include "packets.h"
#include "switches.h"

int main(int argc, char** argv) {
  CLI::App app{"tessera-bench-batching: packets and program switches, one thread"};
  std::string model = TESSERA_BENCH_DEFAULT_MODEL;
  unsigned width = 1024, height = 1024;
  int rounds = 9;
  app.add_option("--model", model, "OBJ model");
  app.add_option("--width", width)->check(CLI::Range(1u, 16384u));
  app.add_option("--height", height)->check(CLI::Range(1u, 16384u));
  app.add_option("--rounds", rounds, "alternating rounds (medians reported)")
      ->check(CLI::Range(1, 1000));
  CLI11_PARSE(app, argc, argv);
  const std::vector<tessera::bench::KernelTime> kernels =
      tessera::bench::TimePackets(model, width, height, rounds);
  const double single = kernels[0].ns_per_ray;
  for (const auto& k : kernels) {
    std::printf("%-24s %7.1f ns/ray  %.3fx  %zu rays differ from rtcIntersect1\n", k.name.c_str(),
                k.ns_per_ray, k.ns_per_ray / single, k.mismatches);
  }
  for (const auto& s : tessera::bench::TimeSwitches(1 << 20, rounds)) {
    std::printf("%-28s %6.1f ns per round trip\n", s.name.c_str(), s.ns_per_round_trip);
  }
  std::printf("packet4_ratio=%.3f\npacket8_ratio=%.3f\npacket16_ratio=%.3f\n",
              kernels[1].ns_per_ray / single, kernels[2].ns_per_ray / single,
              kernels[3].ns_per_ray / single);
  return 0;
}

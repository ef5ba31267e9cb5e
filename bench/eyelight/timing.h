// Wall-clock timing of repeated launches.
#ifndef TESSERA_BENCH_EYELIGHT_TIMING_H_
#define TESSERA_BENCH_EYELIGHT_TIMING_H_

#include <functional>
#include <vector>

namespace tessera::bench {

struct LaunchTimes {
  std::vector<double> seconds;      // wall time of each timed launch, in order
  std::vector<double> cpu_seconds;  // process CPU time (all threads) of each timed launch

  // Mean CPU time over mean wall time: about the thread count on an otherwise idle machine,
  // less when other processes take the cores.
  double Utilization() const;

  double Median() const;
  double Min() const;
  double Max() const;
};

// Runs `launch` `warmup` times untimed, then `runs` times, timing each call with steady_clock
// (and the process CPU clock).
LaunchTimes TimeLaunches(const std::function<void()>& launch, int warmup, int runs);

}  // namespace tessera::bench

#endif  // TESSERA_BENCH_EYELIGHT_TIMING_H_

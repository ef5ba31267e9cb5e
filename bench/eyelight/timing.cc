#include "timing.h"

#include <algorithm>
#include <chrono>
#include <ctime>
#include <numeric>
#include <stdexcept>

namespace tessera::bench {

double LaunchTimes::Median() const {
  if (seconds.empty()) throw std::logic_error("no timed launches");
  std::vector<double> s = seconds;
  std::sort(s.begin(), s.end());
  size_t n = s.size();
  return n % 2 == 1 ? s[n / 2] : 0.5 * (s[n / 2 - 1] + s[n / 2]);
}

double LaunchTimes::Min() const { return *std::min_element(seconds.begin(), seconds.end()); }
double LaunchTimes::Max() const { return *std::max_element(seconds.begin(), seconds.end()); }

double LaunchTimes::Utilization() const {
  double wall = std::accumulate(seconds.begin(), seconds.end(), 0.0);
  double cpu = std::accumulate(cpu_seconds.begin(), cpu_seconds.end(), 0.0);
  return wall > 0 ? cpu / wall : 0;
}

namespace {
double ProcessCpuSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}
}  // namespace

LaunchTimes TimeLaunches(const std::function<void()>& launch, int warmup, int runs) {
  for (int i = 0; i < warmup; ++i) launch();
  LaunchTimes times;
  times.seconds.reserve(static_cast<size_t>(std::max(runs, 0)));
  for (int i = 0; i < runs; ++i) {
    double cpu_start = ProcessCpuSeconds();
    auto start = std::chrono::steady_clock::now();
    launch();
    auto end = std::chrono::steady_clock::now();
    times.seconds.push_back(std::chrono::duration<double>(end - start).count());
    times.cpu_seconds.push_back(ProcessCpuSeconds() - cpu_start);
  }
  return times;
}

}  // namespace tessera::bench

#include "switches.h"

#include <ucontext.h>

#include <algorithm>
#include <boost/context/fiber.hpp>
#include <chrono>
#include <cstdint>
#include <memory>
#include <utility>

#include "lanes.h"

namespace tessera::bench {
namespace {

constexpr size_t kStackBytes = 64 * 1024;

template <typename F>
double NsPer(int n, F&& f) {
  const auto start = std::chrono::steady_clock::now();
  f();
  const std::chrono::duration<double, std::nano> ns = std::chrono::steady_clock::now() - start;
  return ns.count() / n;
}

// A fiber that yields back at once, forever; each resume is one round trip.
double BoostFiber(int n) {
  namespace ctx = boost::context;
  ctx::fiber f{[](ctx::fiber&& back) {
    for (;;) back = std::move(back).resume();
    return std::move(back);
  }};
  return NsPer(n, [&] {
    for (int i = 0; i < n; ++i) f = std::move(f).resume();
  });
}

struct OwnStack {
  void* scheduler_sp = nullptr;
  void* fiber_sp = nullptr;
};

void OwnLoop(void* arg) {
  auto* s = static_cast<OwnStack*>(arg);
  for (;;) tessera_lane_switch(&s->fiber_sp, s->scheduler_sp);
}

// The engine's own lanes (worker/core/lanes.h, lane_switch.S).
double OwnSwitch(int n) {
  worker::LaneStack stack(kStackBytes);
  OwnStack s;
  s.fiber_sp = stack.Start(&OwnLoop, &s);
  return NsPer(n, [&] {
    for (int i = 0; i < n; ++i) tessera_lane_switch(&s.scheduler_sp, s.fiber_sp);
  });
}

ucontext_t g_main, g_fiber;

void UcontextLoop() {
  for (;;) swapcontext(&g_fiber, &g_main);
}

double Ucontext(int n) {
  auto stack = std::make_unique<unsigned char[]>(kStackBytes);
  getcontext(&g_fiber);
  g_fiber.uc_stack.ss_sp = stack.get();
  g_fiber.uc_stack.ss_size = kStackBytes;
  g_fiber.uc_link = nullptr;
  makecontext(&g_fiber, &UcontextLoop, 0);
  return NsPer(n, [&] {
    for (int i = 0; i < n; ++i) swapcontext(&g_main, &g_fiber);
  });
}

double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

}  // namespace

std::vector<SwitchTime> TimeSwitches(int round_trips, int rounds) {
  const std::pair<const char*, double (*)(int)> ways[] = {
      {"boost::context::fiber", &BoostFiber},
      {"lane switch (worker/core)", &OwnSwitch},
      {"ucontext swapcontext", &Ucontext},
  };
  std::vector<SwitchTime> out;
  std::vector<std::vector<double>> times(std::size(ways));
  for (int r = 0; r < rounds; ++r) {
    for (size_t k = 0; k < std::size(ways); ++k) times[k].push_back(ways[k].second(round_trips));
  }
  for (size_t k = 0; k < std::size(ways); ++k) out.push_back({ways[k].first, Median(times[k])});
  return out;
}

}  // namespace tessera::bench

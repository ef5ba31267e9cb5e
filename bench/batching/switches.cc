#include "switches.h"

#include <ucontext.h>

#include <algorithm>
#include <boost/context/fiber.hpp>
#include <chrono>
#include <cstdint>
#include <memory>
#include <utility>

extern "C" void tessera_bench_switch(void** from, void* to);
extern "C" void tessera_bench_start();

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

void OwnLoop(OwnStack* s) {
  for (;;) tessera_bench_switch(&s->fiber_sp, s->scheduler_sp);
}

double OwnSwitch(int n) {
  auto stack = std::make_unique<unsigned char[]>(kStackBytes);
  OwnStack s;
  // tessera_bench_switch pops r15, r14, r13, r12, rbx, rbp and returns into tessera_bench_start,
  // which calls r13(r12) on a 16-byte aligned stack (stack_switch.S).
  auto top = reinterpret_cast<uintptr_t>(stack.get() + kStackBytes) & ~uintptr_t{15};
  auto* slot = reinterpret_cast<uintptr_t*>(top - 8);
  slot[0] = reinterpret_cast<uintptr_t>(&tessera_bench_start);
  uintptr_t* regs = slot - 6;
  regs[0] = 0;                                      // r15
  regs[1] = 0;                                      // r14
  regs[2] = reinterpret_cast<uintptr_t>(&OwnLoop);  // r13
  regs[3] = reinterpret_cast<uintptr_t>(&s);        // r12
  regs[4] = 0;                                      // rbx
  regs[5] = 0;                                      // rbp
  s.fiber_sp = regs;
  return NsPer(n, [&] {
    for (int i = 0; i < n; ++i) tessera_bench_switch(&s.scheduler_sp, s.fiber_sp);
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
      {"own switch (stack_switch.S)", &OwnSwitch},
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

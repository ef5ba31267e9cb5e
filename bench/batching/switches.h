// What suspending a program at a trace and resuming it costs: a round trip (scheduler -> program
// -> scheduler) through Boost.Context's fiber, through a stack switch of our own
// (worker/core/lane_switch.S, the engine's), and through ucontext (swapcontext, which also
// saves the signal mask).
#ifndef TESSERA_BENCH_BATCHING_SWITCHES_H_
#define TESSERA_BENCH_BATCHING_SWITCHES_H_

#include <string>
#include <vector>

namespace tessera::bench {

struct SwitchTime {
  std::string name;
  double ns_per_round_trip = 0;  // median over the rounds
};

std::vector<SwitchTime> TimeSwitches(int round_trips, int rounds);

}  // namespace tessera::bench

#endif  // TESSERA_BENCH_BATCHING_SWITCHES_H_

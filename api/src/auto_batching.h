// Whether an OptiX 3 launch traces its launch indices' first rays as Embree packets (batched
// tracing, docs/programs.md "Batched tracing"), chosen per entry point from what the entry's
// earlier launches measured (TESSERA_BATCHING=auto), so that launches that gain from packets take
// them and launches that would lose keep single rays. Opt-in, as batching itself: on the Intel
// machines measured, packets lose even where this would choose them (docs/programs.md).
//
// Packets pay when a launch index's first ray is most of its work and a packet answers it: then
// Embree's coherent packet traversal replaces most of a ray's traversal, against the ray
// generation program's code before its trace running twice. A launch whose indices trace many
// rays (a path tracer), or whose first rays no packet can answer (user geometry, any-hit
// programs, a write before the trace), pays that and gains little or nothing. So an entry point
// starts on single rays and is watched: after a launch tracing at most kMaxTracesPerIndex rays a
// launch index it takes packets, and keeps them while packets answer at least kMinAnswered of its
// indices and the rays per index stay that few; the first batched launch that falls short turns
// them off for the entry point (and its ray generation program) for good, so that the choice
// never goes back and forth.
//
// Determinism: the figures are a launch's totals over every device (a device's call counts only
// when it finished, and every launch index runs once), and which indices a packet answers
// depends on the launch grid and the programs alone. So every device set makes the same choices
// in the same launches, and the choice itself is shipped with each launch.
#ifndef TESSERA_API_SRC_AUTO_BATCHING_H_
#define TESSERA_API_SRC_AUTO_BATCHING_H_

#include <cstdint>
#include <string>
#include <vector>

namespace tessera::api {

class AutoBatching {
 public:
  // TESSERA_BATCHING: "1" always (both layers), "auto" this choice (OptiX 3 launches; OptiX 7
  // launches stay on single rays, where packets need lanes of their own and cost more than they
  // save), "0", empty or unset never.
  enum class Mode { kAuto, kAlways, kNever };
  // Parses `value` (null: unset); anything else is `kNever` with `*warning` set to say so.
  static Mode Parse(const char* value, std::string* warning);

  static constexpr double kMaxTracesPerIndex = 1.25;
  static constexpr double kMinAnswered = 0.9;

  enum class State { kWatching, kOn, kOff };

  // Whether the next launch of `entry`, whose ray generation program is `program`, is batched.
  // Another program than the last launch's starts the entry point afresh.
  bool Choose(unsigned entry, const void* program);
  // After a launch of `entry` that ran every launch index: how many it had, how many rays they
  // traced, and how many first rays a packet answered (0 for a launch on single rays). Returns
  // true when the entry point's state changed.
  bool Record(unsigned entry, uint64_t indices, uint64_t traces, uint64_t packet_answers);

  State state(unsigned entry) const {
    return entry < entries_.size() ? entries_[entry].state : State::kWatching;
  }

 private:
  struct Entry {
    State state = State::kWatching;
    const void* program = nullptr;
  };
  Entry& At(unsigned entry) {
    if (entry >= entries_.size()) entries_.resize(entry + 1);
    return entries_[entry];
  }
  std::vector<Entry> entries_;
};

const char* ToString(AutoBatching::State s);

}  // namespace tessera::api

#endif  // TESSERA_API_SRC_AUTO_BATCHING_H_

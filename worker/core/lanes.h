// Lanes: launch indices whose programs run on stacks of their own, so that a program can stop at
// a trace and resume when the trace's answer is ready: the engine runs the indices of a block
// until each waits at a trace or is done, traces the waiting rays together as one Embree packet,
// and resumes them (docs/programs.md, "Batched tracing"). A lane switches without system calls
// (lane_switch.S); an interrupted lane is simply never resumed, as an interrupted program on the
// thread's own stack is never returned to.
#ifndef TESSERA_WORKER_CORE_LANES_H_
#define TESSERA_WORKER_CORE_LANES_H_

#include <cstddef>

#include "interrupt.h"

extern "C" void tessera_lane_switch(void** from, void* to);

#if defined(__SANITIZE_ADDRESS__)
#include <sanitizer/common_interface_defs.h>
#endif

namespace tessera::worker {

// A lane's stack: anonymous memory with an inaccessible guard page below it (an overflow faults
// instead of running into other memory), touched only as deep as the lane's programs go.
class LaneStack {
 public:
  // `color`: which of several stacks this is. Stacks begin at page boundaries, so that their
  // tops, the hottest lines, would all fall in the same L1 cache sets (set bits are address bits
  // 6-11): each starts a different number of cache lines below its top instead.
  explicit LaneStack(size_t bytes, unsigned color = 0);
  ~LaneStack();
  LaneStack(const LaneStack&) = delete;
  LaneStack& operator=(const LaneStack&) = delete;

  // Lays the stack out so that the first tessera_lane_switch into the returned stack pointer
  // calls entry(arg); entry must never return (it switches away for good instead).
  void* Start(void (*entry)(void*), void* arg);
  // The lowest usable address and the usable size (the guard page excluded).
  const char* base() const { return base_; }
  size_t size() const { return size_; }

 private:
  // AddressSanitizer builds: clears the shadow of the top `top_bytes` (lanes.cc says why).
  void ForgetFrames(size_t top_bytes);
  static constexpr size_t kFramesOfATile = 256 * 1024;

  char* mapping_ = nullptr;
  size_t mapped_ = 0;
  char* base_ = nullptr;
  size_t size_ = 0;
  size_t color_bytes_ = 0;
};

// Tells AddressSanitizer which stack runs after a switch (without it, an exception thrown in a
// lane looks like a stack overflow to it): Before names the stack switched to, After runs on
// arrival and notes the stack come from, BeforeBack names that one. Nothing in other builds.
struct LaneSanitizer {
#if defined(__SANITIZE_ADDRESS__)
  void* fake = nullptr;
  const void* from_bottom = nullptr;
  size_t from_size = 0;
  void Before(const void* bottom, size_t size) {
    __sanitizer_start_switch_fiber(&fake, bottom, size);
  }
  void After() { __sanitizer_finish_switch_fiber(fake, &from_bottom, &from_size); }
  void BeforeBack() { Before(from_bottom, from_size); }  // to the stack last come from
  // After, on a lane's side (the thread stack it came from, for a jump out: interrupt.h) and on
  // the thread's (back from a lane).
  void AfterIntoLane() {
    After();
    EnteredLane(from_bottom, from_size);
  }
  void AfterBackFromLane() {
    After();
    LeftLane();
  }
#else
  void BeforeBack() {}
  void Before(const void*, size_t) {}
  void After() {}
  void AfterIntoLane() {}
  void AfterBackFromLane() {}
#endif
};

}  // namespace tessera::worker

#endif  // TESSERA_WORKER_CORE_LANES_H_

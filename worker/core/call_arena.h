// The TBB arena a device's calls run their pieces in, kept from one call to the next.
//
// oneTBB keeps its worker threads only while some arena holds its thread pool: an arena made for
// one call and destroyed at its end let the pool go, and the next call started every worker thread
// again. Each new thread then built its engine state afresh (ThreadState, the OptiX 7 lanes'
// stacks, modules' thread-local blocks), touched new stack pages, and on exit unmapped them,
// which interrupts every core the process runs on to flush its TLB: a cost per call that grew
// with the thread count (docs/programs.md, "Threads kept between calls, no lock per tile").
#ifndef TESSERA_WORKER_CORE_CALL_ARENA_H_
#define TESSERA_WORKER_CORE_CALL_ARENA_H_

#include <tbb/task_arena.h>

#include <memory>

namespace tessera::worker {

// Not thread-safe: a device's calls run one at a time.
class CallArena {
 public:
  // An arena of `threads` threads (the caller's own among them), the same one while the count
  // stays (CPU_NUM_THREADS may change it between calls).
  tbb::task_arena& Of(int threads) {
    if (arena_ == nullptr || threads_ != threads) {
      arena_ = std::make_unique<tbb::task_arena>(threads);
      arena_->initialize();  // holds the thread pool from now on, not from the first execute
      threads_ = threads;
    }
    return *arena_;
  }

 private:
  std::unique_ptr<tbb::task_arena> arena_;
  int threads_ = 0;
};

}  // namespace tessera::worker

#endif  // TESSERA_WORKER_CORE_CALL_ARENA_H_

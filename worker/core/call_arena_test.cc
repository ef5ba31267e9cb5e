// A device's arena keeps TBB's worker threads from one call to the next (call_arena.h), also when
// each call comes from a new thread, as a launch's dispatch threads are: in a process of its own,
// so that no other test's arenas or threads hold TBB's thread pool.
#include "call_arena.h"

#include <gtest/gtest.h>
#include <tbb/parallel_for.h>

#include <atomic>
#include <chrono>
#include <thread>

namespace tessera::worker {
namespace {

std::atomic<int> g_workers_seen{0};

// Counts each worker thread the first time it runs a piece.
struct SeenOnThisThread {
  SeenOnThisThread() { ++g_workers_seen; }
};

// Runs two pieces that each wait for the other to start, so that the call needs both of the
// arena's threads: the caller and one worker.
void CallNeedingTwoThreads(tbb::task_arena& arena) {
  std::atomic<int> started{0};
  const std::thread::id caller = std::this_thread::get_id();
  arena.execute([&] {
    tbb::parallel_for(0, 2, 1, [&](int) {
      if (std::this_thread::get_id() != caller) {
        thread_local SeenOnThisThread seen;
        (void)seen;
      }
      ++started;
      const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(10);
      while (started.load() < 2 && std::chrono::steady_clock::now() < give_up) {
        std::this_thread::yield();
      }
    });
  });
  ASSERT_EQ(started.load(), 2);
}

TEST(CallArenaTest, WorkersStayBetweenCalls) {
  CallArena arena;
  for (int call = 0; call < 20; ++call) {
    std::thread([&] { CallNeedingTwoThreads(arena.Of(2)); }).join();
    // Time for a released pool's workers to end, as between launches.
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  // An arena per call, its caller gone after it, let the pool go and started a new worker for the
  // next call: 20 of them.
  EXPECT_GE(g_workers_seen.load(), 1);
  EXPECT_LE(g_workers_seen.load(), 2);
}

TEST(CallArenaTest, SameArenaWhileTheCountStays) {
  CallArena arena;
  tbb::task_arena* two = &arena.Of(2);
  EXPECT_EQ(&arena.Of(2), two);
  EXPECT_EQ(arena.Of(3).max_concurrency(), 3);
  EXPECT_EQ(arena.Of(2).max_concurrency(), 2);
}

}  // namespace
}  // namespace tessera::worker

#include "call_thread.h"

#include <gtest/gtest.h>

#include <future>
#include <stdexcept>
#include <thread>
#include <vector>

namespace tessera::worker {
namespace {

// Calls run in the order they were posted, all on one thread that outlives them (what keeps its
// thread-local state warm), and a call's exception reaches the one waiting for it.
TEST(CallThreadTest, RunsCallsInOrderOnOneThread) {
  CallThread calls;
  std::vector<int> order;
  std::vector<std::thread::id> threads;
  std::vector<std::future<void>> ran;
  for (int i = 0; i < 20; ++i) {
    ran.push_back(calls.Post([&, i] {
      order.push_back(i);
      threads.push_back(std::this_thread::get_id());
    }));
  }
  for (std::future<void>& f : ran) f.get();
  ASSERT_EQ(order.size(), 20u);
  for (int i = 0; i < 20; ++i) EXPECT_EQ(order[i], i);
  for (const std::thread::id& id : threads) EXPECT_EQ(id, threads.front());
  EXPECT_NE(threads.front(), std::this_thread::get_id());
}

TEST(CallThreadTest, ACallsExceptionReachesItsCaller) {
  CallThread calls;
  std::future<void> failed = calls.Post([] { throw std::runtime_error("out of tiles"); });
  EXPECT_THROW(failed.get(), std::runtime_error);
  bool ran = false;
  calls.Post([&] { ran = true; }).get();  // the thread goes on
  EXPECT_TRUE(ran);
}

TEST(CallThreadTest, DestructionRunsWhatWasPosted) {
  int ran = 0;
  {
    CallThread calls;
    for (int i = 0; i < 5; ++i) calls.Post([&] { ++ran; });
  }
  EXPECT_EQ(ran, 5);
}

}  // namespace
}  // namespace tessera::worker

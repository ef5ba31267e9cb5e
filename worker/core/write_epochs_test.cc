// WriteEpochs under threads: no program marks with an epoch after it went out, the epochs go out
// in order, each once, and the epoch moves on as pieces finish.
#include "write_epochs.h"

#include <gtest/gtest.h>

#include <atomic>
#include <thread>
#include <vector>

namespace tessera::worker {
namespace {

TEST(WriteEpochsTest, NoMarkWithAnEpochThatWentOut) {
  constexpr size_t kPieces = 40000;
  constexpr int kThreads = 4;
  Replica replica;
  WriteEpochs epochs(replica, kPieces, WriteEpochs::kMaxEpochs);
  std::atomic<size_t> next{0};
  std::atomic<int> sent_upto{0};     // the last epoch that went out
  std::atomic<int> late_marks{0};    // marks with an epoch already out
  std::atomic<int> out_of_order{0};  // a claim not starting where the last one ended
  std::atomic<int> claims{0};
  auto work = [&] {
    for (size_t i; (i = next.fetch_add(1)) < kPieces;) {
      const unsigned char epoch = epochs.Started();
      // What a program marks with, loaded after its piece started, as programs do.
      for (int k = 0; k < 1 + static_cast<int>(i % 3); ++k) {
        const unsigned char mark = __atomic_load_n(replica.write_epoch(), __ATOMIC_ACQUIRE);
        if (mark <= sent_upto.load()) ++late_marks;
        if (mark < epoch) ++late_marks;  // a piece marks with its own epoch or a later one
      }
      unsigned char after = 0;
      unsigned char upto = epochs.Finished(epoch, &after);
      while (upto != 0) {
        if (after != sent_upto.load()) ++out_of_order;
        ++claims;
        sent_upto.store(upto);
        upto = epochs.Sent(upto, &after);
      }
    }
  };
  std::vector<std::thread> threads;
  for (int t = 0; t < kThreads; ++t) threads.emplace_back(work);
  for (std::thread& t : threads) t.join();
  EXPECT_EQ(late_marks.load(), 0);
  EXPECT_EQ(out_of_order.load(), 0);
  EXPECT_GT(claims.load(), 0);
  EXPECT_EQ(epochs.sent(), sent_upto.load());
  // Every epoch but the last (current when the call ends, taken with the call's final results)
  // can go out while pieces trace; the last piece to end closes all before it.
  EXPECT_EQ(*replica.write_epoch(), WriteEpochs::kMaxEpochs);
  EXPECT_EQ(epochs.sent(), WriteEpochs::kMaxEpochs - 1);
}

TEST(WriteEpochsTest, OneEpochSendsNothingWhileTracing) {
  Replica replica;
  WriteEpochs epochs(replica, 10, 1);
  for (int i = 0; i < 10; ++i) {
    unsigned char after = 0;
    EXPECT_EQ(epochs.Finished(epochs.Started(), &after), 0);
  }
  EXPECT_EQ(*replica.write_epoch(), 1);
  EXPECT_EQ(epochs.sent(), 0);
}

}  // namespace
}  // namespace tessera::worker

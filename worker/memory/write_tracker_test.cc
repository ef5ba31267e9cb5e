// Write tracking by page protection: exactly the bytes programs changed come back, from any
// number of threads writing the same pages at once, and a write the tracker does not own is still
// the crash it would have been.
#include "write_tracker.h"

#include <gtest/gtest.h>
#include <sys/mman.h>
#include <unistd.h>

#include <csignal>
#include <cstring>
#include <thread>
#include <vector>

namespace tessera::memory {
namespace {

class WriteTrackerTest : public ::testing::Test {
 protected:
  void SetUp() override {
    page_ = static_cast<size_t>(sysconf(_SC_PAGESIZE));
    size_ = 64 * page_;
    void* p = mmap(nullptr, size_, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    ASSERT_NE(p, MAP_FAILED);
    base_ = static_cast<unsigned char*>(p);
    for (size_t i = 0; i < size_; ++i) base_[i] = static_cast<unsigned char>(i * 7);
  }
  void TearDown() override { munmap(base_, size_); }
  uintptr_t At(size_t offset) const { return reinterpret_cast<uintptr_t>(base_) + offset; }

  unsigned char* base_ = nullptr;
  size_t page_ = 0, size_ = 0;
};

TEST_F(WriteTrackerTest, ExactlyTheChangedBytesComeBack) {
  auto t = WriteTracker::Create(At(0), size_);
  ASSERT_TRUE(t.ok()) << t.status();
  ASSERT_TRUE((*t)->Protect(At(0), size_).ok());
  base_[10] = 1;
  base_[11] = 2;                                         // with 10: one run of 2
  volatile unsigned char* same = base_ + 3 * page_ + 5;  // a store the compiler keeps
  *same = *same;                                         // written, unchanged: no run
  base_[page_ - 1] = 9;  // the last byte of page 0 and the first of page 1
  base_[page_] = static_cast<unsigned char>(base_[page_] + 1);
  // The first fault claims its whole block of 16 pages (or the range's pages, when fewer).
  EXPECT_EQ((*t)->pages_written(), std::min<size_t>(16, size_ / page_));
  const std::vector<WriteTracker::Run> runs = (*t)->Collect();
  const std::vector<WriteTracker::Run> expected = {
      {At(10), 2}, {At(page_ - 1), 2}};  // adjacent bytes across pages merge
  EXPECT_EQ(runs, expected);
  EXPECT_EQ(base_[11], 2);  // the writes themselves landed
  // Writable again, and ready for the next round.
  base_[20] = 5;
  ASSERT_TRUE((*t)->Protect(At(8 * page_), page_).ok());
  base_[8 * page_] = static_cast<unsigned char>(base_[8 * page_] + 1);
  EXPECT_EQ((*t)->Collect(), (std::vector<WriteTracker::Run>{{At(8 * page_), 1}}));
  EXPECT_TRUE((*t)->Collect().empty());
}

TEST_F(WriteTrackerTest, ThreadsWritingTheSamePagesAtOnce) {
  auto t = WriteTracker::Create(At(0), size_);
  ASSERT_TRUE(t.ok()) << t.status();
  std::vector<unsigned char> before(base_, base_ + size_);
  ASSERT_TRUE((*t)->Protect(At(0), size_).ok());
  constexpr int kThreads = 4;
  std::vector<std::thread> threads;
  for (int k = 0; k < kThreads; ++k) {
    threads.emplace_back([&, k] {
      // Thread k writes every 4th byte from k: all threads fault on every page together.
      for (size_t i = k; i < size_; i += kThreads)
        base_[i] = static_cast<unsigned char>(~before[i]);
    });
  }
  for (std::thread& th : threads) th.join();
  EXPECT_EQ((*t)->pages_written(), size_ / page_);
  const std::vector<WriteTracker::Run> runs = (*t)->Collect();
  // Every byte changed (each was complemented), and the copies were taken before any write.
  ASSERT_EQ(runs.size(), 1u);
  EXPECT_EQ(runs[0], (WriteTracker::Run{At(0), size_}));
  for (size_t i = 0; i < size_; ++i) ASSERT_EQ(base_[i], static_cast<unsigned char>(~before[i]));
}

TEST_F(WriteTrackerTest, OneTrackerAtATimeAndRangesChecked) {
  auto t = WriteTracker::Create(At(0), size_);
  ASSERT_TRUE(t.ok());
  EXPECT_EQ(WriteTracker::Create(At(0), size_).status().code(),
            absl::StatusCode::kFailedPrecondition);
  EXPECT_EQ((*t)->Protect(At(size_ - page_), 2 * page_).code(), absl::StatusCode::kOutOfRange);
  EXPECT_EQ(WriteTracker::Create(At(1), page_).status().code(), absl::StatusCode::kInvalidArgument);
  t->reset();
  EXPECT_TRUE(WriteTracker::Create(At(0), size_).ok());  // the first is gone
}

#ifndef TESSERA_SANITIZER_BUILD
// A fault the tracker does not own (here: a store to a page never protected for tracking, made
// inaccessible) reaches the handler that was there before, and the process dies of it.
TEST_F(WriteTrackerTest, AWriteItDoesNotOwnIsStillACrash) {
  EXPECT_EXIT(
      {
        auto t = WriteTracker::Create(At(0), size_);
        mprotect(base_ + 5 * page_, page_, PROT_NONE);
        base_[5 * page_] = 1;
      },
      ::testing::KilledBySignal(SIGSEGV), "");
}
#endif

}  // namespace
}  // namespace tessera::memory

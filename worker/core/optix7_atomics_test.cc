// What a device does with its programs' atomics (optix7_atomics.h) and what the host does with
// the result (tessera/detail/atomic_ops.h): combined operations must equal the operations one
// after the other.
#include "optix7_atomics.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <map>
#include <thread>
#include <vector>

#include "tessera/detail/atomic_ops.h"

namespace tessera::worker {
namespace {

namespace ops = atomic_ops;

uint32_t IncOnce(uint32_t old, uint32_t limit) { return old >= limit ? 0u : old + 1u; }
uint32_t DecOnce(uint32_t old, uint32_t limit) {
  return (old == 0u || old > limit) ? limit : old - 1u;
}

TEST(AtomicOpsTest, IncAndDecCountsEqualSingleSteps) {
  for (uint32_t limit : {0u, 1u, 6u, 9u, 0xFFFFFFFEu, 0xFFFFFFFFu}) {
    for (uint32_t start : {0u, 1u, 5u, 9u, 10u, 20u, 0xFFFFFFFFu}) {
      uint32_t inc = start, dec = start;
      for (uint64_t k = 0; k <= 25; ++k) {
        uint32_t combined_inc = start, combined_dec = start;
        ops::Apply(ops::kInc, &combined_inc, k, limit);
        ops::Apply(ops::kDec, &combined_dec, k, limit);
        EXPECT_EQ(combined_inc, inc) << "limit " << limit << " start " << start << " k " << k;
        EXPECT_EQ(combined_dec, dec) << "limit " << limit << " start " << start << " k " << k;
        inc = IncOnce(inc, limit);
        dec = DecOnce(dec, limit);
      }
    }
  }
}

// Each kind: two operands combined, then applied, equal applying them one after the other.
TEST(AtomicOpsTest, CombinedEqualsOneAfterTheOther) {
  const uint64_t a = 0xFFFFFFF3u, b = 0x00000020u;  // 32-bit: -13 and 32 as signed
  const uint64_t c = 0x8000000000000005ull, d = 7;  // 64-bit: negative and positive as signed
  struct Case {
    uint32_t op;
    uint64_t start, x, y;
  };
  float fs = 1.5f, fx = 0.25f, fy = 2.0f;
  double ds = -1.0, dx = 0.5, dy = 8.0;
  uint32_t bits32;
  uint64_t f_start, f_x, f_y, d_start, d_x, d_y;
  std::memcpy(&bits32, &fs, 4);
  f_start = bits32;
  std::memcpy(&bits32, &fx, 4);
  f_x = bits32;
  std::memcpy(&bits32, &fy, 4);
  f_y = bits32;
  std::memcpy(&d_start, &ds, 8);
  std::memcpy(&d_x, &dx, 8);
  std::memcpy(&d_y, &dy, 8);
  const Case cases[] = {
      {ops::kAdd32, 0xFFFFFFFFu, a, b},
      {ops::kAdd64, ~0ull, c, d},
      {ops::kAddFloat, f_start, f_x, f_y},
      {ops::kAddDouble, d_start, d_x, d_y},
      {ops::kMinS32, 5, a, b},
      {ops::kMinU32, 5, a, b},
      {ops::kMinS64, 5, c, d},
      {ops::kMinU64, 5, c, d},
      {ops::kMaxS32, 5, a, b},
      {ops::kMaxU32, 5, a, b},
      {ops::kMaxS64, 5, c, d},
      {ops::kMaxU64, 5, c, d},
      {ops::kAnd32, 0xF0F0F0F0u, a, b},
      {ops::kAnd64, ~0ull, c, d | (1ull << 63)},
      {ops::kOr32, 0x100u, a, b},
      {ops::kOr64, 0x100u, c, d},
      {ops::kXor32, 0x1234u, a, b},
      {ops::kXor64, 0x1234u, c, d},
      {ops::kInc, 3, 4, 9},
      {ops::kDec, 3, 4, 9},
  };
  for (const Case& k : cases) {
    uint64_t sequential = k.start, combined = k.start;  // 32-bit kinds use the low half
    ops::Apply(k.op, &sequential, k.x, 6);
    ops::Apply(k.op, &sequential, k.y, 6);
    ops::Apply(k.op, &combined, ops::Combine(k.op, k.x, k.y), 6);
    EXPECT_EQ(combined, sequential) << "op " << k.op;
    EXPECT_EQ(ops::Combine(k.op, k.x, k.y), ops::Combine(k.op, k.y, k.x)) << "op " << k.op;
  }
  EXPECT_FALSE(ops::Apply(ops::kNone, &bits32, 1, 0));
  EXPECT_FALSE(ops::Apply(ops::kOpCount, &bits32, 1, 0));
  EXPECT_EQ(ops::SizeOf(ops::kNone), 0u);
  EXPECT_EQ(ops::SizeOf(ops::kOpCount), 0u);
}

TEST(Optix7AtomicsTest, ThreadsNotesCombinePerAddress) {
  alignas(8) static uint32_t counters[4];
  alignas(8) static uint64_t wide[2];
  BeginAtomicNotes();
  EXPECT_NE(*AtomicsNotedFlag(), 0u);
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t) {
    threads.emplace_back([t] {
      for (int i = 0; i < 10000; ++i) {
        NoteAtomic(&counters[i % 2], ops::kAdd32, 1, 0);
        NoteAtomic(&wide[0], ops::kMaxU64, static_cast<uint64_t>(t * 10000 + i), 0);
      }
      NoteAtomic(&counters[2], ops::kAdd32, 1, 0);
      NoteAtomic(&counters[2], ops::kNone, 0, 0);  // an atomicCAS too: bytes travel
      NoteAtomic(&counters[3], ops::kInc, 1, static_cast<uint32_t>(t == 0 ? 5 : 6));
      NoteAtomic(&wide[1], ops::kDec, 1, 9);
    });
  }
  for (std::thread& t : threads) t.join();
  const std::vector<CombinedAtomic> notes = EndAtomicNotes();
  EXPECT_EQ(*AtomicsNotedFlag(), 0u);
  ASSERT_EQ(notes.size(), 6u);
  for (size_t i = 1; i < notes.size(); ++i) EXPECT_LT(notes[i - 1].address, notes[i].address);
  auto find = [&](const void* p) -> CombinedAtomic {
    for (const CombinedAtomic& a : notes) {
      if (a.address == reinterpret_cast<uintptr_t>(p)) return a;
    }
    ADD_FAILURE() << "no note for " << p;
    return {};
  };
  EXPECT_EQ(find(&counters[0]).op, ops::kAdd32);
  EXPECT_EQ(find(&counters[0]).operand, 20000u);
  EXPECT_EQ(find(&counters[1]).operand, 20000u);
  EXPECT_EQ(find(&counters[2]).op, ops::kNone);
  EXPECT_EQ(find(&counters[3]).op, ops::kNone);  // two limits: the order matters
  EXPECT_EQ(find(&wide[0]).op, ops::kMaxU64);
  EXPECT_EQ(find(&wide[0]).operand, 39999u);
  EXPECT_EQ(find(&wide[1]).op, ops::kDec);
  EXPECT_EQ(find(&wide[1]).operand, 4u);
  EXPECT_EQ(find(&wide[1]).limit, 9u);

  // The next call starts with nothing noted.
  BeginAtomicNotes();
  NoteAtomic(&counters[0], ops::kAdd32, 7, 0);
  const std::vector<CombinedAtomic> next = EndAtomicNotes();
  ASSERT_EQ(next.size(), 1u);
  EXPECT_EQ(next[0].operand, 7u);
}

TEST(Optix7AtomicsTest, OnlyCombinedAtomicsInsideAllocationsAreSent) {
  const std::map<uint64_t, uint64_t> allocations = {{0x1000, 0x100}, {0x2000, 0x10}};
  const std::vector<CombinedAtomic> notes = {
      {0x0800, ops::kAdd32, 0, 1},      // before every allocation
      {0x1000, ops::kAdd32, 0, 1},      // first word
      {0x1010, ops::kNone, 0, 0},       // does not combine
      {0x10FC, ops::kAdd32, 0, 1},      // last word
      {0x10FC + 4, ops::kAdd32, 0, 1},  // just past
      {0x200C, ops::kAdd64, 0, 1},      // runs past its allocation's end
      {0x2008, ops::kAdd64, 0, 1},
  };
  std::vector<CombinedAtomic> sorted = notes;
  std::sort(sorted.begin(), sorted.end(),
            [](const CombinedAtomic& a, const CombinedAtomic& b) { return a.address < b.address; });
  const std::vector<CombinedAtomic> sent = AtomicsToSend(sorted, allocations);
  std::vector<uintptr_t> addresses;
  for (const CombinedAtomic& a : sent) addresses.push_back(a.address);
  EXPECT_EQ(addresses, (std::vector<uintptr_t>{0x1000, 0x10FC, 0x2008}));
}

TEST(Optix7AtomicsTest, RunsLeaveOutAtomicsBytes) {
  const std::vector<std::pair<uintptr_t, size_t>> runs = {{0x100, 0x20}, {0x200, 4}, {0x300, 8}};
  const std::vector<CombinedAtomic> atomics = {
      {0x100, ops::kAdd32, 0, 1},  // the run's first word
      {0x108, ops::kAdd64, 0, 1},  // its middle
      {0x200, ops::kAdd32, 0, 1},  // a whole run
      {0x280, ops::kAdd32, 0, 1},  // no run: nothing to cut
      {0x304, ops::kAdd32, 0, 1},  // a run's last word
  };
  const std::vector<std::pair<uintptr_t, size_t>> want = {{0x104, 4}, {0x110, 0x10}, {0x300, 4}};
  EXPECT_EQ(RunsWithoutAtomics(runs, atomics), want);
  EXPECT_EQ(RunsWithoutAtomics(runs, {}), runs);
}

}  // namespace
}  // namespace tessera::worker

// The word-at-a-time scan of written marks and changed bytes against the element-by-element one it
// replaced, on random marks, epochs and contents.
#include "written_scan.h"

#include <gtest/gtest.h>

#include <random>
#include <vector>

namespace tessera::worker {
namespace {

std::vector<ElementRun> Reference(const std::vector<unsigned char>& marks, size_t begin, size_t end,
                                  const MarkRange& range, const unsigned char* data,
                                  const unsigned char* before, size_t size) {
  std::vector<ElementRun> runs;
  for (size_t e = begin; e < end; ++e) {
    if (!range.Taken(marks[e])) continue;
    if (data != nullptr && std::memcmp(data + e * size, before + e * size, size) == 0) continue;
    AppendRun(runs, e, e + 1);
  }
  return runs;
}

std::vector<ElementRun> Scanned(const std::vector<unsigned char>& marks, size_t begin, size_t end,
                                const MarkRange& range, const unsigned char* data,
                                const unsigned char* before, size_t size) {
  std::vector<ElementRun> runs;
  ForEachTakenRun(marks.data(), begin, end, range, [&](size_t first, size_t stop) {
    if (data != nullptr) {
      AppendChanged(data, before, size, first, stop, runs);
    } else {
      AppendRun(runs, first, stop);
    }
  });
  return runs;
}

void ExpectSameRuns(const std::vector<ElementRun>& want, const std::vector<ElementRun>& got) {
  ASSERT_EQ(want.size(), got.size());
  for (size_t i = 0; i < want.size(); ++i) {
    EXPECT_EQ(want[i].begin, got[i].begin) << "run " << i;
    EXPECT_EQ(want[i].end, got[i].end) << "run " << i;
  }
}

TEST(WrittenScanTest, TakenBitsMatchTheRangeForEveryMarkAndBound) {
  for (int last = 0; last < 2; ++last) {
    for (int after = 0; after < 256; after += 17) {
      for (int upto = 0; upto < 256; upto += 13) {
        const MarkRange range{static_cast<unsigned char>(after), static_cast<unsigned char>(upto),
                              last != 0};
        for (int m = 0; m < 256; ++m) {
          const uint64_t word = static_cast<uint64_t>(m) << 24;  // byte 3
          const unsigned want = range.Taken(static_cast<unsigned char>(m)) ? 1u << 3 : 0u;
          // The other bytes are 0, never taken.
          ASSERT_EQ(TakenBits(word, range), want) << after << " " << upto << " " << m;
        }
      }
    }
  }
  EXPECT_EQ(TakenBits(~uint64_t{0}, MarkRange{0xFF, 0xFF, true}), 0u);
}

// Elements changed at the edges of the chunks compared as blocks, among equal ones.
TEST(WrittenScanTest, ChangedElementsAtChunkEdgesAreFound) {
  for (size_t size : {4, 12, 20}) {
    for (size_t changed : {0, 63, 64, 65, 127, 128, 199}) {
      const size_t n = 200;
      std::vector<unsigned char> marks(n, 1), before(n * size, 7), data = before;
      data[changed * size + size - 1] = 9;
      const MarkRange range{0, 1, false};
      for (size_t begin : {0, 1}) {
        const std::vector<ElementRun> runs =
            Scanned(marks, begin, n, range, data.data(), before.data(), size);
        ASSERT_EQ(runs.size(), changed >= begin ? 1u : 0u) << size << " " << changed;
        if (!runs.empty()) {
          EXPECT_EQ(runs[0].begin, changed);
        }
      }
    }
  }
}

TEST(WrittenScanTest, RunsMatchTheElementByElementScan) {
  std::mt19937 rng(28);
  for (int round = 0; round < 400; ++round) {
    const size_t n = 1 + rng() % 700;
    const size_t size = std::vector<size_t>{1, 2, 4, 8, 12, 16, 3, 20}[rng() % 8];
    std::vector<unsigned char> marks(n + 8);  // +8: scans that start unaligned
    const int style = static_cast<int>(rng() % 3);
    for (unsigned char& m : marks) {
      // Long runs of one mark (whole tiles), or marks that change every element.
      m = style == 0 ? static_cast<unsigned char>(rng() % 4)
                     : (rng() % 40 == 0 ? static_cast<unsigned char>(rng() % 6) : marks[0]);
    }
    std::vector<unsigned char> before((n + 8) * size), data;
    for (unsigned char& b : before) b = static_cast<unsigned char>(rng() % 3);
    data = before;
    const int changes = static_cast<int>(rng() % 4);  // none, a few bytes, most, rare elements
    for (size_t i = 0; i < data.size(); ++i) {
      if ((changes == 1 && rng() % 50 == 0) || (changes == 2 && rng() % 3 != 0)) ++data[i];
    }
    if (changes == 3) {  // equal chunks with changed elements between them
      for (size_t k = 0; k < 1 + n / 60; ++k) ++data[(rng() % (n + 8)) * size + rng() % size];
    }
    const size_t begin = rng() % 8, end = begin + n;
    const MarkRange range{static_cast<unsigned char>(rng() % 3),
                          static_cast<unsigned char>(1 + rng() % 4), rng() % 2 == 0};
    ExpectSameRuns(Reference(marks, begin, end, range, nullptr, nullptr, size),
                   Scanned(marks, begin, end, range, nullptr, nullptr, size));
    ExpectSameRuns(Reference(marks, begin, end, range, data.data(), before.data(), size),
                   Scanned(marks, begin, end, range, data.data(), before.data(), size));
    if (testing::Test::HasFailure()) {
      ADD_FAILURE() << "round " << round << ": n " << n << ", size " << size;
      return;
    }
  }
}

}  // namespace
}  // namespace tessera::worker

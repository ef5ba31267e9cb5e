// The device memory arena (reserved at a fixed address, committed and released by pages) and the
// allocator over it (cudaMalloc's alignment, first fit by address, frees that say what went wrong).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <vector>

#include "device_allocator.h"
#include "device_arena.h"

namespace tessera::memory {
namespace {

// A test's own range: well away from the default, so that tests in one process do not collide.
constexpr uintptr_t kTestBase = uintptr_t{0x300000000000};
constexpr size_t kTestSize = size_t{1} << 30;

TEST(DeviceArenaTest, ReservesExactlyWhereAskedAndCommitsZeroedPages) {
  auto arena = DeviceArena::Reserve(kTestBase, kTestSize);
  ASSERT_TRUE(arena.ok()) << arena.status();
  DeviceArena& a = **arena;
  EXPECT_EQ(a.base(), kTestBase);
  EXPECT_EQ(a.size(), kTestSize);
  const size_t page = DeviceArena::PageSize();
  const uintptr_t at = kTestBase + 5 * page + 100;
  ASSERT_TRUE(a.Commit(at, 3 * page).ok());
  auto* bytes = reinterpret_cast<unsigned char*>(at);
  for (size_t i = 0; i < 3 * page; ++i) ASSERT_EQ(bytes[i], 0) << i;
  std::memset(bytes, 0xAB, 3 * page);
  EXPECT_EQ(bytes[3 * page - 1], 0xAB);

  // Released pages come back as zeros; the partly covered first page keeps its bytes.
  ASSERT_TRUE(a.Release(at, 3 * page).ok());
  ASSERT_TRUE(a.Commit(at, 3 * page).ok());
  EXPECT_EQ(bytes[0], 0xAB);             // page 5: only partly inside the release
  EXPECT_EQ(bytes[page - 100], 0);       // page 6: wholly inside, released
  EXPECT_EQ(bytes[3 * page - 1], 0xAB);  // page 8: partly inside, kept
}

TEST(DeviceArenaTest, RefusesRangesItCannotHaveNamingThem) {
  auto first = DeviceArena::Reserve(kTestBase, kTestSize);
  ASSERT_TRUE(first.ok()) << first.status();
  auto second = DeviceArena::Reserve(kTestBase + 4096, 4096);  // overlaps the first
  ASSERT_FALSE(second.ok());
  EXPECT_EQ(second.status().code(), absl::StatusCode::kFailedPrecondition);
  EXPECT_NE(second.status().message().find("already mapped"), std::string::npos) << second.status();
  EXPECT_NE(second.status().message().find("TESSERA_DEVICE_MEMORY_BASE"), std::string::npos);

  EXPECT_EQ(DeviceArena::Reserve(kTestBase + kTestSize + 1, 4096).status().code(),
            absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(DeviceArena::Reserve(kTestBase + kTestSize, 0).status().code(),
            absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(DeviceArena::Reserve(~uintptr_t{0} - 4095, 8192).status().code(),
            absl::StatusCode::kInvalidArgument);  // wraps

  DeviceArena& a = **first;
  EXPECT_TRUE(a.Contains(kTestBase, kTestSize));
  EXPECT_TRUE(a.Contains(kTestBase + kTestSize - 1, 0));
  EXPECT_FALSE(a.Contains(kTestBase + kTestSize, 0));
  EXPECT_FALSE(a.Contains(kTestBase - 1, 1));
  EXPECT_FALSE(a.Contains(kTestBase + 8, kTestSize));
  EXPECT_EQ(a.Commit(kTestBase + kTestSize - 8, 16).code(), absl::StatusCode::kOutOfRange);
  EXPECT_EQ(a.Release(kTestBase - 4096, 4096).code(), absl::StatusCode::kOutOfRange);
}

TEST(DeviceArenaTest, AnArenaGoneLeavesItsRangeFree) {
  { ASSERT_TRUE(DeviceArena::Reserve(kTestBase, kTestSize).ok()); }
  EXPECT_TRUE(DeviceArena::Reserve(kTestBase, kTestSize).ok());
}

constexpr size_t kPage = 4096;

TEST(DeviceAllocatorTest, AlignsLikeCudaMallocAndFillsTheLowestAddressesFirst) {
  DeviceAllocator a(kTestBase, 1 << 20, kPage);
  auto p = a.Allocate(1);
  auto q = a.Allocate(300);
  auto r = a.Allocate(256);
  ASSERT_TRUE(p.ok() && q.ok() && r.ok());
  EXPECT_EQ(*p, kTestBase);
  EXPECT_EQ(*q, kTestBase + 256);
  EXPECT_EQ(*r, kTestBase + 768);  // 300 bytes take two 256-byte units
  EXPECT_EQ(a.bytes_in_use(), 1024u);
  EXPECT_EQ(a.allocation_count(), 3u);

  // A freed range is reused by the next allocation that fits, lowest first.
  ASSERT_TRUE(a.Free(*q).ok());
  auto s = a.Allocate(200);
  ASSERT_TRUE(s.ok());
  EXPECT_EQ(*s, kTestBase + 256);
  auto t = a.Allocate(400);  // does not fit the 256 bytes left of q's range
  ASSERT_TRUE(t.ok());
  EXPECT_EQ(*t, kTestBase + 1024);
}

TEST(DeviceAllocatorTest, TheSameCallsGiveTheSameAddresses) {
  // Allocations of many sizes with frees in between: the addresses depend on the calls alone.
  auto run = [] {
    DeviceAllocator a(kTestBase, 1 << 24, kPage);
    std::vector<uintptr_t> out;
    for (size_t i = 1; i < 200; ++i) {
      auto p = a.Allocate(i * 37 % 5000 + 1);
      EXPECT_TRUE(p.ok()) << p.status();
      out.push_back(*p);
      if (i % 3 == 0) {
        auto freed = a.Free(out[i - 2]);  // the one before last; each freed once
        EXPECT_TRUE(freed.ok()) << freed.status();
      }
    }
    return out;
  };
  const std::vector<uintptr_t> first = run();
  EXPECT_EQ(first, run());
  // Frees made room that later allocations took: not every address is new.
  EXPECT_LT(*std::max_element(first.begin(), first.end()), kTestBase + 200 * 5120);
}

TEST(DeviceAllocatorTest, FreesSayWhatWentWrong) {
  DeviceAllocator a(kTestBase, 1 << 20, kPage);
  auto p = a.Allocate(1000);
  ASSERT_TRUE(p.ok());
  auto inside = a.Free(*p + 8);
  ASSERT_FALSE(inside.ok());
  EXPECT_EQ(inside.status().code(), absl::StatusCode::kNotFound);
  EXPECT_NE(inside.status().message().find("inside the allocation"), std::string::npos)
      << inside.status();
  ASSERT_TRUE(a.Free(*p).ok());
  auto twice = a.Free(*p);
  ASSERT_FALSE(twice.ok());
  EXPECT_NE(twice.status().message().find("freed already"), std::string::npos) << twice.status();
  EXPECT_EQ(a.bytes_in_use(), 0u);
}

TEST(DeviceAllocatorTest, FindCoversExactlyTheBytesAsked) {
  DeviceAllocator a(kTestBase, 1 << 20, kPage);
  auto p = a.Allocate(100);
  ASSERT_TRUE(p.ok());
  ASSERT_NE(a.Find(*p, 100), nullptr);
  EXPECT_EQ(a.Find(*p + 40, 60)->address, *p);
  EXPECT_EQ(a.Find(*p + 99, 0)->size, 100u);
  EXPECT_EQ(a.Find(*p + 40, 61), nullptr);  // past the 100 bytes asked for
  EXPECT_EQ(a.Find(*p + 100, 0), nullptr);  // one past the end
  EXPECT_EQ(a.Find(*p - 1, 1), nullptr);
}

TEST(DeviceAllocatorTest, ExhaustionNamesWhatIsLeft) {
  DeviceAllocator a(kTestBase, 4096, kPage);
  ASSERT_TRUE(a.Allocate(1024).ok());
  auto p = a.Allocate(1024);
  ASSERT_TRUE(p.ok());
  ASSERT_TRUE(a.Allocate(1024).ok());
  ASSERT_TRUE(a.Free(*p).ok());
  auto big = a.Allocate(2048);
  ASSERT_FALSE(big.ok());
  EXPECT_EQ(big.status().code(), absl::StatusCode::kResourceExhausted);
  EXPECT_NE(big.status().message().find("largest free range holds 1024"), std::string::npos)
      << big.status();
  EXPECT_FALSE(a.Allocate(0).ok());
  EXPECT_FALSE(a.Allocate(8192).ok());
}

// A free gives back the pages that no live allocation touches, merged with free neighbours.
TEST(DeviceAllocatorTest, FreesReleaseOnlyPagesNoAllocationTouches) {
  DeviceAllocator a(kTestBase, 16 * kPage, kPage);
  auto p = a.Allocate(100);        // page 0
  auto q = a.Allocate(3 * kPage);  // 256 .. 256 + 3 pages: pages 0-3
  auto r = a.Allocate(100);        // page 3
  ASSERT_TRUE(p.ok() && q.ok() && r.ok());
  auto freed = a.Free(*q);
  ASSERT_TRUE(freed.ok());
  EXPECT_EQ(freed->allocation.size, 3 * kPage);
  EXPECT_EQ(freed->release_begin, kTestBase + kPage);  // pages 1 and 2: p and r touch 0 and 3
  EXPECT_EQ(freed->release_end, kTestBase + 3 * kPage);
  auto freed_p = a.Free(*p);  // page 0 now holds nothing
  ASSERT_TRUE(freed_p.ok());
  EXPECT_EQ(freed_p->release_begin, kTestBase);
  EXPECT_EQ(freed_p->release_end, kTestBase + kPage);
  auto small = a.Allocate(100);  // reuses page 0
  ASSERT_TRUE(small.ok());
  EXPECT_EQ(*small, kTestBase);
  auto freed_small = a.Free(*small);
  ASSERT_TRUE(freed_small.ok());
  EXPECT_EQ(freed_small->release_begin, kTestBase);
}

}  // namespace
}  // namespace tessera::memory

// The result arena's protocol without processes: the host's leases, the worker's writer, and a
// worker still writing for a call the host gave up on.
#include "transport/result_arena.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <string>

namespace tessera::transport {
namespace {

struct Pair {
  std::unique_ptr<ResultArena> host, worker;  // two mappings of one arena, as in two processes
};

Pair MakePair() {
  Pair p;
  auto host = ResultArena::Create(64 << 10);
  EXPECT_TRUE(host.ok()) << host.status();
  p.host = *std::move(host);
  auto worker = ResultArena::Map(dup(p.host->fd()));
  EXPECT_TRUE(worker.ok()) << worker.status();
  p.worker = *std::move(worker);
  return p;
}

v1::LaunchRequest Request(const ResultArena::Lease& lease) {
  v1::LaunchRequest r;
  r.set_arena_slot(static_cast<uint32_t>(lease.slot));
  r.set_arena_token(lease.token);
  return r;
}

v1::TileResult Result(size_t large, size_t small) {
  v1::TileResult r;
  r.add_regions()->set_data(std::string(large, 'L'));
  r.add_regions()->set_data(std::string(small, 's'));
  return r;
}

TEST(ResultArena, LargeRegionsTravelThroughTheArenaAndComeBack) {
  Pair p = MakePair();
  ResultArena::Lease lease = p.host->Acquire();
  ASSERT_EQ(lease.slot, 0);
  ResultArena::Writer writer(p.worker.get(), Request(lease));
  v1::TileResult r = Result(10000, 100);
  writer.Move(&r);
  EXPECT_TRUE(r.regions(0).data().empty());
  EXPECT_EQ(r.regions(0).arena_size(), 10000u);
  EXPECT_EQ(r.regions(1).data(), std::string(100, 's')) << "small regions stay in the message";
  ASSERT_TRUE(ResultArena::Restore(p.host.get(), lease, &r).ok());
  EXPECT_EQ(r.regions(0).data(), std::string(10000, 'L'));
  EXPECT_EQ(r.regions(0).arena_size(), 0u);
  EXPECT_EQ(p.host->restored_bytes(), 10000u);
  p.host->Release(lease);
}

TEST(ResultArena, WhatDoesNotFitTheSlotStaysInTheMessage) {
  Pair p = MakePair();
  ResultArena::Lease lease = p.host->Acquire();
  ResultArena::Writer writer(p.worker.get(), Request(lease));
  v1::TileResult r = Result(p.host->slot_bytes() + 1, 0);
  writer.Move(&r);
  EXPECT_EQ(r.regions(0).arena_size(), 0u);
  EXPECT_EQ(r.regions(0).data().size(), p.host->slot_bytes() + 1);
}

TEST(ResultArena, AWorkerOfACallTheHostGaveUpOnCannotWriteTheNextLease) {
  Pair p = MakePair();
  ResultArena::Lease old_lease = p.host->Acquire();
  ResultArena::Writer late(p.worker.get(), Request(old_lease));
  p.host->Release(old_lease);  // the call was cancelled; its worker keeps sending
  ResultArena::Lease next = p.host->Acquire();
  ASSERT_EQ(next.slot, old_lease.slot);
  ASSERT_NE(next.token, old_lease.token);
  ResultArena::Writer current(p.worker.get(), Request(next));
  v1::TileResult mine = Result(8192, 0);
  current.Move(&mine);
  v1::TileResult stale = Result(8192, 0);
  late.Move(&stale);
  EXPECT_EQ(stale.regions(0).arena_size(), 0u) << "the late writer keeps its bytes";
  ASSERT_TRUE(ResultArena::Restore(p.host.get(), next, &mine).ok());
  EXPECT_EQ(mine.regions(0).data(), std::string(8192, 'L'));
}

TEST(ResultArena, EverySlotLeasedMeansNoSlot) {
  Pair p = MakePair();
  for (int i = 0; i < ResultArena::kSlots; ++i) EXPECT_EQ(p.host->Acquire().slot, i);
  EXPECT_EQ(p.host->Acquire().slot, -1);
  ResultArena::Writer none(p.worker.get(), Request(ResultArena::Lease{}));
  v1::TileResult r = Result(8192, 0);
  none.Move(&r);
  EXPECT_EQ(r.regions(0).arena_size(), 0u);
}

TEST(ResultArena, ARegionOutsideItsSlotIsAnError) {
  Pair p = MakePair();
  ResultArena::Lease lease = p.host->Acquire();
  v1::TileResult r;
  v1::BufferRegion* region = r.add_regions();
  region->set_arena_offset(p.host->slot_bytes() - 10);
  region->set_arena_size(11);
  absl::Status s = ResultArena::Restore(p.host.get(), lease, &r);
  EXPECT_EQ(s.code(), absl::StatusCode::kDataLoss) << s;
  EXPECT_NE(s.message().find("outside its slot"), std::string::npos) << s;
  region->set_arena_offset(0);
  region->set_arena_size(1);
  EXPECT_FALSE(ResultArena::Restore(p.host.get(), ResultArena::Lease{}, &r).ok())
      << "no lease, no arena bytes";
  s = ResultArena::Restore(nullptr, ResultArena::Lease{}, &r);
  EXPECT_EQ(s.code(), absl::StatusCode::kDataLoss) << "a worker given no arena: " << s;
}

TEST(ResultArena, ADescriptorThatIsNoArenaIsRefused) {
  int fds[2];
  ASSERT_EQ(pipe(fds), 0);
  EXPECT_FALSE(ResultArena::Map(fds[0]).ok());
  close(fds[0]);
  close(fds[1]);
}

}  // namespace
}  // namespace tessera::transport

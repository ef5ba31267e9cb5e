#include "tessera/scheduler/result_pool.h"

#include <gtest/gtest.h>

#include <string>

namespace tessera::scheduler {
namespace {

v1::TileResult WithRegion(size_t bytes) {
  v1::TileResult r;
  r.set_tile_index(7);
  r.add_regions()->set_data(std::string(bytes, 'x'));
  return r;
}

// Each test takes back what it put in: the pool is process-wide.
TEST(ResultPoolTest, RecycledMessagesComeBackEmptyWithTheirBuffers) {
  RecycleTileResult(WithRegion(1 << 20));
  v1::TileResult reused = TakeTileResult();
  EXPECT_EQ(reused.ByteSizeLong(), 0u) << "cleared";
  EXPECT_EQ(reused.regions_size(), 0);
  // Packing or parsing into it reuses the region and its buffer.
  EXPECT_GE(reused.add_regions()->mutable_data()->capacity(), size_t{1} << 20);
}

TEST(ResultPoolTest, SmallMessagesAndOverflowAreNotKept) {
  RecycleTileResult(WithRegion(100));
  EXPECT_LT(TakeTileResult().add_regions()->mutable_data()->capacity(), 100u);
  // The pool holds at most kMaxPooledResultBytes: one message larger than that is dropped.
  RecycleTileResult(WithRegion(kMaxPooledResultBytes + 1));
  EXPECT_LT(TakeTileResult().add_regions()->mutable_data()->capacity(), kMaxPooledResultBytes);
}

}  // namespace
}  // namespace tessera::scheduler

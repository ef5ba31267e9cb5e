#include "tessera/scheduler/tiling.h"

#include <gtest/gtest.h>

#include <algorithm>

namespace tessera::scheduler {
namespace {

TEST(TilingTest, SplitsGridsOfEachDimensionality) {
  EXPECT_EQ(MaxTileSize(1), std::vector<uint64_t>({4096}));
  EXPECT_EQ(MaxTileSize(2), std::vector<uint64_t>({64, 64}));
  EXPECT_EQ(MaxTileSize(3), std::vector<uint64_t>({16, 16, 4}));

  auto tiles = MakeTiles({100, 70}, {64, 64});
  ASSERT_EQ(tiles.size(), 4u);
  EXPECT_EQ(tiles[1].origin(0), 64u);
  EXPECT_EQ(tiles[1].size(0), 36u);
  EXPECT_EQ(tiles[2].origin(1), 64u);
  EXPECT_EQ(tiles[2].size(1), 6u);
  uint64_t covered = 0;
  for (size_t i = 0; i < tiles.size(); ++i) {
    EXPECT_EQ(tiles[i].index(), i);
    covered += tiles[i].size(0) * tiles[i].size(1);
  }
  EXPECT_EQ(covered, 100u * 70u);

  auto one = MakeTiles({10000}, {4096});
  ASSERT_EQ(one.size(), 3u);
  EXPECT_EQ(one[2].size(0), 10000u - 8192u);
  EXPECT_EQ(one[2].origin_size(), 1);

  auto three = MakeTiles({17, 16, 9}, {16, 16, 4});
  EXPECT_EQ(three.size(), 2u * 1u * 3u);
  EXPECT_EQ(three.back().size(2), 1u);

  EXPECT_TRUE(MakeTiles({0, 5}, {64, 64}).empty());
  EXPECT_TRUE(MakeTiles({}, {}).empty());
  EXPECT_EQ(MakeTiles({3, 3}, {0, 0}).size(), 9u);  // tile size 0 reads as 1
}

TEST(TilingTest, OneDeviceTakesFewerLargerTiles) {
  // Its threads balance with pieces of tiles: 16 tiles a thread, not 64.
  EXPECT_EQ(ChooseTileSize({1920, 1080}, 16, kTilesPerThreadOneDevice),
            std::vector<uint64_t>({64, 64}));
  EXPECT_EQ(ChooseTileSize({1024, 1024}, 32, kTilesPerThreadOneDevice),
            std::vector<uint64_t>({32, 32}));
  EXPECT_EQ(ChooseTileSize({1024, 1024}, 32), std::vector<uint64_t>({16, 16}));
}

TEST(TilingTest, ChoosesSmallerTilesForManyThreads) {
  // 1920x1080 has 510 tiles of 64x64: enough for 16 threads (8 each), not for 128.
  EXPECT_EQ(ChooseTileSize({1920, 1080}, 2), std::vector<uint64_t>({64, 64}));
  EXPECT_EQ(ChooseTileSize({1920, 1080}, 16), std::vector<uint64_t>({32, 32}));
  EXPECT_EQ(ChooseTileSize({1920, 1080}, 128), std::vector<uint64_t>({16, 16}));
  // Never below 16x16, however small the launch.
  EXPECT_EQ(ChooseTileSize({20, 20}, 64), std::vector<uint64_t>({16, 16}));
  EXPECT_EQ(ChooseTileSize({100000}, 2), std::vector<uint64_t>({512}));
  EXPECT_EQ(ChooseTileSize({1000000}, 2), std::vector<uint64_t>({4096}));
  EXPECT_EQ(ChooseTileSize({1000}, 4), std::vector<uint64_t>({256}));
  EXPECT_EQ(ChooseTileSize({64, 64, 64}, 1024), std::vector<uint64_t>({8, 8, 2}));
}

// The largest launches (every dimension up to 2^32 - 1) get at most kMaxTiles tiles, which still
// cover the grid exactly once.
TEST(TilingTest, HugeLaunchesGetBoundedTileLists) {
  constexpr uint64_t kMax = 0xFFFFFFFFu;
  auto one = MakeTiles({kMax}, {4096});
  ASSERT_LE(one.size(), kMaxTiles);
  EXPECT_GT(one.size(), kMaxTiles / 2);  // grown no more than needed
  uint64_t covered = 0;
  for (const v1::Tile& t : one) {
    EXPECT_EQ(t.origin(0), covered);
    covered += t.size(0);
  }
  EXPECT_EQ(covered, kMax);

  for (const std::vector<uint64_t>& dims : std::vector<std::vector<uint64_t>>{
           {kMax, kMax}, {70000, 70000}, {kMax, 3}, {kMax, kMax, kMax}, {5, kMax, 7}}) {
    auto tiles = MakeTiles(dims, MaxTileSize(dims.size()));
    ASSERT_LE(tiles.size(), kMaxTiles);
    ASSERT_FALSE(tiles.empty());
    // The last tile ends at the far corner.
    const v1::Tile& last = tiles.back();
    for (size_t d = 0; d < dims.size(); ++d) EXPECT_EQ(last.origin(d) + last.size(d), dims[d]);
    EXPECT_EQ(last.index(), tiles.size() - 1);
  }
  // A launch that fits keeps the tiles it asked for.
  EXPECT_EQ(MakeTiles({1920, 1080}, {8, 8}).size(), 240u * 135u);
}

// A tile of a launch of more than 2^64 indices counts UINT64_MAX, never a wrapped 0 (which the
// dispatcher divides by).
TEST(TilingTest, TileIndicesSaturate) {
  for (const std::vector<uint64_t>& dims : std::vector<std::vector<uint64_t>>{
           {1u << 31, 1u << 31, 1u << 31}, {0xFFFFFFFFu, 0xFFFFFFFFu, 0xFFFFFFFFu}}) {
    auto tiles = MakeTiles(dims, MaxTileSize(3));
    ASSERT_FALSE(tiles.empty());
    EXPECT_EQ(TileIndices(tiles.front()), UINT64_MAX);
  }
  v1::Tile t;
  for (uint64_t s : {uint64_t{1} << 22, uint64_t{1} << 21, uint64_t{1} << 21}) t.add_size(s);
  EXPECT_EQ(TileIndices(t), UINT64_MAX);  // exactly 2^64
}

// Sizes past a launch's extent cut it into the same tiles, and compare equal as cut.
TEST(TilingTest, EffectiveTileSizeClampsToTheLaunch) {
  EXPECT_EQ(EffectiveTileSize({37, 29}, {1000, 1000}), std::vector<uint64_t>({37, 29}));
  EXPECT_EQ(EffectiveTileSize({37, 29}, {64, 64}), EffectiveTileSize({37, 29}, {2000, 37}));
  EXPECT_NE(EffectiveTileSize({37, 29}, {16, 16}), EffectiveTileSize({37, 29}, {64, 64}));
  EXPECT_TRUE(EffectiveTileSize({0, 5}, {1, 1}).empty());
}

// Sides of extent 1 do not shrink tiles to a few indices: 1x1xN is tiled like N.
TEST(TilingTest, DegenerateSidesAreTiledAsFewerDimensions) {
  EXPECT_EQ(ChooseTileSize({1, 1, 1u << 22}, 2), std::vector<uint64_t>({1, 1, 4096}));
  EXPECT_EQ(ChooseTileSize({1u << 22, 1, 1}, 2), std::vector<uint64_t>({4096, 1, 1}));
  EXPECT_EQ(ChooseTileSize({1, 1u << 22}, 2), std::vector<uint64_t>({1, 4096}));
  EXPECT_EQ(ChooseTileSize({2048, 1, 2048}, 2), std::vector<uint64_t>({64, 1, 64}));
  EXPECT_EQ(ChooseTileSize({1, 1, 1}, 2), std::vector<uint64_t>({8, 8, 2}));  // as before
}

TEST(TilingTest, ParsesOverrides) {
  EXPECT_EQ(*ParseTileSize("32x16"), std::vector<uint64_t>({32, 16}));
  EXPECT_EQ(*ParseTileSize("7"), std::vector<uint64_t>({7}));
  EXPECT_EQ(*ParseTileSize("4x4x2"), std::vector<uint64_t>({4, 4, 2}));
  for (const char* bad : {"", "0", "x", "3x", "-1", "1x2x3x4", "abc"}) {
    absl::StatusOr<std::vector<uint64_t>> parsed = ParseTileSize(bad);
    EXPECT_FALSE(parsed.ok()) << bad;
    if (!parsed.ok()) {
      EXPECT_NE(parsed.status().message().find("tile size"), std::string::npos);
    }
  }
}

}  // namespace
}  // namespace tessera::scheduler

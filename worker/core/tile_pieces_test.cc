#include "tile_pieces.h"

#include <gtest/gtest.h>

#include "tessera/scheduler/tiling.h"

namespace tessera::worker {
namespace {

google::protobuf::RepeatedPtrField<v1::Tile> Tiles(const std::vector<uint64_t>& dims,
                                                   const std::vector<uint64_t>& size) {
  google::protobuf::RepeatedPtrField<v1::Tile> out;
  for (v1::Tile& t : scheduler::MakeTiles(dims, size)) *out.Add() = std::move(t);
  return out;
}

// Every launch index of the tiles lands in exactly one piece, and pieces of a tile are adjacent.
void ExpectExactCover(const std::vector<TilePiece>& pieces, const Index3& dims) {
  std::vector<int> hits(size_t{dims[0]} * dims[1] * dims[2], 0);
  for (const TilePiece& p : pieces) {
    for (uint32_t z = p.origin[2]; z < p.origin[2] + p.size[2] && z < dims[2]; ++z)
      for (uint32_t y = p.origin[1]; y < p.origin[1] + p.size[1] && y < dims[1]; ++y)
        for (uint32_t x = p.origin[0]; x < p.origin[0] + p.size[0] && x < dims[0]; ++x)
          ++hits[(size_t{z} * dims[1] + y) * dims[0] + x];
  }
  for (size_t i = 0; i < hits.size(); ++i) ASSERT_EQ(hits[i], 1) << "launch index " << i;
  for (size_t i = 1; i < pieces.size(); ++i) EXPECT_LE(pieces[i - 1].tile, pieces[i].tile);
}

TEST(SplitTiles, OneThreadKeepsTilesWhole) {
  auto tiles = Tiles({100, 70}, {64, 64});
  std::vector<TilePiece> pieces = SplitTiles(tiles, {100, 70, 1}, 1);
  ASSERT_EQ(pieces.size(), 4u);
  EXPECT_EQ(pieces[3].origin, (Index3{64, 64, 0}));
  EXPECT_EQ(pieces[3].size, (Index3{36, 6, 1}));  // MakeTiles clips edge tiles
}

TEST(SplitTiles, ManyThreadsSplitRowsAndCoverEveryIndexOnce) {
  const Index3 dims{1920, 1080, 1};
  auto tiles = Tiles({1920, 1080}, {64, 64});
  std::vector<TilePiece> pieces = SplitTiles(tiles, dims, 16);
  EXPECT_GE(pieces.size(), size_t{kPiecesPerThread} * 16);
  ExpectExactCover(pieces, dims);
}

TEST(SplitTiles, SmallLaunchesKeepPiecesOfHundredsOfIndices) {
  const Index3 dims{256, 256, 1};
  std::vector<TilePiece> pieces = SplitTiles(Tiles({256, 256}, {16, 16}), dims, 32);
  EXPECT_EQ(pieces.size(), 256u * 256u / kLeastPieceIndices);
  ExpectExactCover(pieces, dims);
  // Still a few pieces per thread where the launch has fewer indices than that.
  pieces = SplitTiles(Tiles({64, 64}, {16, 16}), {64, 64, 1}, 32);
  EXPECT_EQ(pieces.size(), size_t{kLeastPiecesPerThread} * 32);
  ExpectExactCover(pieces, {64, 64, 1});
}

TEST(SplitTiles, EdgeTilesSplitOnlyTheirRowsInsideTheLaunch) {
  const Index3 dims{10, 5, 1};
  auto tiles = Tiles({10, 5}, {8, 8});
  std::vector<TilePiece> pieces = SplitTiles(tiles, dims, 64);
  EXPECT_EQ(pieces.size(), 10u);  // two tiles of five rows each
  ExpectExactCover(pieces, dims);
  // A batched launch's: split at the batch blocks' rows, 0-3 and 4.
  pieces = SplitTiles(tiles, dims, 64, /*whole_blocks=*/true);
  EXPECT_EQ(pieces.size(), 4u);
  ExpectExactCover(pieces, dims);
}

TEST(SplitTiles, PiecesBeginAtBatchBlocks) {
  const Index3 dims{1920, 1080, 1};
  for (const TilePiece& p : SplitTiles(Tiles({1920, 1080}, {64, 64}), dims, 64, true)) {
    EXPECT_EQ(p.origin[1] % 4, 0u);
  }
  for (const TilePiece& p : SplitTiles(Tiles({100000}, {4096}), {100000, 1, 1}, 64, true)) {
    EXPECT_EQ(p.origin[0] % 16, 0u);
  }
}

TEST(SplitTiles, OneAndThreeDimensionalLaunches) {
  ExpectExactCover(SplitTiles(Tiles({1000}, {256}), {1000, 1, 1}, 8), {1000, 1, 1});
  ExpectExactCover(SplitTiles(Tiles({20, 12, 3}, {8, 8, 2}), {20, 12, 3}, 8), {20, 12, 3});
}

}  // namespace
}  // namespace tessera::worker

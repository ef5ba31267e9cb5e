#include "tile_pieces.h"

#include <algorithm>

#include "batch_block.h"
#include "tessera/scheduler/tiling.h"

namespace tessera::worker {

std::vector<TilePiece> SplitTiles(const google::protobuf::RepeatedPtrField<v1::Tile>& tiles,
                                  const Index3& dims, int threads, bool whole_blocks) {
  std::vector<TilePiece> pieces;
  if (tiles.empty()) return pieces;
  const int axis = dims[1] > 1 || dims[2] > 1 ? 1 : 0;  // rows of 2D/3D tiles, runs of 1D ones
  uint64_t indices = 0;
  for (const v1::Tile& tile : tiles) indices += scheduler::TileIndices(tile);
  const uint64_t wanted = threads > 1
                              ? std::clamp<uint64_t>(indices / kLeastPieceIndices,
                                                     uint64_t{kLeastPiecesPerThread} * threads,
                                                     uint64_t{kPiecesPerThread} * threads)
                              : 1;
  const uint64_t per_tile = std::max<uint64_t>(1, (wanted + tiles.size() - 1) / tiles.size());
  pieces.reserve(tiles.size() * std::min<uint64_t>(per_tile, 64));
  for (int t = 0; t < tiles.size(); ++t) {
    const v1::Tile& tile = tiles[t];
    TilePiece whole;
    whole.tile = t;
    // Clipped to the launch in 64 bits: an origin or size past 32 bits must not wrap into it.
    for (int i = 0; i < tile.origin_size() && i < 3; ++i) {
      whole.origin[i] = static_cast<uint32_t>(std::min<uint64_t>(tile.origin(i), dims[i]));
    }
    for (int i = 0; i < tile.size_size() && i < 3; ++i) {
      whole.size[i] =
          static_cast<uint32_t>(std::min<uint64_t>(tile.size(i), dims[i] - whole.origin[i]));
    }
    // Rows inside the launch, in bands of whole blocks.
    const uint64_t begin = whole.origin[axis];
    const uint64_t end = std::min<uint64_t>(begin + whole.size[axis], dims[axis]);
    const uint64_t block = !whole_blocks ? 1
                           : axis == 1   ? BatchBlock(dims)[1]
                                         : BatchBlock(dims)[0];
    const uint64_t first = begin / block, last = end > begin ? (end + block - 1) / block : first;
    const uint64_t blocks = last - first;
    const uint64_t n = std::max<uint64_t>(1, std::min(per_tile, blocks));
    for (uint64_t k = 0; k < n; ++k) {
      TilePiece p = whole;
      const uint64_t from = std::max(begin, (first + blocks * k / n) * block);
      const uint64_t to = std::min(end, (first + blocks * (k + 1) / n) * block);
      p.origin[axis] = static_cast<uint32_t>(from);
      p.size[axis] = static_cast<uint32_t>(n == 1 ? whole.size[axis] : to - from);
      pieces.push_back(p);
    }
  }
  return pieces;
}

}  // namespace tessera::worker

// Pieces of a device call's tiles for its threads. The scheduler's tiles are the unit of
// assignment and transfer, sized for the device count; a device with many threads splits them
// further so that its threads still balance when a few tiles cost far more than the rest (a
// glass object in one corner of the image): the last piece to start is short, so no thread waits
// long for the others at the end of a call.
#ifndef TESSERA_WORKER_CORE_TILE_PIECES_H_
#define TESSERA_WORKER_CORE_TILE_PIECES_H_

#include <vector>

#include "runtime.h"
#include "tessera/v1/launch.pb.h"

namespace tessera::worker {

struct TilePiece {
  int tile = 0;  // index into the call's tiles
  Index3 origin{0, 0, 0}, size{1, 1, 1};
};

// About this many pieces per thread in a call (fewer when the tiles have fewer rows)...
inline constexpr int kPiecesPerThread = 128;
// ...but none much smaller than this many launch indices while each thread still gets
// kLeastPiecesPerThread: a piece costs its thread a few microseconds of its own (starting the
// tile, its interrupt slot, counting it done), as much as 16 primary rays, and a 256x256 launch
// on 32 threads made 4,096 pieces of 16 indices.
inline constexpr uint64_t kLeastPieceIndices = 256;
inline constexpr int kLeastPiecesPerThread = 8;

// Splits every tile of `tiles` into bands of whole rows (along y for 2D and 3D launches, along x
// for 1D), as many per tile as make about kPiecesPerThread * threads pieces in all. With
// `whole_blocks` (batched launches), bands begin and end at the launch grid's batch blocks
// (batch_block.h: every fourth row, every sixteenth index in 1D) or the tile's edges, so that no
// thread count splits a block the tile holds whole. A tile is never split when threads is 1.
// Pieces of a tile are adjacent in the result, in row order, and clipped to `dims`.
std::vector<TilePiece> SplitTiles(const google::protobuf::RepeatedPtrField<v1::Tile>& tiles,
                                  const Index3& dims, int threads, bool whole_blocks = false);

}  // namespace tessera::worker

#endif  // TESSERA_WORKER_CORE_TILE_PIECES_H_

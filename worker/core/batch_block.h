// The blocks of the launch grid that batched tracing runs together (optix7_batch.h): aligned to
// the grid, so that which launch indices share a packet depends on the launch alone. A batched
// launch's tile pieces are cut at block boundaries (tile_pieces.h) and the tile sizes the
// scheduler picks (powers of two from 16) are whole blocks, so no device set or thread count
// splits one; a TESSERA_TILE_SIZE that is not cuts blocks at tile edges, the same on every device
// set.
#ifndef TESSERA_WORKER_CORE_BATCH_BLOCK_H_
#define TESSERA_WORKER_CORE_BATCH_BLOCK_H_

#include "runtime.h"

namespace tessera::worker {

// 4x4 launch indices of one z slice in 2D and 3D launches, 16 in a row in 1D ones: one 16-wide
// Embree packet, square where the launch has rows (coherent primary rays).
inline Index3 BatchBlock(const Index3& dims) {
  constexpr uint32_t kSide = 4, kRun = 16;
  return dims[1] > 1 || dims[2] > 1 ? Index3{kSide, kSide, 1} : Index3{kRun, 1, 1};
}

}  // namespace tessera::worker

#endif  // TESSERA_WORKER_CORE_BATCH_BLOCK_H_

// The blocks of the launch grid that batched tracing runs together (optix7_batch.h): aligned to
// the grid, so that which launch indices share a packet depends on the launch alone. Tile pieces
// are cut at block boundaries (tile_pieces.h) and the scheduler's tiles are whole blocks
// (scheduler/tiling.h), so no device set or thread count splits one.
#ifndef TESSERA_WORKER_CORE_BATCH_BLOCK_H_
#define TESSERA_WORKER_CORE_BATCH_BLOCK_H_

#include "runtime.h"
#include "tessera/scheduler/tiling.h"

namespace tessera::worker {

// 4x4 launch indices of one z slice in 2D and 3D launches, 16 in a row in 1D ones: one 16-wide
// Embree packet, square where the launch has rows (coherent primary rays).
inline Index3 BatchBlock(const Index3& dims) {
  constexpr auto kSide = static_cast<uint32_t>(scheduler::kBatchBlockSide);
  constexpr auto kRun = static_cast<uint32_t>(scheduler::kBatchBlockRun);
  return dims[1] > 1 || dims[2] > 1 ? Index3{kSide, kSide, 1} : Index3{kRun, 1, 1};
}

}  // namespace tessera::worker

#endif  // TESSERA_WORKER_CORE_BATCH_BLOCK_H_

// The blocks of the launch grid that batched tracing runs together (optix7_batch.h): aligned to
// the grid, so that which launch indices share a packet depends on the launch alone. A batched
// launch's tile pieces are cut at block boundaries (tile_pieces.h) and the tile sizes the
// scheduler picks (powers of two from 16) are whole blocks, so no device set or thread count
// splits one; a TESSERA_TILE_SIZE that is not cuts blocks at tile edges, the same on every device
// set.
#ifndef TESSERA_WORKER_CORE_BATCH_BLOCK_H_
#define TESSERA_WORKER_CORE_BATCH_BLOCK_H_

#include <algorithm>
#include <atomic>

#include "runtime.h"

namespace tessera::worker {

// 4x4 launch indices of one z slice in 2D and 3D launches, 16 in a row in 1D ones: one 16-wide
// Embree packet, square where the launch has rows (coherent primary rays).
inline Index3 BatchBlock(const Index3& dims) {
  constexpr uint32_t kSide = 4, kRun = 16;
  return dims[1] > 1 || dims[2] > 1 ? Index3{kSide, kSide, 1} : Index3{kRun, 1, 1};
}

// Calls f(from, to) for each block of the launch grid clipped to the launch indices [origin,
// origin + size) of `dims` ([from, to) in each dimension, one z slice), row of blocks by row;
// false when a cancel or a failure elsewhere ended the launch first.
template <typename F>
bool ForEachBlock(const Index3& origin, const Index3& size, const Index3& dims,
                  const std::atomic<bool>& cancel, const std::atomic<bool>& stop, F&& f) {
  const Index3 end{std::min(origin[0] + size[0], dims[0]), std::min(origin[1] + size[1], dims[1]),
                   std::min(origin[2] + size[2], dims[2])};
  const Index3 block = BatchBlock(dims);
  for (uint32_t z = origin[2]; z < end[2]; ++z) {
    for (uint32_t y = origin[1] / block[1] * block[1]; y < end[1]; y += block[1]) {
      for (uint32_t x = origin[0] / block[0] * block[0]; x < end[0]; x += block[0]) {
        if (cancel.load(std::memory_order_relaxed) || stop.load(std::memory_order_relaxed)) {
          return false;
        }
        f(Index3{std::max(x, origin[0]), std::max(y, origin[1]), z},
          Index3{std::min(x + block[0], end[0]), std::min(y + block[1], end[1]), z + 1});
      }
    }
  }
  return true;
}

}  // namespace tessera::worker

#endif  // TESSERA_WORKER_CORE_BATCH_BLOCK_H_

// Splits a launch grid into tiles of its own dimensionality so devices can balance work.
#ifndef TESSERA_API_SRC_TILING_H_
#define TESSERA_API_SRC_TILING_H_

#include <cstdint>
#include <vector>

#include "tessera/v1/launch.pb.h"

namespace tessera::api {

// 4096 (1D), 64x64 (2D), 16x16x4 (3D).
std::vector<uint64_t> DefaultTileSize(size_t dimensionality);

// Tiles covering `dims` (1..3 entries) in x-fastest order, numbered from 0; edge tiles are
// clipped. Empty when any dimension is 0. `tile_size` has one entry per dimension (0 reads as 1).
std::vector<v1::Tile> MakeTiles(const std::vector<uint64_t>& dims,
                                const std::vector<uint64_t>& tile_size);

}  // namespace tessera::api

#endif  // TESSERA_API_SRC_TILING_H_

// Splits a launch grid into tiles of its own dimensionality (OptiX guide ch. 9: work follows the
// launch's shape), sized so that every thread of every device gets several tiles to balance.
#ifndef TESSERA_SCHEDULER_TILING_H_
#define TESSERA_SCHEDULER_TILING_H_

#include <cstdint>
#include <vector>

#include "absl/status/statusor.h"
#include "absl/strings/string_view.h"
#include "tessera/v1/launch.pb.h"

namespace tessera::scheduler {

// The largest tiles: 4096 (1D), 64x64 (2D), 16x16x4 (3D).
std::vector<uint64_t> MaxTileSize(size_t dimensionality);

// Tiles per thread a launch on several devices aims for: fewer leave devices idle at the end of
// a launch, waiting for the last expensive tiles (on 16 cores, 8 per thread, 64x64 tiles at
// 1920x1080, lost 20% of the tracing time to that tail, 64 per thread about 5%).
inline constexpr uint64_t kTilesPerThread = 64;
// On one device, whose threads balance among themselves with pieces of tiles
// (worker/core/tile_pieces.h), tiles only feed its calls, and each costs the host and the device
// bookkeeping of its own: 4,096 tiles (16x16 at 1024x1024, 32 threads) took ~1.3 ms to make,
// queue and take before a 14 ms launch's call began.
inline constexpr uint64_t kTilesPerThreadOneDevice = 16;

// A tile size for `dims` on devices with `total_threads` threads in all: the largest tiles that
// still give every thread about `tiles_per_thread` tiles, halving no further than 256 (1D),
// 16x16 (2D) or 8x8x2 (3D) — below that, per-tile overhead outweighs balance. Sides of extent 1
// get 1 and the others are chosen as for a launch of fewer dimensions (1x1xN as N, Nx1xM as NxM).
std::vector<uint64_t> ChooseTileSize(const std::vector<uint64_t>& dims, int total_threads,
                                     uint64_t tiles_per_thread = kTilesPerThread);

// Parses an override such as "32x32", "4096" or "16x16x4" (TESSERA_TILE_SIZE); one entry per
// launch dimension is used, missing ones repeat the last. INVALID_ARGUMENT names the bad text.
absl::StatusOr<std::vector<uint64_t>> ParseTileSize(absl::string_view text);

// The most tiles a launch is cut into: a tile list costs memory up front (about 150 bytes a
// tile), and a launch of 2^32 indices in tiles of 4096 would otherwise take a gigabyte before it
// traced a ray. Far more than balance needs (64 per thread).
inline constexpr uint64_t kMaxTiles = uint64_t{1} << 18;

// Tiles covering `dims` (1..3 entries) in x-fastest order, numbered from 0; edge tiles are
// clipped. Empty when any dimension is 0. `tile_size` has one entry per dimension (0 reads as 1);
// where it would give more than kMaxTiles tiles, tiles grow (doubling along the dimension with
// the most tiles) until it does not.
std::vector<v1::Tile> MakeTiles(const std::vector<uint64_t>& dims,
                                const std::vector<uint64_t>& tile_size);

// The tile size MakeTiles cuts `dims` with for `tile_size`: each side clamped to 1..its extent,
// grown where the launch would get more than kMaxTiles tiles. Two sizes with the same effective
// size cut a launch into the same tiles. Empty when `dims` is empty or has a 0.
std::vector<uint64_t> EffectiveTileSize(const std::vector<uint64_t>& dims,
                                        const std::vector<uint64_t>& tile_size);

// How many launch indices `tile` covers (a size of 0 counts as 1), saturating at UINT64_MAX.
uint64_t TileIndices(const v1::Tile& tile);

}  // namespace tessera::scheduler

#endif  // TESSERA_SCHEDULER_TILING_H_

#include "tessera/scheduler/tiling.h"

#include <algorithm>

#include "absl/strings/numbers.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_split.h"

namespace tessera::scheduler {

std::vector<uint64_t> MaxTileSize(size_t dimensionality) {
  switch (dimensionality) {
    case 1:
      return {4096};
    case 2:
      return {64, 64};
    default:
      return {16, 16, 4};
  }
}

namespace {

// Tiles per dimension; their product saturates at UINT64_MAX (three dimensions of 2^32 - 1 in
// tiles of 1 would overflow).
uint64_t TilesAlong(uint64_t extent, uint64_t size) { return extent / size + (extent % size != 0); }
uint64_t TileCount(const std::vector<uint64_t>& dims, const std::vector<uint64_t>& size) {
  uint64_t count = 1;
  for (size_t d = 0; d < dims.size() && d < size.size(); ++d) {
    const uint64_t along = TilesAlong(dims[d], std::max<uint64_t>(size[d], 1));
    if (along != 0 && count > UINT64_MAX / along) return UINT64_MAX;
    count *= along;
  }
  return count;
}

// `size` grown, one doubling at a time along the dimension with the most tiles, until the launch
// has at most kMaxTiles of them.
std::vector<uint64_t> LimitTileCount(const std::vector<uint64_t>& dims,
                                     std::vector<uint64_t> size) {
  while (TileCount(dims, size) > kMaxTiles) {
    size_t most = 0;
    for (size_t d = 1; d < dims.size(); ++d) {
      if (TilesAlong(dims[d], size[d]) > TilesAlong(dims[most], size[most])) most = d;
    }
    size[most] = size[most] >= dims[most] / 2 ? dims[most] : size[most] * 2;
  }
  return size;
}

}  // namespace

std::vector<uint64_t> ChooseTileSize(const std::vector<uint64_t>& dims, int total_threads,
                                     uint64_t tiles_per_thread) {
  // Sides of extent 1 take no part: a 1x1xN launch is tiled as the 1D launch of N it is, and
  // Nx1xM as NxM, instead of tiles clipped to 1x1x4 (4 indices each, 2^18 tiles for N = 2^20).
  std::vector<uint64_t> reduced;
  for (uint64_t extent : dims) {
    if (extent > 1) reduced.push_back(extent);
  }
  if (!reduced.empty() && reduced.size() < dims.size()) {
    const std::vector<uint64_t> chosen = ChooseTileSize(reduced, total_threads, tiles_per_thread);
    std::vector<uint64_t> size(dims.size(), 1);
    for (size_t d = 0, r = 0; d < dims.size(); ++d) {
      if (dims[d] > 1) size[d] = chosen[r++];
    }
    return size;
  }
  std::vector<uint64_t> size = MaxTileSize(dims.size());
  const std::vector<uint64_t> smallest =
      dims.size() == 1
          ? std::vector<uint64_t>{256}
          : (dims.size() == 2 ? std::vector<uint64_t>{16, 16} : std::vector<uint64_t>{8, 8, 2});
  const uint64_t wanted = tiles_per_thread * static_cast<uint64_t>(std::max(total_threads, 1));
  while (TileCount(dims, size) < wanted) {
    bool halved = false;
    for (size_t d = 0; d < size.size(); ++d) {
      if (size[d] / 2 >= smallest[d]) {
        size[d] /= 2;
        halved = true;
      }
    }
    if (!halved) break;
  }
  return size;
}

absl::StatusOr<std::vector<uint64_t>> ParseTileSize(absl::string_view text) {
  std::vector<uint64_t> size;
  for (absl::string_view part : absl::StrSplit(text, 'x')) {
    uint64_t n = 0;
    if (!absl::SimpleAtoi(part, &n) || n == 0 || n > (uint64_t{1} << 31)) {
      return absl::InvalidArgumentError(absl::StrCat(
          "tile size '", text, "' is not of the form W, WxH or WxHxD with positive integers"));
    }
    size.push_back(n);
  }
  if (size.size() > 3) {
    return absl::InvalidArgumentError(
        absl::StrCat("tile size '", text, "' has more than three dimensions"));
  }
  return size;
}

std::vector<uint64_t> EffectiveTileSize(const std::vector<uint64_t>& dims,
                                        const std::vector<uint64_t>& tile_size) {
  const size_t n = dims.size();
  if (n == 0 || n > 3) return {};
  std::vector<uint64_t> size(n);
  for (size_t d = 0; d < n; ++d) {
    if (dims[d] == 0) return {};
    // A side longer than the launch covers the same indices as one of the launch's length.
    size[d] = std::clamp<uint64_t>(d < tile_size.size() ? tile_size[d] : 1, 1, dims[d]);
  }
  return LimitTileCount(dims, std::move(size));
}

std::vector<v1::Tile> MakeTiles(const std::vector<uint64_t>& dims,
                                const std::vector<uint64_t>& tile_size) {
  std::vector<v1::Tile> tiles;
  const size_t n = dims.size();
  const std::vector<uint64_t> size = EffectiveTileSize(dims, tile_size);
  if (size.empty()) return tiles;
  uint64_t count[3] = {1, 1, 1};
  for (size_t d = 0; d < n; ++d) count[d] = TilesAlong(dims[d], size[d]);
  tiles.reserve(count[0] * count[1] * count[2]);
  uint32_t index = 0;
  for (uint64_t tz = 0; tz < count[2]; ++tz) {
    for (uint64_t ty = 0; ty < count[1]; ++ty) {
      for (uint64_t tx = 0; tx < count[0]; ++tx) {
        const uint64_t t[3] = {tx, ty, tz};
        v1::Tile tile;
        tile.set_index(index++);
        for (size_t d = 0; d < n; ++d) {
          uint64_t origin = t[d] * size[d];
          tile.add_origin(origin);
          tile.add_size(std::min(size[d], dims[d] - origin));
        }
        tiles.push_back(std::move(tile));
      }
    }
  }
  return tiles;
}

uint64_t TileIndices(const v1::Tile& tile) {
  // Saturates: a tile of a launch with more than 2^64 indices (three dimensions near 2^32 in at
  // most kMaxTiles tiles) would otherwise wrap, to 0 where its sides are powers of two.
  uint64_t n = 1;
  for (uint64_t s : tile.size()) {
    s = std::max<uint64_t>(s, 1);
    if (n > UINT64_MAX / s) return UINT64_MAX;
    n *= s;
  }
  return n;
}

}  // namespace tessera::scheduler

#include "tiling.h"

#include <algorithm>

namespace tessera::api {

std::vector<uint64_t> DefaultTileSize(size_t dimensionality) {
  switch (dimensionality) {
    case 1:
      return {4096};
    case 2:
      return {64, 64};
    default:
      return {16, 16, 4};
  }
}

std::vector<v1::Tile> MakeTiles(const std::vector<uint64_t>& dims,
                                const std::vector<uint64_t>& tile_size) {
  std::vector<v1::Tile> tiles;
  const size_t n = dims.size();
  if (n == 0 || n > 3) return tiles;
  uint64_t size[3] = {1, 1, 1};
  uint64_t extent[3] = {1, 1, 1};
  uint64_t count[3] = {1, 1, 1};
  for (size_t d = 0; d < n; ++d) {
    if (dims[d] == 0) return tiles;
    extent[d] = dims[d];
    size[d] = std::max<uint64_t>(1, d < tile_size.size() ? tile_size[d] : 1);
    count[d] = (extent[d] + size[d] - 1) / size[d];
  }
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
          tile.add_size(std::min(size[d], extent[d] - origin));
        }
        tiles.push_back(std::move(tile));
      }
    }
  }
  return tiles;
}

}  // namespace tessera::api

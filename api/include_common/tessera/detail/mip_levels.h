// Where the mip levels of a buffer lie (OptiX 3.9 rtBufferSetMipLevelCount): level i is
// max(1, size >> i) in each dimension, except the depth of a layered or cube map buffer (3D, its
// depth counting layers or faces), which stays; levels are stored one after another from level 0.
// The host (api/) and devices (worker/core) lay buffers out with these same functions.
#ifndef TESSERA_DETAIL_MIP_LEVELS_H_
#define TESSERA_DETAIL_MIP_LEVELS_H_

#include <array>
#include <cstdint>

namespace tessera::detail {

// `dims` of the buffer's level 0 (unused dimensions 1); `keep_depth`: layered or cube map.
inline std::array<uint64_t, 3> MipLevelDims(const std::array<uint64_t, 3>& dims, unsigned ndims,
                                            bool keep_depth, unsigned level) {
  std::array<uint64_t, 3> out = dims;
  for (unsigned axis = 0; axis < 3; ++axis) {
    if (axis >= ndims || (axis == 2 && keep_depth)) continue;
    const uint64_t d = level >= 64 ? 0 : dims[axis] >> level;
    out[axis] = d == 0 ? 1 : d;
  }
  return out;
}

inline uint64_t MipLevelElements(const std::array<uint64_t, 3>& dims, unsigned ndims,
                                 bool keep_depth, unsigned level) {
  const std::array<uint64_t, 3> d = MipLevelDims(dims, ndims, keep_depth, level);
  return d[0] * d[1] * d[2];
}

// Elements before level `level` (the sum of the levels below it).
inline uint64_t MipLevelOffset(const std::array<uint64_t, 3>& dims, unsigned ndims, bool keep_depth,
                               unsigned level) {
  uint64_t offset = 0;
  for (unsigned i = 0; i < level; ++i) offset += MipLevelElements(dims, ndims, keep_depth, i);
  return offset;
}

// The most levels a buffer of `dims` has: until every mipmapped dimension is 1.
inline unsigned MaxMipLevels(const std::array<uint64_t, 3>& dims, unsigned ndims, bool keep_depth) {
  uint64_t largest = 1;
  for (unsigned axis = 0; axis < ndims && axis < 3; ++axis) {
    if (axis == 2 && keep_depth) continue;
    if (dims[axis] > largest) largest = dims[axis];
  }
  unsigned levels = 1;
  while (largest > 1) {
    largest >>= 1;
    ++levels;
  }
  return levels;
}

}  // namespace tessera::detail

#endif  // TESSERA_DETAIL_MIP_LEVELS_H_

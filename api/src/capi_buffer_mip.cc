// rtBuffer* for mip levels (OptiX 3.9): level counts, level sizes, and mapping one level.
#include "absl/strings/str_cat.h"
#include "boundary.h"
#include "buffer.h"

using namespace tessera::api;  // NOLINT: C entry points only

namespace {

// The size of `level` as rtBufferGetMipLevelSize{1,2,3}D report it: the buffer's own
// dimensionality must match, as for rtBufferGetSize*.
absl::Status LevelSize(const Buffer& b, unsigned level, unsigned dims, RTsize* out[3]) {
  for (unsigned i = 0; i < dims; ++i) TS_RETURN_IF_ERROR(NotNull(out[i], "size pointer"));
  if (level >= b.mip_levels()) {
    return RtError(RT_ERROR_INVALID_VALUE, absl::StrCat("mip level ", level, " is past the ",
                                                        b.mip_levels(), " levels the buffer has"));
  }
  if (b.sized() && b.dimensionality() != dims) {
    return RtError(RT_ERROR_INVALID_VALUE,
                   absl::StrCat("the buffer is ", b.dimensionality(), "D, not ", dims, "D"));
  }
  const std::array<uint64_t, 3> d = b.LevelDims(level);
  for (unsigned i = 0; i < dims; ++i) *out[i] = b.sized() ? d[i] : 0;
  return absl::OkStatus();
}

}  // namespace

extern "C" {

RTresult rtBufferSetMipLevelCount(RTbuffer buffer, unsigned int levels) {
  return Call<Buffer>(__func__, buffer, [&](Buffer& b) { return b.SetMipLevelCount(levels); });
}

RTresult rtBufferGetMipLevelCount(RTbuffer buffer, unsigned int* level) {
  return Call<Buffer>(__func__, buffer, [&](Buffer& b) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(level, "level count pointer"));
    *level = b.mip_levels();
    return absl::OkStatus();
  });
}

RTresult rtBufferGetMipLevelSize1D(RTbuffer buffer, unsigned int level, RTsize* width) {
  return Call<Buffer>(__func__, buffer, [&](Buffer& b) {
    RTsize* out[3] = {width, nullptr, nullptr};
    return LevelSize(b, level, 1, out);
  });
}

RTresult rtBufferGetMipLevelSize2D(RTbuffer buffer, unsigned int level, RTsize* width,
                                   RTsize* height) {
  return Call<Buffer>(__func__, buffer, [&](Buffer& b) {
    RTsize* out[3] = {width, height, nullptr};
    return LevelSize(b, level, 2, out);
  });
}

RTresult rtBufferGetMipLevelSize3D(RTbuffer buffer, unsigned int level, RTsize* width,
                                   RTsize* height, RTsize* depth) {
  return Call<Buffer>(__func__, buffer, [&](Buffer& b) {
    RTsize* out[3] = {width, height, depth};
    return LevelSize(b, level, 3, out);
  });
}

RTresult rtBufferMapEx(RTbuffer buffer, unsigned int map_flags, unsigned int level,
                       void* user_owned, void** optix_owned) {
  return Call<Buffer>(__func__, buffer, [&](Buffer& b) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(optix_owned, "mapped pointer"));
    if (map_flags != RT_BUFFER_MAP_READ && map_flags != RT_BUFFER_MAP_READ_WRITE &&
        map_flags != RT_BUFFER_MAP_WRITE && map_flags != RT_BUFFER_MAP_WRITE_DISCARD) {
      return RtError(RT_ERROR_INVALID_VALUE, absl::StrCat("map flags 0x", absl::Hex(map_flags),
                                                          " are not one RT_BUFFER_MAP_* value"));
    }
    if (user_owned != nullptr) {
      // OptiX 6 does not take application memory here either.
      return RtError(RT_ERROR_INVALID_VALUE, "user_owned must be null (not supported)");
    }
    TS_ASSIGN_OR_RETURN(*optix_owned, b.Map(level));
    return absl::OkStatus();
  });
}

RTresult rtBufferUnmapEx(RTbuffer buffer, unsigned int level) {
  return Call<Buffer>(__func__, buffer, [&](Buffer& b) { return b.Unmap(level); });
}

}  // extern "C"

// A texture sampler (OptiX guide 3.3): how programs read a buffer as a texture. The sampler
// travels to devices on its own; its buffer travels as any buffer, so changing a sampler's modes
// ships no texels.
#ifndef TESSERA_API_SRC_TEXTURE_SAMPLER_H_
#define TESSERA_API_SRC_TEXTURE_SAMPLER_H_

#include <array>
#include <string>

#include "absl/status/status.h"
#include "object.h"

namespace tessera::api {

class Buffer;

class TextureSampler : public Object {
 public:
  static constexpr Kind kKind = Kind::kTextureSampler;

  TextureSampler(Context* context, uint64_t id);

  // Setters take enum values as C callers passed them (any int) and check them first.
  absl::Status SetWrapMode(unsigned dimension, int mode);
  absl::Status SetFilteringModes(int minification, int magnification, int mipmapping);
  void SetMaxAnisotropy(float value);
  absl::Status SetMipLevelClamp(float min_level, float max_level);
  absl::Status SetMipLevelBias(float bias);
  absl::Status SetReadMode(int mode);
  absl::Status SetIndexingMode(int mode);
  // `buffer` null detaches it; a buffer programs cannot read from (OUTPUT only) is refused.
  absl::Status SetBuffer(Buffer* buffer);

  RTwrapmode wrap_mode(unsigned dimension) const { return wrap_[dimension]; }
  RTfiltermode min_filter() const { return min_filter_; }
  RTfiltermode mag_filter() const { return mag_filter_; }
  RTfiltermode mip_filter() const { return mip_filter_; }
  float max_anisotropy() const { return max_anisotropy_; }
  float mip_level_clamp_min() const { return mip_clamp_[0]; }
  float mip_level_clamp_max() const { return mip_clamp_[1]; }
  float mip_level_bias() const { return mip_bias_; }
  RTtexturereadmode read_mode() const { return read_mode_; }
  RTtextureindexmode indexing_mode() const { return index_mode_; }
  Buffer* buffer() const;
  // rtTextureSamplerGetId: programs can now reach the sampler by id, bound to a variable or not.
  void NoteIdTaken() { id_taken_ = true; }
  bool id_taken() const { return id_taken_; }

  // Why programs cannot sample through the sampler as it is (no buffer, a format no texture
  // reads, a cube map of the wrong shape …), or OK.
  absl::Status CheckComplete() const;

  void VisitEdges(EdgeVisitor visit) const override;

 private:
  void DropLinks() override { buffer_.Resize(0); }

  std::array<RTwrapmode, 3> wrap_{RT_WRAP_REPEAT, RT_WRAP_REPEAT, RT_WRAP_REPEAT};
  RTfiltermode min_filter_ = RT_FILTER_LINEAR;
  RTfiltermode mag_filter_ = RT_FILTER_LINEAR;
  RTfiltermode mip_filter_ = RT_FILTER_NONE;
  float max_anisotropy_ = 1.f;
  std::array<float, 2> mip_clamp_{0.f, 0.f};
  float mip_bias_ = 0.f;
  RTtexturereadmode read_mode_ = RT_TEXTURE_READ_NORMALIZED_FLOAT;
  RTtextureindexmode index_mode_ = RT_TEXTURE_INDEX_NORMALIZED_COORDINATES;
  bool id_taken_ = false;
  Links buffer_;
};

// Whether a texture can read elements of `format` (numbers of 1 to 4 components).
bool IsTextureFormat(RTformat format);

}  // namespace tessera::api

#endif  // TESSERA_API_SRC_TEXTURE_SAMPLER_H_

#include "texture_sampler.h"

#include <algorithm>
#include <cmath>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "buffer.h"
#include "buffer_format.h"
#include "status.h"

namespace tessera::api {
namespace {

absl::Status NotEnum(const char* what, int value, const char* expected) {
  return RtError(RT_ERROR_INVALID_VALUE, absl::StrCat(what, " ", value, " is not ", expected));
}

}  // namespace

bool IsTextureFormat(RTformat format) {
  switch (format) {
    case RT_FORMAT_UNKNOWN:
    case RT_FORMAT_USER:
    case RT_FORMAT_BUFFER_ID:
    case RT_FORMAT_PROGRAM_ID:
      return false;
    default:
      return IsValidFormat(format);
  }
}

TextureSampler::TextureSampler(Context* context, uint64_t id)
    : Object(Kind::kTextureSampler, context, id), buffer_(this, 1) {
  Touch();
}

absl::Status TextureSampler::SetWrapMode(unsigned dimension, int mode) {
  if (dimension > 2) {
    return RtError(RT_ERROR_INVALID_VALUE,
                   absl::StrCat("dimension ", dimension, " is not 0, 1 or 2"));
  }
  if (mode < RT_WRAP_REPEAT || mode > RT_WRAP_CLAMP_TO_BORDER) {
    return NotEnum("wrap mode", mode,
                   "RT_WRAP_REPEAT, _CLAMP_TO_EDGE, _MIRROR or _CLAMP_TO_BORDER");
  }
  wrap_[dimension] = static_cast<RTwrapmode>(mode);
  Touch();
  return absl::OkStatus();
}

absl::Status TextureSampler::SetFilteringModes(int minification, int magnification,
                                               int mipmapping) {
  // Texels are filtered NEAREST or LINEAR; NONE means "no mipmapping" and fits only there.
  for (auto [what, mode] : {std::pair<const char*, int>{"minification filter", minification},
                            {"magnification filter", magnification}}) {
    if (mode != RT_FILTER_NEAREST && mode != RT_FILTER_LINEAR) {
      return NotEnum(what, mode, "RT_FILTER_NEAREST or RT_FILTER_LINEAR");
    }
  }
  if (mipmapping < RT_FILTER_NEAREST || mipmapping > RT_FILTER_NONE) {
    return NotEnum("mipmapping filter", mipmapping,
                   "RT_FILTER_NEAREST, RT_FILTER_LINEAR or RT_FILTER_NONE");
  }
  min_filter_ = static_cast<RTfiltermode>(minification);
  mag_filter_ = static_cast<RTfiltermode>(magnification);
  mip_filter_ = static_cast<RTfiltermode>(mipmapping);
  Touch();
  return absl::OkStatus();
}

void TextureSampler::SetMaxAnisotropy(float value) {
  // OptiX clamps to [1, 16]; NaN counts as none.
  max_anisotropy_ = std::isnan(value) ? 1.f : std::clamp(value, 1.f, 16.f);
  Touch();
}

absl::Status TextureSampler::SetMipLevelClamp(float min_level, float max_level) {
  if (std::isnan(min_level) || std::isnan(max_level) || min_level < 0.f || min_level > max_level) {
    return RtError(RT_ERROR_INVALID_VALUE,
                   absl::StrCat("mip level clamp [", min_level, ", ", max_level,
                                "] is not a range of levels (0 <= min <= max)"));
  }
  mip_clamp_ = {min_level, max_level};
  Touch();
  return absl::OkStatus();
}

absl::Status TextureSampler::SetMipLevelBias(float bias) {
  if (!std::isfinite(bias)) {
    return RtError(RT_ERROR_INVALID_VALUE, absl::StrCat("mip level bias ", bias, " is not finite"));
  }
  mip_bias_ = bias;
  Touch();
  return absl::OkStatus();
}

absl::Status TextureSampler::SetReadMode(int mode) {
  if (mode < RT_TEXTURE_READ_ELEMENT_TYPE || mode > RT_TEXTURE_READ_NORMALIZED_FLOAT_SRGB) {
    return NotEnum("read mode", mode,
                   "RT_TEXTURE_READ_ELEMENT_TYPE, _NORMALIZED_FLOAT or their _SRGB forms");
  }
  read_mode_ = static_cast<RTtexturereadmode>(mode);
  Touch();
  return absl::OkStatus();
}

absl::Status TextureSampler::SetIndexingMode(int mode) {
  if (mode != RT_TEXTURE_INDEX_NORMALIZED_COORDINATES && mode != RT_TEXTURE_INDEX_ARRAY_INDEX) {
    return NotEnum("indexing mode", mode,
                   "RT_TEXTURE_INDEX_NORMALIZED_COORDINATES or RT_TEXTURE_INDEX_ARRAY_INDEX");
  }
  index_mode_ = static_cast<RTtextureindexmode>(mode);
  Touch();
  return absl::OkStatus();
}

absl::Status TextureSampler::SetBuffer(Buffer* buffer) {
  if (buffer != nullptr && !buffer->is_input()) {
    return RtError(RT_ERROR_INVALID_VALUE,
                   absl::StrCat(buffer->Describe(),
                                " is an RT_BUFFER_OUTPUT buffer: a texture reads what the host "
                                "wrote (RT_BUFFER_INPUT or RT_BUFFER_INPUT_OUTPUT)"));
  }
  buffer_.Set(0, buffer);
  Touch();
  return absl::OkStatus();
}

Buffer* TextureSampler::buffer() const { return static_cast<Buffer*>(buffer_.Get(0)); }

absl::Status TextureSampler::CheckComplete() const {
  const Buffer* b = buffer();
  if (b == nullptr) return RtError(RT_ERROR_INVALID_VALUE, "buffer is not set");
  const std::string who = b->Describe();
  if (!IsTextureFormat(b->format())) {
    return RtError(RT_ERROR_INVALID_VALUE,
                   absl::StrCat(who, " has format ", FormatName(b->format()),
                                ", which a texture cannot read (float, half, byte, short or int "
                                "of 1 to 4 components)"));
  }
  if (!b->sized()) return RtError(RT_ERROR_INVALID_VALUE, absl::StrCat(who, " has no size"));
  const unsigned desc = b->desc();
  const bool layered = (desc & RT_BUFFER_LAYERED) != 0, cubemap = (desc & RT_BUFFER_CUBEMAP) != 0;
  if ((layered || cubemap) && b->dimensionality() != 3) {
    return RtError(RT_ERROR_INVALID_VALUE,
                   absl::StrCat(who, " is a ", layered ? "layered" : "cube map", " buffer of ",
                                b->dimensionality(),
                                " dimensions; its depth counts layers or faces, so it must be 3D"));
  }
  if (cubemap) {
    const size_t w = b->dim(0), h = b->dim(1), d = b->dim(2);
    if (w != h || d == 0 || d % 6 != 0 || (!layered && d != 6)) {
      return RtError(RT_ERROR_INVALID_VALUE,
                     absl::StrCat(who, " is a cube map of ", w, "x", h, "x", d,
                                  ": faces must be square and the depth ",
                                  layered ? "a multiple of 6 (6 faces per layer)" : "6"));
    }
  }
  return absl::OkStatus();
}

void TextureSampler::VisitEdges(EdgeVisitor visit) const {
  if (buffer_.Get(0) != nullptr) visit(buffer_.Get(0), EdgeRole{"buffer"});
}

}  // namespace tessera::api

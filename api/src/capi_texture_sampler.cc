// rtTextureSampler* and rtContextGetTextureSamplerFromId.
#include <climits>

#include "absl/strings/str_cat.h"
#include "boundary.h"
#include "buffer.h"
#include "context.h"
#include "scope_api.h"
#include "texture_sampler.h"
#include "validate.h"

using namespace tessera::api;  // NOLINT: C entry points only

namespace {

template <typename Body>
RTresult SamplerCall(const char* fn, RTtexturesampler sampler, Body&& body) {
  return Call<TextureSampler>(fn, sampler, std::forward<Body>(body));
}

// Arguments OptiX 3.9 deprecated (texture arrays and per-sampler mip levels, replaced by layered
// buffers and buffer mip levels): only the value that means "not used" is accepted.
absl::Status Deprecated(unsigned value, unsigned accepted, const char* what, const char* instead) {
  if (value == accepted) return absl::OkStatus();
  return RtError(RT_ERROR_INVALID_VALUE,
                 absl::StrCat(what, " ", value, " is not supported (must be ", accepted,
                              "; OptiX 3.9 deprecated it: ", instead, ")"));
}

}  // namespace

extern "C" {

RTresult rtTextureSamplerCreate(RTcontext context, RTtexturesampler* texturesampler) {
  return CreateCall<RTtexturesampler>(__func__, context, texturesampler,
                                      [](Context& c) { return c.Make<TextureSampler>(); });
}

RTresult rtTextureSamplerDestroy(RTtexturesampler texturesampler) {
  return DestroyCall<TextureSampler>(__func__, texturesampler);
}

RTresult rtTextureSamplerValidate(RTtexturesampler texturesampler) {
  return SamplerCall(__func__, texturesampler,
                     [&](TextureSampler& s) { return ValidateObject(s); });
}

RTresult rtTextureSamplerGetContext(RTtexturesampler texturesampler, RTcontext* context) {
  return GetContextCall<TextureSampler>(__func__, texturesampler, context);
}

RTresult rtTextureSamplerSetMipLevelCount(RTtexturesampler texturesampler,
                                          unsigned int num_mip_levels) {
  return SamplerCall(__func__, texturesampler, [&](TextureSampler&) {
    return Deprecated(num_mip_levels, 1, "mip level count",
                      "set the buffer's levels with rtBufferSetMipLevelCount");
  });
}

RTresult rtTextureSamplerGetMipLevelCount(RTtexturesampler texturesampler,
                                          unsigned int* num_mip_levels) {
  return SamplerCall(__func__, texturesampler, [&](TextureSampler&) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(num_mip_levels, "mip level count pointer"));
    *num_mip_levels = 1;
    return absl::OkStatus();
  });
}

RTresult rtTextureSamplerSetArraySize(RTtexturesampler texturesampler,
                                      unsigned int num_textures_in_array) {
  return SamplerCall(__func__, texturesampler, [&](TextureSampler&) {
    return Deprecated(num_textures_in_array, 1, "array size",
                      "use a buffer created with RT_BUFFER_LAYERED");
  });
}

RTresult rtTextureSamplerGetArraySize(RTtexturesampler texturesampler,
                                      unsigned int* num_textures_in_array) {
  return SamplerCall(__func__, texturesampler, [&](TextureSampler&) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(num_textures_in_array, "array size pointer"));
    *num_textures_in_array = 1;
    return absl::OkStatus();
  });
}

RTresult rtTextureSamplerSetWrapMode(RTtexturesampler texturesampler, unsigned int dimension,
                                     RTwrapmode wrapmode) {
  const int mode = wrapmode;  // any int from C; checked before it is an RTwrapmode
  return SamplerCall(__func__, texturesampler,
                     [&](TextureSampler& s) { return s.SetWrapMode(dimension, mode); });
}

RTresult rtTextureSamplerGetWrapMode(RTtexturesampler texturesampler, unsigned int dimension,
                                     RTwrapmode* wrapmode) {
  return SamplerCall(__func__, texturesampler, [&](TextureSampler& s) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(wrapmode, "wrap mode pointer"));
    TS_RETURN_IF_ERROR(CheckIndex(dimension, 3, "dimension", "dimensions"));
    *wrapmode = s.wrap_mode(dimension);
    return absl::OkStatus();
  });
}

RTresult rtTextureSamplerSetFilteringModes(RTtexturesampler texturesampler,
                                           RTfiltermode minification, RTfiltermode magnification,
                                           RTfiltermode mipmapping) {
  const int min = minification, mag = magnification, mip = mipmapping;
  return SamplerCall(__func__, texturesampler,
                     [&](TextureSampler& s) { return s.SetFilteringModes(min, mag, mip); });
}

RTresult rtTextureSamplerGetFilteringModes(RTtexturesampler texturesampler,
                                           RTfiltermode* minification, RTfiltermode* magnification,
                                           RTfiltermode* mipmapping) {
  return SamplerCall(__func__, texturesampler, [&](TextureSampler& s) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(minification, "minification pointer"));
    TS_RETURN_IF_ERROR(NotNull(magnification, "magnification pointer"));
    TS_RETURN_IF_ERROR(NotNull(mipmapping, "mipmapping pointer"));
    *minification = s.min_filter();
    *magnification = s.mag_filter();
    *mipmapping = s.mip_filter();
    return absl::OkStatus();
  });
}

RTresult rtTextureSamplerSetMaxAnisotropy(RTtexturesampler texturesampler, float value) {
  return SamplerCall(__func__, texturesampler, [&](TextureSampler& s) -> absl::Status {
    s.SetMaxAnisotropy(value);
    return absl::OkStatus();
  });
}

RTresult rtTextureSamplerGetMaxAnisotropy(RTtexturesampler texturesampler, float* value) {
  return SamplerCall(__func__, texturesampler, [&](TextureSampler& s) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(value, "anisotropy pointer"));
    *value = s.max_anisotropy();
    return absl::OkStatus();
  });
}

RTresult rtTextureSamplerSetMipLevelClamp(RTtexturesampler texturesampler, float min_level,
                                          float max_level) {
  return SamplerCall(__func__, texturesampler,
                     [&](TextureSampler& s) { return s.SetMipLevelClamp(min_level, max_level); });
}

RTresult rtTextureSamplerGetMipLevelClamp(RTtexturesampler texturesampler, float* min_level,
                                          float* max_level) {
  return SamplerCall(__func__, texturesampler, [&](TextureSampler& s) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(min_level, "minimum level pointer"));
    TS_RETURN_IF_ERROR(NotNull(max_level, "maximum level pointer"));
    *min_level = s.mip_level_clamp_min();
    *max_level = s.mip_level_clamp_max();
    return absl::OkStatus();
  });
}

RTresult rtTextureSamplerSetMipLevelBias(RTtexturesampler texturesampler, float value) {
  return SamplerCall(__func__, texturesampler,
                     [&](TextureSampler& s) { return s.SetMipLevelBias(value); });
}

RTresult rtTextureSamplerGetMipLevelBias(RTtexturesampler texturesampler, float* value) {
  return SamplerCall(__func__, texturesampler, [&](TextureSampler& s) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(value, "bias pointer"));
    *value = s.mip_level_bias();
    return absl::OkStatus();
  });
}

RTresult rtTextureSamplerSetReadMode(RTtexturesampler texturesampler, RTtexturereadmode readmode) {
  const int mode = readmode;
  return SamplerCall(__func__, texturesampler,
                     [&](TextureSampler& s) { return s.SetReadMode(mode); });
}

RTresult rtTextureSamplerGetReadMode(RTtexturesampler texturesampler, RTtexturereadmode* readmode) {
  return SamplerCall(__func__, texturesampler, [&](TextureSampler& s) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(readmode, "read mode pointer"));
    *readmode = s.read_mode();
    return absl::OkStatus();
  });
}

RTresult rtTextureSamplerSetIndexingMode(RTtexturesampler texturesampler,
                                         RTtextureindexmode indexmode) {
  const int mode = indexmode;
  return SamplerCall(__func__, texturesampler,
                     [&](TextureSampler& s) { return s.SetIndexingMode(mode); });
}

RTresult rtTextureSamplerGetIndexingMode(RTtexturesampler texturesampler,
                                         RTtextureindexmode* indexmode) {
  return SamplerCall(__func__, texturesampler, [&](TextureSampler& s) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(indexmode, "indexing mode pointer"));
    *indexmode = s.indexing_mode();
    return absl::OkStatus();
  });
}

RTresult rtTextureSamplerSetBuffer(RTtexturesampler texturesampler, unsigned int deprecated0,
                                   unsigned int deprecated1, RTbuffer buffer) {
  return SamplerCall(__func__, texturesampler, [&](TextureSampler& s) -> absl::Status {
    TS_RETURN_IF_ERROR(Deprecated(deprecated0, 0, "texture array index",
                                  "use a buffer created with RT_BUFFER_LAYERED"));
    TS_RETURN_IF_ERROR(Deprecated(deprecated1, 0, "mip level",
                                  "set the buffer's levels with rtBufferSetMipLevelCount"));
    TS_ASSIGN_OR_RETURN(Buffer * b, Arg<Buffer>(buffer, s.context(), "buffer"));
    return s.SetBuffer(b);
  });
}

RTresult rtTextureSamplerGetBuffer(RTtexturesampler texturesampler, unsigned int deprecated0,
                                   unsigned int deprecated1, RTbuffer* buffer) {
  return SamplerCall(__func__, texturesampler, [&](TextureSampler& s) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(buffer, "buffer pointer"));
    TS_RETURN_IF_ERROR(Deprecated(deprecated0, 0, "texture array index",
                                  "use a buffer created with RT_BUFFER_LAYERED"));
    TS_RETURN_IF_ERROR(Deprecated(deprecated1, 0, "mip level",
                                  "set the buffer's levels with rtBufferSetMipLevelCount"));
    *buffer = ToHandle<RTbuffer>(s.buffer());
    return absl::OkStatus();
  });
}

RTresult rtTextureSamplerGetId(RTtexturesampler texturesampler, int* texture_id) {
  return SamplerCall(__func__, texturesampler, [&](TextureSampler& s) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(texture_id, "id pointer"));
    // The object id, as for buffers: devices know samplers by it, and it is never 0.
    if (s.id() > static_cast<uint64_t>(INT_MAX)) {
      return RtError(RT_ERROR_INVALID_VALUE, "texture sampler id does not fit in an int");
    }
    *texture_id = static_cast<int>(s.id());
    if (!s.id_taken()) {
      s.NoteIdTaken();
      s.context()->StructureChanged();  // validation now covers it (ValidateContext)
    }
    return absl::OkStatus();
  });
}

RTresult rtContextGetTextureSamplerFromId(RTcontext context, int sampler_id,
                                          RTtexturesampler* sampler) {
  return Call<Context>(__func__, context, [&](Context& c) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(sampler, "sampler pointer"));
    Object* object = sampler_id > 0 ? c.FindById(static_cast<uint64_t>(sampler_id)) : nullptr;
    if (object == nullptr || object->kind() != Kind::kTextureSampler) {
      return RtError(RT_ERROR_INVALID_VALUE,
                     absl::StrCat("no live texture sampler has id ", sampler_id));
    }
    *sampler = ToHandle<RTtexturesampler>(object);
    return absl::OkStatus();
  });
}

}  // extern "C"

#include "texture_views.h"

#include "absl/strings/str_cat.h"
#include "tessera/detail/mip_levels.h"
#include "tessera/detail/texture_fast_float.h"
#include "tessera/detail/texture_modes.h"
#include "tessera/rt.h"

namespace tessera::worker {
namespace {

// Views hold OptiX 3's enum values as they are; the shared sampler names them without rt.h.
namespace tx = tessera::texture;
constexpr bool Same(unsigned sampler, unsigned optix3) { return sampler == optix3; }
static_assert(Same(tx::kFormatFloat, RT_FORMAT_FLOAT) && Same(tx::kFormatFloat4, RT_FORMAT_FLOAT4));
static_assert(Same(tx::kFormatByte, RT_FORMAT_BYTE) &&
              Same(tx::kFormatUnsignedByte4, RT_FORMAT_UNSIGNED_BYTE4));
static_assert(Same(tx::kFormatShort, RT_FORMAT_SHORT) &&
              Same(tx::kFormatUnsignedShort4, RT_FORMAT_UNSIGNED_SHORT4));
static_assert(Same(tx::kFormatInt, RT_FORMAT_INT) &&
              Same(tx::kFormatUnsignedInt4, RT_FORMAT_UNSIGNED_INT4));
static_assert(Same(tx::kFormatHalf, RT_FORMAT_HALF) && Same(tx::kFormatHalf4, RT_FORMAT_HALF4));
static_assert(Same(tx::kWrapRepeat, RT_WRAP_REPEAT) &&
              Same(tx::kWrapClampToEdge, RT_WRAP_CLAMP_TO_EDGE) &&
              Same(tx::kWrapMirror, RT_WRAP_MIRROR) &&
              Same(tx::kWrapClampToBorder, RT_WRAP_CLAMP_TO_BORDER));
static_assert(Same(tx::kFilterNearest, RT_FILTER_NEAREST) &&
              Same(tx::kFilterLinear, RT_FILTER_LINEAR) && Same(tx::kFilterNone, RT_FILTER_NONE));
static_assert(Same(tx::kReadElementType, RT_TEXTURE_READ_ELEMENT_TYPE) &&
              Same(tx::kReadNormalizedFloat, RT_TEXTURE_READ_NORMALIZED_FLOAT) &&
              Same(tx::kReadElementTypeSrgb, RT_TEXTURE_READ_ELEMENT_TYPE_SRGB) &&
              Same(tx::kReadNormalizedFloatSrgb, RT_TEXTURE_READ_NORMALIZED_FLOAT_SRGB));
static_assert(Same(tx::kIndexNormalizedCoordinates, RT_TEXTURE_INDEX_NORMALIZED_COORDINATES) &&
              Same(tx::kIndexArrayIndex, RT_TEXTURE_INDEX_ARRAY_INDEX));

// Components of the numeric RTformats a texture reads (RT_FORMAT_FLOAT … RT_FORMAT_UNSIGNED_INT4
// and RT_FORMAT_HALF …), 0 for any other format.
unsigned TexelComponents(uint32_t format) {
  if (format >= RT_FORMAT_FLOAT && format <= RT_FORMAT_UNSIGNED_INT4) {
    return (format - RT_FORMAT_FLOAT) % 4 + 1;
  }
  if (format >= RT_FORMAT_HALF && format <= RT_FORMAT_HALF4) return format - RT_FORMAT_HALF + 1;
  return 0;
}

}  // namespace

absl::StatusOr<TesseraTextureView> MakeTextureView(const Replica& replica, uint64_t sampler_id) {
  const SamplerRec* s = replica.Find(replica.texture_samplers, sampler_id);
  if (s == nullptr) {
    return absl::NotFoundError(
        absl::StrCat("texture sampler #", sampler_id, " is unknown to the device"));
  }
  const std::string who = absl::StrCat("texture sampler #", sampler_id);
  if (s->buffer == 0) {
    return absl::FailedPreconditionError(absl::StrCat(who, " has no buffer"));
  }
  const BufferRec* b = replica.Find(replica.buffers, s->buffer);
  if (b == nullptr) {
    return absl::NotFoundError(absl::StrCat(who, " reads unknown buffer #", s->buffer));
  }
  if (TexelComponents(b->format) == 0 || b->element_size == 0 || b->ndims == 0 ||
      b->Elements() == 0) {
    return absl::FailedPreconditionError(
        absl::StrCat(who, " reads buffer #", s->buffer, ", of format 0x", absl::Hex(b->format),
                     " and ", b->Elements(), " elements, which no texture can read"));
  }
  if (b->mip_levels > TESSERA_TEXTURE_MAX_LEVELS) {
    return absl::FailedPreconditionError(
        absl::StrCat(who, " reads buffer #", s->buffer, " of ", b->mip_levels, " mip levels"));
  }
  TesseraTextureView v{};
  const bool keep_depth = b->KeepsDepth();
  for (unsigned level = 0; level < b->mip_levels; ++level) {
    const std::array<uint64_t, 3> d = detail::MipLevelDims(b->dims, b->ndims, keep_depth, level);
    const uint64_t offset = detail::MipLevelOffset(b->dims, b->ndims, keep_depth, level);
    v.levels[level].data = b->data.data() + offset * b->element_size;
    v.levels[level].width = static_cast<unsigned>(d[0]);
    v.levels[level].height = static_cast<unsigned>(d[1]);
    v.levels[level].depth = static_cast<unsigned>(d[2]);
  }
  v.level_count = b->mip_levels;
  v.dimensionality = b->ndims;
  v.format = b->format;
  v.element_size = static_cast<unsigned>(b->element_size);
  v.layered = (b->desc & RT_BUFFER_LAYERED) != 0 ? 1 : 0;
  v.cubemap = (b->desc & RT_BUFFER_CUBEMAP) != 0 ? 1 : 0;
  for (int i = 0; i < 3; ++i) v.wrap[i] = s->wrap[i];
  v.min_filter = s->min_filter;
  v.mag_filter = s->mag_filter;
  v.mip_filter = s->mip_filter;
  v.read_mode = s->read_mode;
  v.index_mode = s->index_mode;
  v.max_anisotropy = s->max_anisotropy;
  v.mip_level_clamp[0] = s->mip_level_clamp_min;
  v.mip_level_clamp[1] = s->mip_level_clamp_max;
  v.mip_level_bias = s->mip_level_bias;
  v.id = static_cast<int>(sampler_id);
  texture::MarkFastLookups(v);
  return v;
}

namespace {
const TesseraTextureIdTable kNoTextureIds = {0, nullptr};
}  // namespace

__thread const TesseraTextureIdTable* t_texture_ids __attribute__((tls_model("initial-exec"))) =
    &kNoTextureIds;
__thread const TesseraTextureView* t_texture_table __attribute__((tls_model("initial-exec"))) =
    nullptr;

void PlanTextures(const Replica& replica, TextureTable& table) {
  std::vector<std::pair<uint64_t, uint32_t>> ids;
  for (const auto& [id, sampler] : replica.texture_samplers) {
    absl::StatusOr<TesseraTextureView> view = MakeTextureView(replica, id);
    ids.emplace_back(id, static_cast<uint32_t>(table.samplers.size()));
    table.samplers.push_back(view.ok() ? TextureById{*view, absl::OkStatus()}
                                       : TextureById{TesseraTextureView{}, view.status()});
  }
  table.index.Build(std::move(ids));
  if (table.index.dense()) {
    for (const auto& [id, sampler] : replica.texture_samplers) {
      const TextureById& t = table.samplers[table.index.Find(static_cast<long long>(id))];
      if (!t.problem.ok()) continue;
      if (table.fast_views.size() <= id) table.fast_views.resize(id + 1, nullptr);
      table.fast_views[id] = &t.view;
    }
  }
  table.fast = {table.fast_views.size(), table.fast_views.data()};
}

const char* TextureShapeMismatch(unsigned declared, const TesseraTextureView& v) {
  constexpr unsigned k1D = 0x01, k2D = 0x02, k3D = 0x03, kCube = 0x0C, k1DLayered = 0xF1,
                     k2DLayered = 0xF2, kCubeLayered = 0xFC;  // cudaTextureType*
  const bool plain = v.layered == 0 && v.cubemap == 0;
  switch (declared) {
    case k1D:
      return plain && v.dimensionality == 1 ? nullptr : "a 1D buffer";
    case k2D:
      return plain && v.dimensionality == 2 ? nullptr : "a 2D buffer";
    case k3D:
      return plain && v.dimensionality == 3 ? nullptr : "a 3D buffer";
    case kCube:
      return v.cubemap != 0 && v.layered == 0 ? nullptr : "an RT_BUFFER_CUBEMAP buffer";
    case k1DLayered:
    case k2DLayered:
      return v.layered != 0 && v.cubemap == 0 ? nullptr : "an RT_BUFFER_LAYERED buffer";
    case kCubeLayered:
      return v.layered != 0 && v.cubemap != 0
                 ? nullptr
                 : "a buffer with RT_BUFFER_LAYERED and RT_BUFFER_CUBEMAP";
    default:
      return "a texture type this engine knows";
  }
}

}  // namespace tessera::worker

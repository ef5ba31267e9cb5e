#include "accel_format.h"

#include <cstring>

#include "absl/strings/str_cat.h"

namespace tessera::memory {
namespace {

bool InRange(uint64_t offset, uint64_t bytes, uint64_t size) {
  return offset <= size && bytes <= size - offset;
}

}  // namespace

absl::StatusOr<const AccelHeader*> ReadAccelHeader(const void* data, size_t size) {
  if (data == nullptr || size < sizeof(AccelHeader)) {
    return absl::InvalidArgumentError(
        absl::StrCat("acceleration descriptor of ", size, " bytes: shorter than its header"));
  }
  const auto* h = static_cast<const AccelHeader*>(data);
  if (std::memcmp(h->magic, kAccelMagic, sizeof(kAccelMagic)) != 0) {
    return absl::InvalidArgumentError(
        "not an acceleration optixAccelBuild wrote (a traversable handle that is not one, or "
        "memory overwritten since the build)");
  }
  if (h->version != kAccelFormatVersion) {
    return absl::InvalidArgumentError(absl::StrCat("acceleration descriptor of format version ",
                                                   h->version, " (this Tessera reads ",
                                                   kAccelFormatVersion, ")"));
  }
  if (h->total_size < sizeof(AccelHeader) || h->total_size > size) {
    return absl::InvalidArgumentError(absl::StrCat("acceleration descriptor says ", h->total_size,
                                                   " bytes, ", size, " are there"));
  }
  const auto* bytes = static_cast<const unsigned char*>(data);
  const uint64_t record = h->kind == AccelKind::kInstances ? kInstanceBytes : sizeof(AccelInput);
  const uint64_t records = h->kind == AccelKind::kInstances ? h->primitive_count : h->input_count;
  if (h->kind != AccelKind::kTriangles && h->kind != AccelKind::kCustom &&
      h->kind != AccelKind::kInstances && h->kind != AccelKind::kSpheres) {
    return absl::InvalidArgumentError(
        absl::StrCat("acceleration descriptor of unknown kind ", static_cast<uint32_t>(h->kind)));
  }
  if (records > h->total_size / record ||
      !InRange(h->inputs_offset, records * record, h->total_size)) {
    return absl::InvalidArgumentError("acceleration descriptor's inputs lie outside it");
  }
  uint64_t keys = 1;
  if (h->motion_offset != 0) {
    if (!InRange(h->motion_offset, sizeof(AccelMotion), h->total_size)) {
      return absl::InvalidArgumentError("acceleration descriptor's motion options lie outside it");
    }
    const auto* m = reinterpret_cast<const AccelMotion*>(bytes + h->motion_offset);
    if (m->keys < 2 || !(m->time_begin <= m->time_end)) {
      return absl::InvalidArgumentError(
          absl::StrCat("acceleration descriptor's motion options are invalid (", m->keys,
                       " keys, time ", m->time_begin, " to ", m->time_end, ")"));
    }
    keys = m->keys;
  }
  if (h->kind == AccelKind::kInstances) return h;
  const auto* inputs = reinterpret_cast<const AccelInput*>(bytes + h->inputs_offset);
  for (uint32_t i = 0; i < h->input_count; ++i) {
    const AccelInput& in = inputs[i];
    const uint64_t p = in.primitive_count;
    const bool ok =
        in.num_sbt_records > 0 &&
        InRange(in.flags_offset, 4ull * in.num_sbt_records, h->total_size) &&
        (in.sbt_index_offsets_offset == 0 ||
         InRange(in.sbt_index_offsets_offset, 4 * p, h->total_size)) &&
        (h->kind == AccelKind::kTriangles
             ? in.vertex_count <= h->total_size / 12 / keys &&
                   InRange(in.vertices_offset, 12ull * in.vertex_count * keys, h->total_size) &&
                   InRange(in.indices_offset, 12 * p, h->total_size)
         : h->kind == AccelKind::kSpheres
             ? p <= h->total_size / 16 / keys &&
                   InRange(in.vertices_offset, 16 * p * keys, h->total_size)
             : p <= h->total_size / 24 / keys &&
                   InRange(in.aabbs_offset, 24 * p * keys, h->total_size));
    if (!ok) {
      return absl::InvalidArgumentError(
          absl::StrCat("acceleration descriptor's input ", i, " lies outside it"));
    }
  }
  return h;
}

}  // namespace tessera::memory

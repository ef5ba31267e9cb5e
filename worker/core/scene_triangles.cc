#include "scene_triangles.h"

#include <cmath>
#include <cstring>
#include <string>
#include <utility>

#include "absl/strings/numbers.h"
#include "absl/strings/str_cat.h"
#include "tessera/rt.h"
#include "tessera/scheduler/device.h"

namespace tessera::worker {
namespace {

// A triangle vertex Embree would leave out of the build with its triangles (never hit, without a
// word): finite but beyond its FLT_LARGE. Vertices cannot be clamped like bounds (the triangle
// would change), so the launch fails naming it. NaN vertices only make their triangles vanish,
// as degenerate triangles do in OptiX (so does a vertex with any infinite coordinate). OK
// otherwise.
absl::Status CheckVertexInRange(const std::string& what, const float* v, uint32_t vertex) {
  constexpr float kEmbreeLarge = 1.844e18f;
  if (!std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2])) {
    return absl::OkStatus();
  }
  for (int k = 0; k < 3; ++k) {
    if (std::fabs(v[k]) > kEmbreeLarge) {
      return absl::OutOfRangeError(absl::StrCat(
          what, ": vertex ", vertex, " at (", v[0], ", ", v[1], ", ", v[2],
          ") lies beyond +-1.844e18, which Embree cannot build (scale the scene down)"));
    }
  }
  return absl::OkStatus();
}

// Checks triangle `t`'s indices against the vertices, and its vertices against Embree's range.
absl::Status CheckTriangle(const std::string& what, const float* vertices, uint64_t nverts,
                           const uint32_t* tri, uint64_t t) {
  for (int k = 0; k < 3; ++k) {
    const uint32_t vertex = tri[k];
    if (vertex >= nverts) {
      return absl::OutOfRangeError(absl::StrCat(what, ": triangle ", t, " uses vertex ", vertex,
                                                " but the vertex buffer holds ", nverts));
    }
    if (absl::Status s = CheckVertexInRange(what, vertices + 3 * size_t{vertex}, vertex); !s.ok()) {
      return s;
    }
  }
  return absl::OkStatus();
}

const BufferRec* FindBuffer(const Replica& r, const InstanceRec& gi, const GeometryRec& g,
                            const std::string& name, uint64_t* id) {
  for (const Scope* s : {&gi.vars, &g.vars}) {
    auto it = s->find(name);
    if (it != s->end() && it->second.type == RT_OBJECTTYPE_BUFFER) {
      *id = it->second.object_id;
      return r.Find(r.buffers, it->second.object_id);
    }
  }
  return nullptr;
}

}  // namespace

bool TriangleBuilder(const AccelRec& a) {
  return a.builder == "Sbvh" || a.builder == "TriangleKdTree" || a.builder == "Trbvh" ||
         a.properties.count("vertex_buffer_name") > 0;
}

std::string Property(const AccelRec& a, const std::string& name, const std::string& fallback) {
  auto it = a.properties.find(name);
  return it == a.properties.end() ? fallback : it->second;
}

absl::StatusOr<std::optional<TriangleSource>> BufferTriangleSource(
    const Replica& r, uint64_t accel_id, const AccelRec& a, uint64_t instance_id,
    const InstanceRec& gi, const GeometryRec& g) {
  if (!TriangleBuilder(a)) return std::nullopt;
  uint64_t vertex_id = 0, index_id = 0;
  const BufferRec* vertices =
      FindBuffer(r, gi, g, Property(a, "vertex_buffer_name", "vertex_buffer"), &vertex_id);
  const BufferRec* indices =
      FindBuffer(r, gi, g, Property(a, "index_buffer_name", "index_buffer"), &index_id);
  if (vertices == nullptr || indices == nullptr) return std::nullopt;
  size_t vertex_stride = 0, index_stride = 0;
  for (const auto& [name, stride] : {std::pair{"vertex_buffer_stride", &vertex_stride},
                                     std::pair{"index_buffer_stride", &index_stride}}) {
    const std::string text = Property(a, name, "0");
    if (!absl::SimpleAtoi(text, stride)) {
      return absl::InvalidArgumentError(absl::StrCat("acceleration #", accel_id, ": property ",
                                                     name, " is '", text, "', not a byte count"));
    }
  }
  if (vertex_stride == 0) vertex_stride = vertices->element_size;
  if (index_stride == 0) index_stride = indices->element_size;
  if (vertex_stride < 12 || index_stride < 12) return std::nullopt;
  TriangleSource out;
  // An element's last vertex or triangle needs its 12 bytes, not a whole stride.
  const size_t vbytes = vertices->data.size();
  out.vertex_count = vbytes < 12 ? 0 : (vbytes - 12) / vertex_stride + 1;
  // Every primitive is a triangle of the index buffer: one it cannot hold would never be hit.
  out.triangle_count = g.primitive_count;
  if (!StridedFits(indices->data.size(), 0, out.triangle_count, index_stride, 12)) {
    return absl::OutOfRangeError(
        absl::StrCat("geometry instance #", instance_id, ": ", out.triangle_count,
                     " triangles' indices every ", index_stride, " bytes (acceleration #", accel_id,
                     ", property index_buffer_stride) do not fit index buffer #", index_id, " (",
                     indices->data.size(), " bytes)"));
  }
  const uint64_t nverts = out.vertex_count, ntris = out.triangle_count;
  out.copy = [=](float* v, uint32_t* idx) -> absl::Status {
    for (uint64_t i = 0; i < nverts; ++i) {
      std::memcpy(v + 3 * i, vertices->data.data() + i * vertex_stride, 12);
    }
    const std::string what = absl::StrCat("geometry instance #", instance_id);
    for (uint64_t t = 0; t < ntris; ++t) {
      std::memcpy(idx + 3 * t, indices->data.data() + t * index_stride, 12);
      if (absl::Status s = CheckTriangle(what, v, nverts, idx + 3 * t, t); !s.ok()) return s;
    }
    return absl::OkStatus();
  };
  return out;
}

absl::StatusOr<TriangleSource> BuiltinTriangleSource(const Replica& r, uint64_t id,
                                                     const GeometryRec& g) {
  const v1::TriangleMesh& m = g.mesh;
  const std::string what = absl::StrCat("geometry triangles #", id);
  const BufferRec* vb = r.Find(r.buffers, m.vertex_buffer());
  if (vb == nullptr) {
    return absl::FailedPreconditionError(
        absl::StrCat(what, ": vertex buffer #", m.vertex_buffer(), " is unknown"));
  }
  const unsigned components = m.vertex_format() == RT_FORMAT_FLOAT3   ? 3
                              : m.vertex_format() == RT_FORMAT_FLOAT2 ? 2
                                                                      : 0;
  if (components == 0) {
    return absl::InvalidArgumentError(absl::StrCat(what, ": vertex format ", m.vertex_format(),
                                                   " is not RT_FORMAT_FLOAT3 or RT_FORMAT_FLOAT2"));
  }
  const uint64_t vbytes = components * sizeof(float);
  const uint64_t vstride = m.vertex_stride() != 0 ? m.vertex_stride() : vbytes;
  const uint64_t nverts = m.vertex_count();
  if (vstride < vbytes ||
      !StridedFits(vb->data.size(), m.vertex_offset(), nverts, vstride, vbytes)) {
    return absl::OutOfRangeError(absl::StrCat(
        what, ": ", nverts, " vertices every ", vstride, " bytes from byte ", m.vertex_offset(),
        " do not fit vertex buffer #", m.vertex_buffer(), " (", vb->data.size(), " bytes)"));
  }
  const BufferRec* ib = nullptr;
  uint64_t ibytes = 0, istride = 0;
  if (m.index_buffer() != 0) {
    ib = r.Find(r.buffers, m.index_buffer());
    if (ib == nullptr) {
      return absl::FailedPreconditionError(
          absl::StrCat(what, ": index buffer #", m.index_buffer(), " is unknown"));
    }
    ibytes = m.index_format() == RT_FORMAT_UNSIGNED_INT3     ? 12
             : m.index_format() == RT_FORMAT_UNSIGNED_SHORT3 ? 6
                                                             : 0;
    if (ibytes == 0) {
      return absl::InvalidArgumentError(
          absl::StrCat(what, ": index format ", m.index_format(),
                       " is not RT_FORMAT_UNSIGNED_INT3 or RT_FORMAT_UNSIGNED_SHORT3"));
    }
    istride = m.index_stride() != 0 ? m.index_stride() : ibytes;
    if (istride < ibytes ||
        !StridedFits(ib->data.size(), m.index_offset(), g.primitive_count, istride, ibytes)) {
      return absl::OutOfRangeError(
          absl::StrCat(what, ": ", g.primitive_count, " triangles' indices every ", istride,
                       " bytes from byte ", m.index_offset(), " do not fit index buffer #",
                       m.index_buffer(), " (", ib->data.size(), " bytes)"));
    }
  } else if (g.primitive_count > nverts / 3) {
    return absl::OutOfRangeError(absl::StrCat(what, ": ", g.primitive_count,
                                              " triangles without an index buffer need ",
                                              3 * g.primitive_count, " vertices, not ", nverts));
  }
  TriangleSource out;
  out.vertex_count = nverts;
  out.triangle_count = g.primitive_count;
  const unsigned char* vsrc = vb->data.data() + m.vertex_offset();
  const unsigned char* isrc = ib != nullptr ? ib->data.data() + m.index_offset() : nullptr;
  const uint64_t ntris = g.primitive_count;
  out.copy = [=](float* v, uint32_t* idx) -> absl::Status {
    for (uint64_t i = 0; i < nverts; ++i) {
      v[3 * i + 2] = 0.f;  // FLOAT2 vertices lie in the z = 0 plane
      std::memcpy(v + 3 * i, vsrc + i * vstride, vbytes);
    }
    for (uint64_t t = 0; t < ntris; ++t) {
      for (unsigned k = 0; k < 3; ++k) {
        uint32_t vertex = static_cast<uint32_t>(3 * t + k);
        if (isrc != nullptr) {
          const unsigned char* src = isrc + t * istride;
          if (ibytes == 12) {
            std::memcpy(&vertex, src + 4 * k, 4);
          } else {
            uint16_t s;
            std::memcpy(&s, src + 2 * k, 2);
            vertex = s;
          }
        }
        idx[3 * t + k] = vertex;
      }
      if (absl::Status s = CheckTriangle(what, v, nverts, idx + 3 * t, t); !s.ok()) return s;
    }
    return absl::OkStatus();
  };
  return out;
}

}  // namespace tessera::worker

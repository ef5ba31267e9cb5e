// Where a GeometryGroup's triangles come from — GeometryTriangles (OptiX 6) or the vertex and index
// buffers an acceleration names (OptiX 3 "vertex_buffer_name") — checked, and copied into the
// arrays a scene builds from: Embree's own triangle buffers, or the watertight test's copies
// (docs/accuracy.md). A refit copies them again into the same arrays.
#ifndef TESSERA_WORKER_CORE_SCENE_TRIANGLES_H_
#define TESSERA_WORKER_CORE_SCENE_TRIANGLES_H_

#include <cstdint>
#include <functional>
#include <optional>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "replica.h"

namespace tessera::worker {

struct TriangleSource {
  uint64_t vertex_count = 0;
  uint64_t triangle_count = 0;
  // Copies the vertices (3 floats each) and indices (3 each) into arrays of those counts; fails
  // naming the geometry for an index past the vertices or a vertex Embree cannot build.
  std::function<absl::Status(float* vertices, uint32_t* indices)> copy;
};

// The triangles of GeometryTriangles `id`.
absl::StatusOr<TriangleSource> BuiltinTriangleSource(const Replica& r, uint64_t id,
                                                     const GeometryRec& g);

// The triangles acceleration `accel_id` takes from the buffers its properties name for geometry
// instance `instance_id`, or nullopt when it takes the geometry's intersection program instead
// (a builder without triangle support, or no such buffers).
absl::StatusOr<std::optional<TriangleSource>> BufferTriangleSource(
    const Replica& r, uint64_t accel_id, const AccelRec& a, uint64_t instance_id,
    const InstanceRec& gi, const GeometryRec& g);

// Whether acceleration `a` may take triangles from buffers (its builder, or vertex_buffer_name).
bool TriangleBuilder(const AccelRec& a);

// An acceleration property, or `fallback` when it is not set.
std::string Property(const AccelRec& a, const std::string& name, const std::string& fallback);

}  // namespace tessera::worker

#endif  // TESSERA_WORKER_CORE_SCENE_TRIANGLES_H_

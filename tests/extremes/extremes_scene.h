// A closed mesh in an OptiX 3 context, shot with rays from a buffer (extremes_programs.cu): as
// GeometryTriangles or as an application's mesh (intersection program over vertex and index
// buffers, traced as native triangles), its vertices baked at an offset and scale or placed there
// by a Transform, under given accuracy settings.
#ifndef TESSERA_TESTS_EXTREMES_EXTREMES_SCENE_H_
#define TESSERA_TESTS_EXTREMES_EXTREMES_SCENE_H_

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "closed_meshes.h"
#include "rt_fixture.h"

namespace tessera::testing {

struct Ray {
  std::array<float, 3> origin, direction;
  float tmin = 0.f, tmax = 1e30f;
  std::array<float, 3> secondary{0.f, 0.f, 1.f};  // spawn modes 1-3
};

struct RayResult {
  bool hit = false;
  float t = 0.f;
  uint32_t primitive = 0, candidates = 0;
  bool secondary_hit = false;
};

struct Placement {
  double scale = 1.0;
  std::array<double, 3> offset{0, 0, 0};
  bool by_transform = false;  // else baked into the vertices
};

enum class MeshKind { kGeometryTriangles, kApplicationMesh };

class ExtremesScene : public RtFixture {
 protected:
  // Builds the context: `mesh` placed by `placement`, the context's accuracy `flags`, the
  // acceleration `builder` with `properties`, a counting any-hit program when `any_hit`.
  void Build(const meshgen::Mesh& mesh, MeshKind kind, const Placement& placement, uint32_t flags,
             bool any_hit = false, const char* builder = "Trbvh",
             const std::vector<std::pair<std::string, std::string>>& properties = {},
             const char* devices = "inproc");
  // Traces `rays` with spawn mode `spawn` (extremes_programs.cu) and scene_epsilon `epsilon`.
  std::vector<RayResult> Trace(const std::vector<Ray>& rays, unsigned spawn = 0,
                               float epsilon = 1e-4f);
  // The vertices as the device holds them (world space when baked, object space otherwise).
  const std::vector<float>& stored() const { return stored_; }
  // The vertex buffer Build made (refit tests move its vertices).
  RTbuffer vertex_buffer() const { return vertex_buffer_; }

 private:
  std::vector<float> stored_;
  RTbuffer vertex_buffer_ = nullptr;
};

}  // namespace tessera::testing

#endif  // TESSERA_TESTS_EXTREMES_EXTREMES_SCENE_H_

// A scene's assets and frames as an OptiX 6 node graph (OptiXpp):
//
//   top_object: Group (Trbvh) -- Transform per instance -- GeometryGroup per mesh (Trbvh)
//     -- GeometryInstance -- GeometryTriangles (built-in triangles, attribute program mesh.cu)
//                         -- Material (closest hit material.cu, its factors and texture ids)
//
// Meshes, materials and textures are made once; SetFrame changes only what moves: the Transforms'
// matrices (and how many there are), the lights and the emissive triangles.
#ifndef TESSERA_TOOLS_TESSERA_RENDER_SCENE_GRAPH_H_
#define TESSERA_TOOLS_TESSERA_RENDER_SCENE_GRAPH_H_

#include <optixu/optixpp_namespace.h>

#include <vector>

#include "absl/status/status.h"
#include "tools/tessera/scene/scene.h"

namespace tessera::render {

class SceneGraph {
 public:
  // The programs every mesh and material uses.
  struct Programs {
    optix::Program closest_hit;  // radiance rays
    optix::Program attributes;
  };

  // Builds the meshes, materials and textures of `assets` in `context`; `assets` must outlive the
  // graph. Throws optix::Exception for an API failure; INVALID_ARGUMENT names a mesh or material
  // that refers to something that is not there.
  static absl::StatusOr<SceneGraph> Build(optix::Context context, const Programs& programs,
                                          const Assets& assets);

  // Makes the graph show `frame`: one Transform per instance of a mesh with triangles (instances
  // whose matrix is singular are left out, as zero-scaled glTF nodes show nothing), the `lights`
  // buffer and the emissive triangles (`emissive_triangles`, `emissive_cdf`, `emissive_power`),
  // all context variables. Throws optix::Exception for an API failure.
  void SetFrame(const Frame& frame);

  optix::Group top() const { return top_; }
  size_t emissive_triangle_count() const { return emissive_count_; }

 private:
  SceneGraph() = default;
  void UpdateLights(const Frame& frame);
  void UpdateEmissiveTriangles(const Frame& frame);

  // The material `mesh` is shaded with: its own, or the default (white, rough, dielectric).
  const Material& MaterialOf(const Mesh& mesh) const;

  optix::Context context_;
  const Assets* assets_ = nullptr;
  std::vector<optix::GeometryGroup> mesh_groups_;  // per mesh; null for one without triangles
  Material default_material_;
  std::vector<int> texture_ids_;  // sampler id per texture of the assets
  optix::Group top_;
  optix::Acceleration top_acceleration_;
  std::vector<optix::Transform> transforms_;
  optix::Buffer lights_;
  optix::Buffer emissive_triangles_;
  optix::Buffer emissive_cdf_;
  size_t emissive_count_ = 0;
};

}  // namespace tessera::render

#endif  // TESSERA_TOOLS_TESSERA_RENDER_SCENE_GRAPH_H_

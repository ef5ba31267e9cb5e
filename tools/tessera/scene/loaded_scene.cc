#include "loaded_scene.h"

#include <algorithm>
#include <limits>
#include <utility>

namespace tessera::render {

LoadedScene::LoadedScene(Assets assets, SceneGraphData graph, std::vector<std::string> warnings)
    : graph_(std::move(graph)) {
  assets_ = std::move(assets);
  warnings_ = std::move(warnings);
  time_begin_ = graph_.time_begin;
  time_end_ = graph_.time_end;
  // Per-mesh boxes once, so that a frame's bounds cost 8 corners per instance, not its vertices.
  mesh_bounds_.reserve(assets_.meshes.size());
  for (const Mesh& mesh : assets_.meshes) {
    constexpr double kInf = std::numeric_limits<double>::infinity();
    std::array<double, 6> box{kInf, kInf, kInf, -kInf, -kInf, -kInf};
    for (size_t i = 0; i + 2 < mesh.positions.size(); i += 3) {
      for (int a = 0; a < 3; ++a) {
        box[a] = std::min<double>(box[a], mesh.positions[i + a]);
        box[a + 3] = std::max<double>(box[a + 3], mesh.positions[i + a]);
      }
    }
    mesh_bounds_.push_back(box);
  }
}

Frame LoadedScene::FrameAt(double time) const {
  Frame frame;
  frame.time = time;

  std::vector<Trs> local(graph_.nodes.size());
  for (size_t i = 0; i < graph_.nodes.size(); ++i) local[i] = graph_.nodes[i].trs;
  for (const AnimationChannel& channel : graph_.channels) {
    double value[4];
    SampleChannel(channel, time, value);
    Trs& trs = local[channel.node];
    switch (channel.property) {
      case AnimatedProperty::kTranslation:
        std::copy(value, value + 3, trs.translation.begin());
        break;
      case AnimatedProperty::kRotation:
        std::copy(value, value + 4, trs.rotation.begin());
        break;
      case AnimatedProperty::kScale:
        std::copy(value, value + 3, trs.scale.begin());
        break;
    }
  }

  std::vector<AffineD> world(graph_.nodes.size());
  constexpr double kInf = std::numeric_limits<double>::infinity();
  double bounds[6] = {kInf, kInf, kInf, -kInf, -kInf, -kInf};
  for (size_t i = 0; i < graph_.nodes.size(); ++i) {
    const SceneNode& node = graph_.nodes[i];
    const AffineD to_parent = node.has_matrix ? node.matrix : TrsToAffine(local[i]);
    world[i] = node.parent < 0 ? to_parent : Compose(world[node.parent], to_parent);
    const Affine to_world = ToFloat(world[i]);

    for (int mesh : node.meshes) {
      frame.instances.push_back({mesh, to_world});
      const std::array<double, 6>& box = mesh_bounds_[mesh];
      if (box[0] > box[3]) continue;  // no vertices
      for (int corner = 0; corner < 8; ++corner) {
        const std::array<double, 3> p = TransformPoint(
            world[i], {box[corner & 1 ? 3 : 0], box[corner & 2 ? 4 : 1], box[corner & 4 ? 5 : 2]});
        for (int a = 0; a < 3; ++a) {
          bounds[a] = std::min(bounds[a], p[a]);
          bounds[a + 3] = std::max(bounds[a + 3], p[a]);
        }
      }
    }
    if (node.camera >= 0) {
      frame.cameras.push_back(graph_.cameras[node.camera]);
      frame.cameras.back().to_world = to_world;
    }
    if (node.light >= 0) {
      frame.lights.push_back(graph_.lights[node.light]);
      frame.lights.back().to_world = to_world;
    }
  }
  if (bounds[0] <= bounds[3]) {
    for (int a = 0; a < 6; ++a) frame.bounds[a] = static_cast<float>(bounds[a]);
  }
  return frame;
}

}  // namespace tessera::render

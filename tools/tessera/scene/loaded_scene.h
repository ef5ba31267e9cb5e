// The one SceneFile both loaders build: a forest of nodes (glTF nodes; one identity node per OBJ
// mesh) whose transforms animation channels change, evaluated per frame time by FrameAt.
#ifndef TESSERA_TOOLS_TESSERA_SCENE_LOADED_SCENE_H_
#define TESSERA_TOOLS_TESSERA_SCENE_LOADED_SCENE_H_

#include <array>
#include <string>
#include <vector>

#include "animation.h"
#include "scene.h"
#include "transform.h"

namespace tessera::render {

struct SceneNode {
  int parent = -1;  // into SceneGraphData::nodes, always an earlier node; -1 for a root
  bool has_matrix = false;
  AffineD matrix{};         // the local transform when has_matrix (glTF nodes with a matrix)
  Trs trs;                  // otherwise, and what animation channels change
  std::vector<int> meshes;  // into Assets::meshes: one instance each
  int camera = -1;          // into SceneGraphData::cameras
  int light = -1;           // into SceneGraphData::lights
};

struct SceneGraphData {
  std::vector<SceneNode> nodes;
  // Their to_world is set per frame from the node that holds them.
  std::vector<Camera> cameras;
  std::vector<Light> lights;
  std::vector<AnimationChannel> channels;  // validated (ValidateChannel)
  double time_begin = 0.0, time_end = 0.0;
};

class LoadedScene final : public SceneFile {
 public:
  // `graph` refers to `assets` by index; the loaders check every index before building this.
  LoadedScene(Assets assets, SceneGraphData graph, std::vector<std::string> warnings);

  Frame FrameAt(double time) const override;

 private:
  SceneGraphData graph_;
  std::vector<std::array<double, 6>> mesh_bounds_;  // object-space box per mesh: min xyz, max
};

}  // namespace tessera::render

#endif  // TESSERA_TOOLS_TESSERA_SCENE_LOADED_SCENE_H_

// glTF animations into AnimationChannels over the scene's nodes.
#ifndef TESSERA_TOOLS_TESSERA_SCENE_GLTF_ANIMATION_H_
#define TESSERA_TOOLS_TESSERA_SCENE_GLTF_ANIMATION_H_

#include <vector>

#include "absl/status/statusor.h"
#include "gltf_document.h"
#include "loaded_scene.h"
#include "warnings.h"

namespace tessera::render {

// Every channel of every animation (all play at once, from their own first key) that targets the
// translation, rotation or scale of a node in the scene: `scene_node_of` maps glTF node indices
// to SceneGraphData::nodes, -1 for nodes outside the scene. Fills graph.channels and the time
// range (the earliest and latest key of all samplers). Morph weights are ignored with a warning.
absl::Status ConvertGltfAnimations(const GltfDocument& document,
                                   const std::vector<int>& scene_node_of, SceneGraphData& graph,
                                   WarningList& warnings);

}  // namespace tessera::render

#endif  // TESSERA_TOOLS_TESSERA_SCENE_GLTF_ANIMATION_H_

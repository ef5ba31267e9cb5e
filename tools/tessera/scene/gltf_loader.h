// glTF 2.0 (.gltf with its buffers and images, or .glb) into a SceneFile.
#ifndef TESSERA_TOOLS_TESSERA_SCENE_GLTF_LOADER_H_
#define TESSERA_TOOLS_TESSERA_SCENE_GLTF_LOADER_H_

#include <memory>
#include <string>

#include "absl/status/statusor.h"
#include "scene.h"

namespace tessera::render {

// Loads the default scene (or scene 0; every root node when the file has no scenes) of `path`,
// a .glb when `binary`. docs/render_scenes.md lists what is loaded, ignored or refused.
absl::StatusOr<std::unique_ptr<SceneFile>> LoadGltf(const std::string& path, bool binary);

}  // namespace tessera::render

#endif  // TESSERA_TOOLS_TESSERA_SCENE_GLTF_LOADER_H_

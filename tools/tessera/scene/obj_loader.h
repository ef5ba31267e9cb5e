// Wavefront OBJ with its MTL materials into a SceneFile.
#ifndef TESSERA_TOOLS_TESSERA_SCENE_OBJ_LOADER_H_
#define TESSERA_TOOLS_TESSERA_SCENE_OBJ_LOADER_H_

#include <memory>
#include <string>

#include "absl/status/statusor.h"
#include "scene.h"

namespace tessera::render {

// Loads `path` through tinyobjloader, polygons triangulated: one Mesh per (shape, material)
// pair, each instanced once with an identity transform; no cameras or lights (OBJ has none).
// Materials are converted as Material's comment says; textures are found relative to the .obj.
absl::StatusOr<std::unique_ptr<SceneFile>> LoadObj(const std::string& path);

}  // namespace tessera::render

#endif  // TESSERA_TOOLS_TESSERA_SCENE_OBJ_LOADER_H_

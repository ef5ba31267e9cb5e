// glTF mesh primitives into Assets::meshes: triangles, strips and fans as triangle lists, with
// POSITION, NORMAL, TEXCOORD_0 and TANGENT; every index checked against the vertex count.
#ifndef TESSERA_TOOLS_TESSERA_SCENE_GLTF_MESH_H_
#define TESSERA_TOOLS_TESSERA_SCENE_GLTF_MESH_H_

#include <vector>

#include "absl/status/statusor.h"
#include "gltf_document.h"
#include "gltf_material.h"
#include "scene.h"
#include "warnings.h"

namespace tessera::render {

// Appends glTF mesh `mesh`'s primitives to `assets` (materials through `materials`) and returns
// their Assets::meshes indices, one per primitive that has triangles. Points and lines are left
// out with a warning, morph targets ignored with one.
absl::StatusOr<std::vector<int>> ConvertGltfMesh(const GltfDocument& document, int mesh,
                                                 GltfMaterials& materials, Assets& assets,
                                                 WarningList& warnings);

}  // namespace tessera::render

#endif  // TESSERA_TOOLS_TESSERA_SCENE_GLTF_MESH_H_

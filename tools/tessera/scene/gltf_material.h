// glTF materials, textures and images into Assets, converted when a primitive first uses them:
// an image that no rendered mesh samples is never decoded.
#ifndef TESSERA_TOOLS_TESSERA_SCENE_GLTF_MATERIAL_H_
#define TESSERA_TOOLS_TESSERA_SCENE_GLTF_MATERIAL_H_

#include <map>
#include <string>
#include <utility>

#include "absl/status/statusor.h"
#include "gltf_document.h"
#include "scene.h"
#include "textures.h"
#include "warnings.h"

namespace tessera::render {

class GltfMaterials {
 public:
  // Adds to `assets` and `warnings`, which must outlive this.
  GltfMaterials(const GltfDocument& document, Assets* assets, WarningList* warnings)
      : document_(document), assets_(*assets), warnings_(*warnings) {}

  // The Assets::materials index of glTF material `material` (-1 stays -1: the default
  // material), converting it on first use.
  absl::StatusOr<int> Get(int material);

 private:
  absl::StatusOr<Material> Convert(int material);
  // The Assets::textures index for glTF texture `texture` read in `color_space`, or -1 with a
  // warning when its image cannot be read or decoded (the material keeps its factors).
  // `object` names the material and slot for messages.
  absl::StatusOr<int> TextureIndex(int texture, ColorSpace color_space, const std::string& object);

  const GltfDocument& document_;
  Assets& assets_;
  WarningList& warnings_;
  std::map<int, int> materials_;  // glTF material -> Assets::materials
  // (glTF image, colour space) -> Assets::textures, or -1 for an image that failed.
  std::map<std::pair<int, ColorSpace>, int> textures_;
};

}  // namespace tessera::render

#endif  // TESSERA_TOOLS_TESSERA_SCENE_GLTF_MATERIAL_H_

// A glTF 2.0 file (.gltf with its buffers, or .glb) parsed by tinygltf, before conversion: the
// model, and the encoded bytes of the images it names by URI, decoded later by textures.cc only
// where a material uses them.
#ifndef TESSERA_TOOLS_TESSERA_SCENE_GLTF_DOCUMENT_H_
#define TESSERA_TOOLS_TESSERA_SCENE_GLTF_DOCUMENT_H_

#include <tiny_gltf.h>

#include <map>
#include <string>
#include <vector>

#include "absl/status/statusor.h"

namespace tessera::render {

struct GltfDocument {
  std::string file;  // the path as given, for messages
  tinygltf::Model model;
  // Image index -> encoded bytes of an image given by URI (data: or a file). Images in buffer
  // views are not copied here (read through the checked view instead), and an image whose file
  // could not be read has no entry.
  std::map<int, std::vector<unsigned char>> uri_image_bytes;
};

// Parses `path` (`binary`: a .glb). INVALID_ARGUMENT for malformed JSON or binary containers and
// missing buffers, UNIMPLEMENTED naming an extension in extensionsRequired that the loaders do
// not support.
absl::StatusOr<GltfDocument> ReadGltfDocument(const std::string& path, bool binary);

// The extensions the loaders implement (and so accept in extensionsRequired).
bool IsSupportedGltfExtension(const std::string& name);

}  // namespace tessera::render

#endif  // TESSERA_TOOLS_TESSERA_SCENE_GLTF_DOCUMENT_H_

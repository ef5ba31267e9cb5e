#include "gltf_document.h"

#include <exception>

#include "absl/strings/ascii.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "absl/strings/str_split.h"

namespace tessera::render {
namespace {

// tinygltf's image hook, called while parsing. It only keeps the bytes of URI images: decoding
// waits until a material needs the image (and then goes through OpenImageIO). For an image in a
// buffer view tinygltf passes a pointer computed from the view's unchecked offset and length,
// so those bytes are never touched here; the loader reads the view after checking it.
bool KeepImageBytes(tinygltf::Image* image, const int image_index, std::string* /*err*/,
                    std::string* /*warn*/, int /*req_width*/, int /*req_height*/,
                    const unsigned char* bytes, int size, void* user_data) {
  if (image->bufferView >= 0 || size <= 0) return true;
  auto* kept = static_cast<std::map<int, std::vector<unsigned char>>*>(user_data);
  (*kept)[image_index].assign(bytes, bytes + size);
  return true;
}

std::vector<std::string> Lines(const std::string& text) {
  std::vector<std::string> lines;
  for (absl::string_view line : absl::StrSplit(text, '\n', absl::SkipWhitespace())) {
    lines.emplace_back(absl::StripAsciiWhitespace(line));
  }
  return lines;
}

}  // namespace

bool IsSupportedGltfExtension(const std::string& name) {
  return name == "KHR_lights_punctual" || name == "KHR_materials_emissive_strength" ||
         name == "KHR_materials_ior" || name == "KHR_materials_specular" ||
         name == "KHR_materials_transmission" || name == "KHR_mesh_quantization";
}

absl::StatusOr<GltfDocument> ReadGltfDocument(const std::string& path, bool binary) {
  GltfDocument document;
  document.file = path;
  tinygltf::TinyGLTF parser;
  parser.SetImageLoader(&KeepImageBytes, &document.uri_image_bytes);
  std::string error, warning;
  bool parsed = false;
  try {
    parsed = binary ? parser.LoadBinaryFromFile(&document.model, &error, &warning, path)
                    : parser.LoadASCIIFromFile(&document.model, &error, &warning, path);
  } catch (const std::exception& e) {  // std::bad_alloc for absurd sizes, a JSON exception
    return absl::InvalidArgumentError(absl::StrCat(path, ": not a glTF 2.0 file: ", e.what()));
  }
  if (!parsed) {
    std::vector<std::string> errors = Lines(error);
    return absl::InvalidArgumentError(
        absl::StrCat(path, ": not a valid glTF 2.0 ", binary ? "binary (.glb)" : "file", ": ",
                     errors.empty() ? "unreadable" : absl::StrJoin(errors, "; ")));
  }
  // tinygltf 2.7 warns only about image files it could not read. Those are left out of
  // SceneFile::warnings: the material that uses such an image reports it (GltfMaterials), and an
  // image no rendered material uses does not matter.
  for (const std::string& extension : document.model.extensionsRequired) {
    if (!IsSupportedGltfExtension(extension)) {
      return absl::UnimplementedError(absl::StrCat(path, ": requires glTF extension ", extension,
                                                   ", which tessera render does not support"));
    }
  }
  return document;
}

}  // namespace tessera::render

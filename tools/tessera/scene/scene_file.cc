// SceneFile::Open: the loader by file extension.
#include <filesystem>
#include <system_error>

#include "absl/strings/ascii.h"
#include "absl/strings/str_cat.h"
#include "gltf_loader.h"
#include "obj_loader.h"
#include "scene.h"

namespace tessera::render {

absl::StatusOr<std::unique_ptr<SceneFile>> SceneFile::Open(const std::string& path) {
  std::error_code error;
  const std::filesystem::file_status status = std::filesystem::status(path, error);
  if (!std::filesystem::exists(status)) {
    return absl::NotFoundError(absl::StrCat(path, ": no such file"));
  }
  if (!std::filesystem::is_regular_file(status)) {
    return absl::InvalidArgumentError(absl::StrCat(path, ": not a regular file"));
  }
  const std::string extension =
      absl::AsciiStrToLower(std::filesystem::path(path).extension().string());
  if (extension == ".gltf") return LoadGltf(path, /*binary=*/false);
  if (extension == ".glb") return LoadGltf(path, /*binary=*/true);
  if (extension == ".obj") return LoadObj(path);
  return absl::UnimplementedError(absl::StrCat(path, ": unknown scene format '", extension,
                                               "' (tessera render reads .gltf, .glb, .obj)"));
}

}  // namespace tessera::render

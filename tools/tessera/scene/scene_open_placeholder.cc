// SceneFile::Open until the glTF/OBJ loaders are merged: names the file and says what is missing.
// The loaders' own Open replaces this file (tools/tessera/scene/CMakeLists.txt).
#include <sys/stat.h>

#include <string>

#include "absl/status/status.h"
#include "tools/tessera/scene/scene.h"

namespace tessera::render {

absl::StatusOr<std::unique_ptr<SceneFile>> SceneFile::Open(const std::string& path) {
  struct stat st {};
  if (stat(path.c_str(), &st) != 0) {
    return absl::NotFoundError("cannot open scene '" + path + "': no such file");
  }
  return absl::UnimplementedError("cannot open scene '" + path +
                                  "': this build has no glTF/OBJ loader yet (try builtin:cornell)");
}

}  // namespace tessera::render

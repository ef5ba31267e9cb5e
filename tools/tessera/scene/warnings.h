// The loaders' notes for the user (SceneFile::warnings): one line per kind of problem, so that a
// file with a thousand morphed meshes says so once, with a count, not a thousand times.
#ifndef TESSERA_TOOLS_TESSERA_SCENE_WARNINGS_H_
#define TESSERA_TOOLS_TESSERA_SCENE_WARNINGS_H_

#include <map>
#include <string>
#include <vector>

namespace tessera::render {

class WarningList {
 public:
  explicit WarningList(std::string file) : file_(std::move(file)) {}

  // Notes `message` (about the file, which the line names) the first time `kind` is seen; later
  // notes of that kind only add to its count.
  void Add(const std::string& kind, const std::string& message);
  // "file: message", plus " (and N more like it)" where the kind repeated.
  std::vector<std::string> Lines() const;

 private:
  struct Entry {
    std::string message;
    int more = 0;
  };
  std::string file_;
  std::vector<Entry> entries_;  // in the order first seen
  std::map<std::string, size_t> index_of_kind_;
};

}  // namespace tessera::render

#endif  // TESSERA_TOOLS_TESSERA_SCENE_WARNINGS_H_

// Writes the files the scene loader tests read: glTF documents built in code (buffers embedded as
// base64 data URIs or in a .glb), PNG images written with OpenImageIO, and plain text (OBJ, MTL).
// No third-party assets: every byte a test loads is made here.
#ifndef TESSERA_TESTS_RENDER_SCENE_SCENE_FILES_H_
#define TESSERA_TESTS_RENDER_SCENE_SCENE_FILES_H_

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace tessera::render::testing {

// A fresh directory under the test's temporary directory, removed when the test process exits.
std::string MakeTempDir();
void WriteText(const std::string& path, const std::string& text);
void WriteBytes(const std::string& path, const std::vector<unsigned char>& bytes);
std::vector<unsigned char> ReadBytes(const std::string& path);
std::string Base64(const std::vector<unsigned char>& bytes);
// An 8-bit RGBA PNG of `width` x `height` texels (rgba: 4 bytes per texel, row 0 at the top).
void WritePng(const std::string& path, int width, int height,
              const std::vector<unsigned char>& rgba);

// A glTF 2.0 document and its one binary buffer, grown by the Add* calls, which return the index
// of what they add. Everything else (nodes, meshes, materials, ...) is edited in `json` directly.
class GltfBuilder {
 public:
  GltfBuilder();

  nlohmann::json json;

  // A buffer view over `bytes`, appended to the buffer at a 4-byte boundary.
  int AddView(const std::vector<unsigned char>& bytes, int byte_stride = 0);
  // An accessor of `type` ("VEC3", ...) over floats in a new tightly packed view.
  int AddFloats(const std::vector<float>& values, const std::string& type);
  // An accessor of unsigned indices: component type 5121 (byte), 5123 (short) or 5125 (int).
  int AddIndices(const std::vector<uint32_t>& indices, int component_type = 5123);
  // A mesh of one triangle primitive (positions xyz, optional indices) and a node holding it;
  // returns the node. The node is not put in any scene.
  int AddTriangleMeshNode(const std::string& name, const std::vector<float>& positions,
                          const std::vector<uint32_t>& indices = {});
  // Adds `node` to scene 0's roots (creating scene 0 on first use).
  void AddRoot(int node);

  const std::vector<unsigned char>& buffer() const { return buffer_; }

  // A .gltf with the buffer as a base64 data URI.
  void WriteGltf(const std::string& path);
  // A .glb with the buffer as its BIN chunk.
  void WriteGlb(const std::string& path);
  std::vector<unsigned char> GlbBytes();

 private:
  std::vector<unsigned char> buffer_;
};

}  // namespace tessera::render::testing

#endif  // TESSERA_TESTS_RENDER_SCENE_SCENE_FILES_H_

#include "scene_files.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <stdlib.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>

namespace tessera::render::testing {

namespace {

// Removes the test's directories when the process exits (a function-local static's destructor),
// so that repeated runs leave nothing behind in the temporary directory.
class TempDirs {
 public:
  ~TempDirs() {
    for (const std::string& dir : dirs_) {
      std::error_code ignored;
      std::filesystem::remove_all(dir, ignored);
    }
  }
  void Add(const std::string& dir) { dirs_.push_back(dir); }

 private:
  std::vector<std::string> dirs_;
};

}  // namespace

std::string MakeTempDir() {
  static TempDirs dirs;
  std::string pattern = ::testing::TempDir() + "render_scene_XXXXXX";
  if (mkdtemp(pattern.data()) == nullptr) throw std::runtime_error("mkdtemp " + pattern);
  dirs.Add(pattern);
  return pattern;
}

void WriteText(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  if (!out) throw std::runtime_error("cannot write " + path);
}

void WriteBytes(const std::string& path, const std::vector<unsigned char>& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(bytes.data()),
            static_cast<std::streamsize>(bytes.size()));
  if (!out) throw std::runtime_error("cannot write " + path);
}

std::vector<unsigned char> ReadBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::string Base64(const std::vector<unsigned char>& bytes) {
  static const char kDigits[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (size_t i = 0; i < bytes.size(); i += 3) {
    const uint32_t n = (uint32_t{bytes[i]} << 16) |
                       (i + 1 < bytes.size() ? uint32_t{bytes[i + 1]} << 8 : 0) |
                       (i + 2 < bytes.size() ? uint32_t{bytes[i + 2]} : 0);
    out += kDigits[(n >> 18) & 63];
    out += kDigits[(n >> 12) & 63];
    out += i + 1 < bytes.size() ? kDigits[(n >> 6) & 63] : '=';
    out += i + 2 < bytes.size() ? kDigits[n & 63] : '=';
  }
  return out;
}

void WritePng(const std::string& path, int width, int height,
              const std::vector<unsigned char>& rgba) {
  std::unique_ptr<OIIO::ImageOutput> out = OIIO::ImageOutput::create(path);
  OIIO::ImageSpec spec(width, height, 4, OIIO::TypeDesc::UINT8);
  // The bytes are straight (unassociated) alpha, as glTF's are: written as they are.
  spec.attribute("oiio:UnassociatedAlpha", 1);
  if (!out || !out->open(path, spec) || !out->write_image(OIIO::TypeDesc::UINT8, rgba.data()) ||
      !out->close()) {
    throw std::runtime_error("cannot write " + path + ": " + OIIO::geterror());
  }
}

GltfBuilder::GltfBuilder() {
  json["asset"] = {{"version", "2.0"}, {"generator", "tessera render_scene tests"}};
}

int GltfBuilder::AddView(const std::vector<unsigned char>& bytes, int byte_stride) {
  while (buffer_.size() % 4 != 0) buffer_.push_back(0);
  nlohmann::json view = {
      {"buffer", 0}, {"byteOffset", buffer_.size()}, {"byteLength", bytes.size()}};
  if (byte_stride > 0) view["byteStride"] = byte_stride;
  buffer_.insert(buffer_.end(), bytes.begin(), bytes.end());
  json["bufferViews"].push_back(view);
  return static_cast<int>(json["bufferViews"].size()) - 1;
}

int GltfBuilder::AddFloats(const std::vector<float>& values, const std::string& type) {
  const size_t components = type == "SCALAR" ? 1 : type == "VEC2" ? 2 : type == "VEC3" ? 3 : 4;
  std::vector<unsigned char> bytes(values.size() * 4);
  std::memcpy(bytes.data(), values.data(), bytes.size());
  const int view = AddView(bytes);
  json["accessors"].push_back({{"bufferView", view},
                               {"componentType", 5126},
                               {"count", values.size() / components},
                               {"type", type}});
  return static_cast<int>(json["accessors"].size()) - 1;
}

int GltfBuilder::AddIndices(const std::vector<uint32_t>& indices, int component_type) {
  const size_t size = component_type == 5121 ? 1 : component_type == 5123 ? 2 : 4;
  std::vector<unsigned char> bytes(indices.size() * size);
  for (size_t i = 0; i < indices.size(); ++i) {
    for (size_t b = 0; b < size; ++b) bytes[i * size + b] = (indices[i] >> (8 * b)) & 0xFF;
  }
  const int view = AddView(bytes);
  json["accessors"].push_back({{"bufferView", view},
                               {"componentType", component_type},
                               {"count", indices.size()},
                               {"type", "SCALAR"}});
  return static_cast<int>(json["accessors"].size()) - 1;
}

int GltfBuilder::AddTriangleMeshNode(const std::string& name, const std::vector<float>& positions,
                                     const std::vector<uint32_t>& indices) {
  nlohmann::json primitive = {{"attributes", {{"POSITION", AddFloats(positions, "VEC3")}}}};
  if (!indices.empty()) primitive["indices"] = AddIndices(indices);
  json["meshes"].push_back({{"name", name}, {"primitives", {primitive}}});
  json["nodes"].push_back({{"name", name}, {"mesh", json["meshes"].size() - 1}});
  return static_cast<int>(json["nodes"].size()) - 1;
}

void GltfBuilder::AddRoot(int node) {
  if (!json.contains("scenes")) {
    json["scenes"] = {{{"nodes", nlohmann::json::array()}}};
    json["scene"] = 0;
  }
  json["scenes"][0]["nodes"].push_back(node);
}

void GltfBuilder::WriteGltf(const std::string& path) {
  nlohmann::json document = json;
  if (!buffer_.empty()) {
    document["buffers"] = {{{"byteLength", buffer_.size()},
                            {"uri", "data:application/octet-stream;base64," + Base64(buffer_)}}};
  }
  WriteText(path, document.dump(1));
}

std::vector<unsigned char> GltfBuilder::GlbBytes() {
  nlohmann::json document = json;
  std::vector<unsigned char> bin = buffer_;
  while (bin.size() % 4 != 0) bin.push_back(0);
  if (!bin.empty()) document["buffers"] = {{{"byteLength", buffer_.size()}}};
  std::string text = document.dump();
  while (text.size() % 4 != 0) text += ' ';
  std::vector<unsigned char> glb;
  const auto u32 = [&glb](uint32_t v) {
    for (int b = 0; b < 4; ++b) glb.push_back((v >> (8 * b)) & 0xFF);
  };
  const uint32_t length =
      static_cast<uint32_t>(12 + 8 + text.size() + (bin.empty() ? 0 : 8 + bin.size()));
  u32(0x46546C67);  // "glTF"
  u32(2);
  u32(length);
  u32(static_cast<uint32_t>(text.size()));
  u32(0x4E4F534A);  // "JSON"
  glb.insert(glb.end(), text.begin(), text.end());
  if (!bin.empty()) {
    u32(static_cast<uint32_t>(bin.size()));
    u32(0x004E4942);  // "BIN"
    glb.insert(glb.end(), bin.begin(), bin.end());
  }
  return glb;
}

void GltfBuilder::WriteGlb(const std::string& path) { WriteBytes(path, GlbBytes()); }

}  // namespace tessera::render::testing

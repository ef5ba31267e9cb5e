// Files the loaders refuse: each gives an error status naming the file and the object, never a
// crash or a read outside the file's buffers (run under tools/sanitize.sh to check the latter).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "scene/scene.h"
#include "scene_files.h"
#include "test_util.h"

namespace tessera::render::testing {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

const std::vector<float> kTriangle = {0, 0, 0, 1, 0, 0, 0, 1, 0};

// A one-triangle scene: mesh 0 'Wheel' on node 0, POSITION in accessor 0 (buffer view 0).
GltfBuilder Wheel(const std::vector<uint32_t>& indices = {}) {
  GltfBuilder gltf;
  gltf.AddRoot(gltf.AddTriangleMeshNode("Wheel", kTriangle, indices));
  return gltf;
}

absl::Status OpenStatus(const std::string& path) { return SceneFile::Open(path).status(); }

absl::Status OpenGltf(GltfBuilder& gltf, const std::string& name = "scene.gltf") {
  const std::string path = MakeTempDir() + "/" + name;
  gltf.WriteGltf(path);
  return OpenStatus(path);
}

void ExpectError(const absl::Status& status, absl::StatusCode code,
                 const std::vector<std::string>& parts) {
  EXPECT_EQ(status.code(), code) << status;
  for (const std::string& part : parts) EXPECT_THAT(status.message(), HasSubstr(part));
}

TEST(RenderSceneErrorTest, MissingFileIsNotFoundNamingThePath) {
  const std::string path = MakeTempDir() + "/nowhere.gltf";
  ExpectError(OpenStatus(path), absl::StatusCode::kNotFound, {path});
}

TEST(RenderSceneErrorTest, UnknownFormatIsUnimplemented) {
  const std::string path = MakeTempDir() + "/scene.fbx";
  WriteText(path, "Kaydara FBX Binary");
  ExpectError(OpenStatus(path), absl::StatusCode::kUnimplemented, {path, ".fbx"});
}

TEST(RenderSceneErrorTest, MalformedJson) {
  const std::string path = MakeTempDir() + "/broken.gltf";
  WriteText(path, R"({"asset": {"version": "2.0"}, "nodes": [ {"mesh": )");
  ExpectError(OpenStatus(path), absl::StatusCode::kInvalidArgument, {path, "not a valid glTF"});
}

TEST(RenderSceneErrorTest, TruncatedAndCorruptGlb) {
  const std::string dir = MakeTempDir();
  GltfBuilder gltf = Wheel({0, 1, 2});
  const std::vector<unsigned char> glb = gltf.GlbBytes();
  // Cut inside the JSON chunk, inside the BIN chunk, and inside the header.
  for (size_t size : {glb.size() / 2, glb.size() - 4, size_t{10}}) {
    const std::string path = dir + "/cut" + std::to_string(size) + ".glb";
    WriteBytes(path, std::vector<unsigned char>(glb.begin(), glb.begin() + size));
    ExpectError(OpenStatus(path), absl::StatusCode::kInvalidArgument, {path, "binary (.glb)"});
  }
  std::vector<unsigned char> bad_magic = glb;
  bad_magic[0] = 'X';
  WriteBytes(dir + "/magic.glb", bad_magic);
  ExpectError(OpenStatus(dir + "/magic.glb"), absl::StatusCode::kInvalidArgument, {"magic.glb"});
}

TEST(RenderSceneErrorTest, AccessorPastItsBufferView) {
  GltfBuilder gltf = Wheel();
  gltf.json["accessors"][0]["count"] = 4;  // the view holds 3 VEC3 floats
  ExpectError(OpenGltf(gltf), absl::StatusCode::kInvalidArgument,
              {"scene.gltf: mesh 0 'Wheel' primitive 0 POSITION (accessor 0)",
               "4 elements of 12 bytes, 12 apart from byte 0, run past the 36 bytes of buffer "
               "view 0"});
}

TEST(RenderSceneErrorTest, AccessorOffsetsStridesAndCountsThatWouldOverflow) {
  for (const auto& [key, value] : std::vector<std::pair<std::string, nlohmann::json>>{
           {"byteOffset", uint64_t{1} << 40},
           {"count", uint64_t{1} << 62},  // count * stride wraps size_t
           {"count", std::numeric_limits<uint64_t>::max()}}) {
    GltfBuilder gltf = Wheel();
    gltf.json["accessors"][0][key] = value;
    const absl::Status status = OpenGltf(gltf);
    EXPECT_EQ(status.code(), absl::StatusCode::kInvalidArgument) << key << ": " << status;
    EXPECT_THAT(status.message(), HasSubstr("scene.gltf")) << key;
  }
  GltfBuilder strided = Wheel();
  strided.json["bufferViews"][0]["byteStride"] = 8;  // less than a VEC3 of floats
  ExpectError(OpenGltf(strided), absl::StatusCode::kInvalidArgument,
              {"POSITION", "byte stride 8 is less than its elements' 12 bytes"});
}

TEST(RenderSceneErrorTest, BufferViewPastItsBuffer) {
  GltfBuilder gltf = Wheel();
  gltf.json["bufferViews"][0]["byteOffset"] = 8;  // 36 bytes from 8 in a 36-byte buffer
  const absl::Status status = OpenGltf(gltf);
  EXPECT_EQ(status.code(), absl::StatusCode::kInvalidArgument) << status;
  EXPECT_THAT(status.message(), HasSubstr("scene.gltf"));
}

TEST(RenderSceneErrorTest, AccessorThatDoesNotExistOrHasTheWrongType) {
  GltfBuilder missing = Wheel();
  missing.json["meshes"][0]["primitives"][0]["attributes"]["NORMAL"] = 9;
  ExpectError(OpenGltf(missing), absl::StatusCode::kInvalidArgument,
              {"mesh 0 'Wheel' primitive 0 NORMAL: accessor 9 does not exist"});
  GltfBuilder wrong_type = Wheel();
  wrong_type.json["accessors"][0]["type"] = "VEC2";
  ExpectError(OpenGltf(wrong_type), absl::StatusCode::kInvalidArgument,
              {"POSITION (accessor 0): type VEC2 where VEC3 belongs"});
}

TEST(RenderSceneErrorTest, IndexPastTheVertexCount) {
  GltfBuilder gltf = Wheel({0, 1, 7});
  ExpectError(OpenGltf(gltf), absl::StatusCode::kInvalidArgument,
              {"scene.gltf: mesh 0 'Wheel' primitive 0: index 7 past its 3 vertices"});
}

TEST(RenderSceneErrorTest, SparseIndexPastTheAccessor) {
  GltfBuilder gltf = Wheel();
  const int indices = gltf.AddView({5, 0, 0, 0});
  const int values = gltf.AddView(std::vector<unsigned char>(12, 0));
  gltf.json["accessors"][0]["sparse"] = {
      {"count", 1},
      {"indices", {{"bufferView", indices}, {"componentType", 5121}}},
      {"values", {{"bufferView", values}}}};
  ExpectError(OpenGltf(gltf), absl::StatusCode::kInvalidArgument,
              {"POSITION (accessor 0): sparse index 5 past its 3 elements"});
}

TEST(RenderSceneErrorTest, UnsupportedRequiredExtensionIsUnimplementedAndAnUsedOneAWarning) {
  GltfBuilder gltf = Wheel();
  gltf.json["extensionsUsed"] = {"KHR_draco_mesh_compression", "KHR_texture_transform"};
  gltf.json["extensionsRequired"] = {"KHR_draco_mesh_compression"};
  ExpectError(OpenGltf(gltf), absl::StatusCode::kUnimplemented,
              {"scene.gltf: requires glTF extension KHR_draco_mesh_compression"});

  gltf.json.erase("extensionsRequired");
  const std::string path = MakeTempDir() + "/used.gltf";
  gltf.WriteGltf(path);
  std::unique_ptr<SceneFile> scene = OpenOrFail(path);
  ASSERT_NE(scene, nullptr);
  EXPECT_THAT(scene->warnings(),
              ::testing::ElementsAre(HasSubstr("KHR_draco_mesh_compression, which tessera render "
                                               "ignores"),
                                     HasSubstr("KHR_texture_transform")));
}

TEST(RenderSceneErrorTest, NodeCycleAndSharedChild) {
  GltfBuilder cycle = Wheel();
  cycle.json["nodes"].push_back({{"name", "Loop"}, {"children", {0}}});
  cycle.json["nodes"][0]["children"] = {1};
  ExpectError(OpenGltf(cycle), absl::StatusCode::kInvalidArgument,
              {"scene.gltf: node 0 'Wheel' is reached twice"});
  GltfBuilder shared = Wheel();
  shared.json["nodes"].push_back({{"name", "SecondParent"}, {"children", {0}}});
  shared.AddRoot(1);  // node 0 is a root and node 1's child
  ExpectError(OpenGltf(shared), absl::StatusCode::kInvalidArgument,
              {"node 0 'Wheel' is reached twice"});
  GltfBuilder missing = Wheel();
  missing.json["nodes"][0]["children"] = {42};
  ExpectError(OpenGltf(missing), absl::StatusCode::kInvalidArgument, {"node 42 does not exist"});
}

TEST(RenderSceneErrorTest, NoTrianglesIsUnimplemented) {
  GltfBuilder gltf = Wheel();
  gltf.json["meshes"][0]["primitives"][0]["mode"] = 1;  // LINES
  ExpectError(OpenGltf(gltf), absl::StatusCode::kUnimplemented,
              {"scene.gltf: its scene holds no triangles"});
}

TEST(RenderSceneErrorTest, MissingExternalBuffer) {
  GltfBuilder gltf = Wheel();
  const std::string dir = MakeTempDir();
  gltf.WriteGltf(dir + "/external.gltf");
  nlohmann::json document = nlohmann::json::parse(ReadBytes(dir + "/external.gltf"));
  document["buffers"][0]["uri"] = "geometry.bin";
  WriteText(dir + "/external.gltf", document.dump());
  ExpectError(OpenStatus(dir + "/external.gltf"), absl::StatusCode::kInvalidArgument,
              {"external.gltf", "geometry.bin"});
  // With the file there, the same document loads.
  WriteBytes(dir + "/geometry.bin", gltf.buffer());
  EXPECT_NE(OpenOrFail(dir + "/external.gltf"), nullptr);
}

}  // namespace
}  // namespace tessera::render::testing

// glTF node hierarchies, cameras, lights and primitives through SceneFile::Open.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "scene/scene.h"
#include "scene_files.h"
#include "test_util.h"

namespace tessera::render::testing {
namespace {

using ::testing::ElementsAre;
using ::testing::ElementsAreArray;
using ::testing::FloatNear;
using ::testing::HasSubstr;
using ::testing::Pointwise;

const std::vector<float> kTriangle = {0, 0, 0, 1, 0, 0, 0, 1, 0};
const float kHalfSqrt2 = std::sqrt(0.5f);

// T(1, 2, 3) * Rz(90 degrees) * S(2): x goes to 2y, y to -2x.
const std::array<float, 12> kParentWorld = {0, -2, 0, 1, 2, 0, 0, 2, 0, 0, 2, 3};

TEST(RenderSceneGltfTest, NodeHierarchyComposesTrsAndMatrixTransforms) {
  GltfBuilder gltf;
  const int parent = gltf.AddTriangleMeshNode("Parent", kTriangle);
  gltf.json["nodes"][parent]["translation"] = {1, 2, 3};
  gltf.json["nodes"][parent]["rotation"] = {0, 0, kHalfSqrt2, kHalfSqrt2};
  gltf.json["nodes"][parent]["scale"] = {2, 2, 2};
  const int child = gltf.AddTriangleMeshNode("Child", kTriangle);
  // Column-major translation by (1, 0, 0): in the parent's frame, 2 units along world +y.
  gltf.json["nodes"][child]["matrix"] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 1, 0, 0, 1};
  gltf.json["nodes"][parent]["children"] = {child};
  gltf.AddRoot(parent);
  const std::string dir = MakeTempDir();
  gltf.WriteGltf(dir + "/hierarchy.gltf");

  std::unique_ptr<SceneFile> scene = OpenOrFail(dir + "/hierarchy.gltf");
  ASSERT_NE(scene, nullptr);
  EXPECT_THAT(scene->warnings(), ::testing::IsEmpty());
  ASSERT_EQ(scene->assets().meshes.size(), 2u);
  EXPECT_EQ(scene->assets().meshes[0].name, "Parent");
  EXPECT_THAT(scene->assets().meshes[0].positions, ElementsAreArray(kTriangle));
  // Non-indexed: one index per vertex, in order.
  EXPECT_THAT(scene->assets().meshes[0].indices, ElementsAre(0, 1, 2));
  EXPECT_EQ(scene->time_begin(), 0.0);
  EXPECT_EQ(scene->time_end(), 0.0);

  const Frame frame = scene->FrameAt(0.0);
  ASSERT_EQ(frame.instances.size(), 2u);
  EXPECT_EQ(frame.instances[0].mesh, 0);
  ExpectAffineNear(frame.instances[0].to_world, kParentWorld);
  EXPECT_EQ(frame.instances[1].mesh, 1);
  ExpectAffineNear(frame.instances[1].to_world, {0, -2, 0, 1, 2, 0, 0, 4, 0, 0, 2, 3});
  // Parent's triangle spans x in [-1, 1], y in [2, 4]; the child's y in [4, 6]; z = 3.
  EXPECT_THAT(frame.bounds, Pointwise(FloatNear(1e-5f), {-1.f, 2.f, 3.f, 1.f, 6.f, 3.f}));
}

TEST(RenderSceneGltfTest, MatrixAndTrsOfTheSameTransformAgree) {
  GltfBuilder gltf;
  const int trs = gltf.AddTriangleMeshNode("Trs", kTriangle);
  gltf.json["nodes"][trs]["translation"] = {1, 2, 3};
  gltf.json["nodes"][trs]["rotation"] = {0, 0, kHalfSqrt2, kHalfSqrt2};
  gltf.json["nodes"][trs]["scale"] = {2, 2, 2};
  const int matrix = gltf.AddTriangleMeshNode("Matrix", kTriangle);
  gltf.json["nodes"][matrix]["matrix"] = {0, 2, 0, 0, -2, 0, 0, 0, 0, 0, 2, 0, 1, 2, 3, 1};
  // A node that is not in the scene is not instanced.
  gltf.AddTriangleMeshNode("Elsewhere", kTriangle);
  gltf.AddRoot(trs);
  gltf.AddRoot(matrix);
  const std::string dir = MakeTempDir();
  gltf.WriteGltf(dir + "/same.gltf");

  std::unique_ptr<SceneFile> scene = OpenOrFail(dir + "/same.gltf");
  ASSERT_NE(scene, nullptr);
  EXPECT_EQ(scene->assets().meshes.size(), 2u);
  const Frame frame = scene->FrameAt(0.0);
  ASSERT_EQ(frame.instances.size(), 2u);
  ExpectAffineNear(frame.instances[0].to_world, kParentWorld);
  ExpectAffineNear(frame.instances[1].to_world, kParentWorld);
}

TEST(RenderSceneGltfTest, CamerasAndPunctualLightsTakeTheirNodesTransforms) {
  GltfBuilder gltf;
  gltf.AddTriangleMeshNode("Ground", kTriangle);
  gltf.json["extensionsUsed"] = {"KHR_lights_punctual"};
  gltf.json["extensionsRequired"] = {"KHR_lights_punctual"};  // supported, so accepted
  gltf.json["cameras"] = {
      {{"name", "Main"},
       {"type", "perspective"},
       {"perspective", {{"yfov", 0.8}, {"aspectRatio", 1.5}, {"znear", 0.1}, {"zfar", 100}}}},
      {{"type", "orthographic"},
       {"orthographic", {{"xmag", 2}, {"ymag", 3}, {"znear", 0.5}, {"zfar", 10}}}},
  };
  gltf.json["extensions"]["KHR_lights_punctual"]["lights"] = {
      {{"name", "Bulb"},
       {"type", "point"},
       {"color", {1, 0.5, 0.25}},
       {"intensity", 40},
       {"range", 12}},
      {{"type", "spot"},
       {"intensity", 100},
       {"spot", {{"innerConeAngle", 0.2}, {"outerConeAngle", 0.6}}}},
      {{"name", "Sun"}, {"type", "directional"}, {"intensity", 3}},
  };
  // Nodes: 0 Ground, 1 CamNode, 2 OrthoNode, 3 BulbNode, 4 Rig, 5 SpotNode, 6 SunNode.
  nlohmann::json& nodes = gltf.json["nodes"];
  nodes.push_back({{"name", "CamNode"}, {"camera", 0}, {"translation", {0, 1, 5}}});
  nodes.push_back({{"name", "OrthoNode"}, {"camera", 1}});
  nodes.push_back({{"name", "BulbNode"},
                   {"translation", {0, 4, 0}},
                   {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
  // The spot hangs below a translated parent: its world transform composes both.
  nodes.push_back({{"name", "Rig"}, {"translation", {10, 0, 0}}, {"children", {5}}});
  nodes.push_back({{"name", "SpotNode"},
                   {"translation", {0, 0, -1}},
                   {"extensions", {{"KHR_lights_punctual", {{"light", 1}}}}}});
  nodes.push_back({{"name", "SunNode"},
                   {"rotation", {-kHalfSqrt2, 0, 0, kHalfSqrt2}},  // -Z turned to point down
                   {"extensions", {{"KHR_lights_punctual", {{"light", 2}}}}}});
  for (int root : {0, 1, 2, 3, 4, 6}) gltf.AddRoot(root);
  const std::string dir = MakeTempDir();
  gltf.WriteGltf(dir + "/lights.gltf");

  std::unique_ptr<SceneFile> scene = OpenOrFail(dir + "/lights.gltf");
  ASSERT_NE(scene, nullptr);
  EXPECT_THAT(scene->warnings(), ::testing::IsEmpty());
  const Frame frame = scene->FrameAt(0.0);

  ASSERT_EQ(frame.cameras.size(), 2u);
  const Camera& main = frame.cameras[0];
  EXPECT_EQ(main.name, "Main");
  EXPECT_FALSE(main.orthographic);
  EXPECT_FLOAT_EQ(main.yfov, 0.8f);
  EXPECT_FLOAT_EQ(main.aspect, 1.5f);
  EXPECT_FLOAT_EQ(main.znear, 0.1f);
  ExpectAffineNear(main.to_world, {1, 0, 0, 0, 0, 1, 0, 1, 0, 0, 1, 5});
  const Camera& ortho = frame.cameras[1];
  EXPECT_EQ(ortho.name, "OrthoNode");  // the camera has no name: its node's
  EXPECT_TRUE(ortho.orthographic);
  EXPECT_FLOAT_EQ(ortho.xmag, 2.f);
  EXPECT_FLOAT_EQ(ortho.ymag, 3.f);
  EXPECT_FLOAT_EQ(ortho.znear, 0.5f);

  ASSERT_EQ(frame.lights.size(), 3u);
  const Light& bulb = frame.lights[0];
  EXPECT_EQ(bulb.name, "Bulb");
  EXPECT_EQ(bulb.type, Light::Type::kPoint);
  EXPECT_THAT(bulb.color, ElementsAre(1.f, 0.5f, 0.25f));
  EXPECT_FLOAT_EQ(bulb.intensity, 40.f);
  EXPECT_FLOAT_EQ(bulb.range, 12.f);
  ExpectAffineNear(bulb.to_world, {1, 0, 0, 0, 0, 1, 0, 4, 0, 0, 1, 0});
  const Light& spot = frame.lights[1];
  EXPECT_EQ(spot.name, "SpotNode");
  EXPECT_EQ(spot.type, Light::Type::kSpot);
  EXPECT_THAT(spot.color, ElementsAre(1.f, 1.f, 1.f));
  EXPECT_FLOAT_EQ(spot.intensity, 100.f);
  EXPECT_FLOAT_EQ(spot.range, 0.f);  // infinite
  EXPECT_FLOAT_EQ(spot.inner_cone, 0.2f);
  EXPECT_FLOAT_EQ(spot.outer_cone, 0.6f);
  ExpectAffineNear(spot.to_world, {1, 0, 0, 10, 0, 1, 0, 0, 0, 0, 1, -1});
  const Light& sun = frame.lights[2];
  EXPECT_EQ(sun.type, Light::Type::kDirectional);
  EXPECT_FLOAT_EQ(sun.intensity, 3.f);
  // Rx(-90 degrees): the light's -Z (its direction) is the third column negated: (0, -1, 0).
  EXPECT_NEAR(-sun.to_world[2], 0.f, 1e-6f);
  EXPECT_NEAR(-sun.to_world[6], -1.f, 1e-6f);
  EXPECT_NEAR(-sun.to_world[10], 0.f, 1e-6f);
}

std::vector<unsigned char> Bytes(const std::vector<float>& values) {
  std::vector<unsigned char> bytes(values.size() * 4);
  std::memcpy(bytes.data(), values.data(), bytes.size());
  return bytes;
}

TEST(RenderSceneGltfTest, PrimitivesOfEveryIndexTypeModeAndSparsePositions) {
  GltfBuilder gltf;
  const int positions = gltf.AddFloats({0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0}, "VEC3");
  const int u8 = gltf.AddIndices({0, 1, 2}, 5121);
  const int u32 = gltf.AddIndices({2, 1, 3}, 5125);
  // TEXCOORD_0 as normalized unsigned bytes, 4 bytes apart (KHR_mesh_quantization's layout).
  const int uv_view = gltf.AddView({0, 255, 0, 0, 255, 0, 0, 0, 51, 102, 0, 0, 255, 255, 0, 0}, 4);
  gltf.json["accessors"].push_back({{"bufferView", uv_view},
                                    {"componentType", 5121},
                                    {"normalized", true},
                                    {"count", 4},
                                    {"type", "VEC2"}});
  const int uvs = static_cast<int>(gltf.json["accessors"].size()) - 1;
  const int normals = gltf.AddFloats({0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1}, "VEC3");
  const int tangents = gltf.AddFloats({1, 0, 0, 1, 1, 0, 0, 1, 1, 0, 0, 1, 1, 0, 0, -1}, "VEC4");
  // Sparse: vertex 2 of the base positions replaced by (0, 0, 7).
  const int sparse_index = gltf.AddView({2, 0, 0, 0});
  const int sparse_value = gltf.AddView(Bytes({0, 0, 7}));
  nlohmann::json sparse = gltf.json["accessors"][positions];
  sparse["sparse"] = {{"count", 1},
                      {"indices", {{"bufferView", sparse_index}, {"componentType", 5121}}},
                      {"values", {{"bufferView", sparse_value}}}};
  gltf.json["accessors"].push_back(sparse);
  const int sparse_positions = static_cast<int>(gltf.json["accessors"].size()) - 1;

  const nlohmann::json position_only = {{"POSITION", positions}};
  gltf.json["meshes"] = {{
      {"name", "Strip"},
      {"primitives",
       {
           {{"attributes",
             {{"POSITION", positions},
              {"NORMAL", normals},
              {"TEXCOORD_0", uvs},
              {"TANGENT", tangents}}},
            {"indices", u8}},
           {{"attributes", position_only}, {"indices", u32}},
           {{"attributes", position_only}, {"mode", 5}},  // TRIANGLE_STRIP, no indices
           {{"attributes", position_only}, {"mode", 6}},  // TRIANGLE_FAN
           {{"attributes", position_only}, {"mode", 0}},  // POINTS: left out
           {{"attributes", {{"POSITION", sparse_positions}}}, {"indices", u8}},
       }},
  }};
  gltf.json["nodes"] = {{{"mesh", 0}}};
  gltf.AddRoot(0);
  const std::string dir = MakeTempDir();
  gltf.WriteGltf(dir + "/primitives.gltf");

  std::unique_ptr<SceneFile> scene = OpenOrFail(dir + "/primitives.gltf");
  ASSERT_NE(scene, nullptr);
  const std::vector<Mesh>& meshes = scene->assets().meshes;
  ASSERT_EQ(meshes.size(), 5u);
  EXPECT_EQ(meshes[0].name, "Strip/0");
  EXPECT_THAT(meshes[0].indices, ElementsAre(0, 1, 2));
  EXPECT_THAT(meshes[0].normals, ElementsAre(0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1));
  EXPECT_THAT(meshes[0].texcoords,
              Pointwise(FloatNear(1e-6f), {0.f, 1.f, 1.f, 0.f, 0.2f, 0.4f, 1.f, 1.f}));
  EXPECT_THAT(meshes[0].tangents, ElementsAre(1, 0, 0, 1, 1, 0, 0, 1, 1, 0, 0, 1, 1, 0, 0, -1));
  EXPECT_THAT(meshes[1].indices, ElementsAre(2, 1, 3));
  EXPECT_TRUE(meshes[1].normals.empty());
  EXPECT_TRUE(meshes[1].texcoords.empty());
  // glTF 2.0 3.7.2.1: strip triangle i is (i, i + 1 + i % 2, i + 2 - i % 2); fan (i+1, i+2, 0).
  EXPECT_THAT(meshes[2].indices, ElementsAre(0, 1, 2, 1, 3, 2));
  EXPECT_THAT(meshes[3].indices, ElementsAre(1, 2, 0, 2, 3, 0));
  EXPECT_THAT(meshes[4].positions, ElementsAre(0, 0, 0, 1, 0, 0, 0, 0, 7, 1, 1, 0));
  ASSERT_EQ(scene->warnings().size(), 1u);
  EXPECT_THAT(scene->warnings()[0], HasSubstr("POINTS"));
  EXPECT_THAT(scene->warnings()[0], HasSubstr("primitives.gltf: mesh 0 'Strip' primitive 4"));
  EXPECT_EQ(scene->FrameAt(0).instances.size(), 5u);
}

TEST(RenderSceneGltfTest, MorphTargetsAndSkinsAreIgnoredWithOneWarningEach) {
  GltfBuilder gltf;
  const int positions = gltf.AddFloats(kTriangle, "VEC3");
  const int offsets = gltf.AddFloats({0, 0, 1, 0, 0, 1, 0, 0, 1}, "VEC3");
  const nlohmann::json morphed = {{"attributes", {{"POSITION", positions}}},
                                  {"targets", {{{"POSITION", offsets}}}}};
  gltf.json["meshes"] = {{{"name", "Face"}, {"primitives", {morphed, morphed}}, {"weights", {1}}}};
  gltf.json["nodes"] = {{{"name", "Body"}, {"mesh", 0}, {"skin", 0}}, {{"name", "Bone"}}};
  gltf.json["skins"] = {{{"joints", {1}}}};
  gltf.AddRoot(0);
  gltf.AddRoot(1);
  const std::string dir = MakeTempDir();
  gltf.WriteGltf(dir + "/morph.gltf");

  std::unique_ptr<SceneFile> scene = OpenOrFail(dir + "/morph.gltf");
  ASSERT_NE(scene, nullptr);
  // The base shape: the targets' offsets are not applied.
  EXPECT_THAT(scene->assets().meshes.at(0).positions, ElementsAreArray(kTriangle));
  EXPECT_THAT(scene->warnings(),
              ElementsAre(AllOf(HasSubstr("morph.gltf: mesh 0 'Face' primitive 0: morph targets"),
                                HasSubstr("(and 1 more like it)")),
                          HasSubstr("node 0 'Body': skins are not supported")));
}

TEST(RenderSceneGltfTest, AFileWithoutScenesRendersEveryRootNode) {
  GltfBuilder gltf;
  const int a = gltf.AddTriangleMeshNode("A", kTriangle);
  const int b = gltf.AddTriangleMeshNode("B", kTriangle);
  gltf.json["nodes"][a]["children"] = {b};
  gltf.AddTriangleMeshNode("C", kTriangle);
  const std::string dir = MakeTempDir();
  gltf.WriteGltf(dir + "/no_scenes.gltf");

  std::unique_ptr<SceneFile> scene = OpenOrFail(dir + "/no_scenes.gltf");
  ASSERT_NE(scene, nullptr);
  EXPECT_EQ(scene->FrameAt(0).instances.size(), 3u);
}

}  // namespace
}  // namespace tessera::render::testing

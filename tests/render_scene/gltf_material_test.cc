// glTF materials and textures: factors and extensions, images from data URIs, files beside the
// .gltf and .glb buffer views, sRGB decoding of colour textures only, and missing images.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>

#include "scene/scene.h"
#include "scene_files.h"
#include "test_util.h"

namespace tessera::render::testing {
namespace {

using ::testing::ElementsAre;
using ::testing::FloatNear;
using ::testing::HasSubstr;
using ::testing::Pointwise;

const std::vector<float> kTriangle = {0, 0, 0, 1, 0, 0, 0, 1, 0};
// sRGB 188 and 64 (of 255) in linear light: ((c / 255 + 0.055) / 1.055)^2.4.
constexpr float kLinear188 = 0.50288646f;
constexpr float kLinear64 = 0.05126946f;

// 2x1 texels: (188, 64, 255, 128) then opaque black.
const std::vector<unsigned char> kBaseTexels = {188, 64, 255, 128, 0, 0, 0, 255};

nlohmann::json FullMaterial() {
  return {{"name", "Everything"},
          {"pbrMetallicRoughness",
           {{"baseColorFactor", {0.5, 0.6, 0.7, 0.8}},
            {"baseColorTexture", {{"index", 0}}},
            {"metallicFactor", 0.25},
            {"roughnessFactor", 0.75},
            {"metallicRoughnessTexture", {{"index", 1}}}}},
          {"normalTexture", {{"index", 1}, {"scale", 0.5}}},
          {"emissiveFactor", {1, 0.5, 0}},
          {"emissiveTexture", {{"index", 2}}},
          {"doubleSided", true},
          {"extensions",
           {{"KHR_materials_emissive_strength", {{"emissiveStrength", 4}}},
            {"KHR_materials_ior", {{"ior", 1.33}}},
            {"KHR_materials_specular", {{"specularFactor", 0.4}}},
            {"KHR_materials_transmission", {{"transmissionFactor", 0.7}}}}}};
}

TEST(RenderSceneGltfMaterialTest, FactorsExtensionsAndTexturesFromDataUriAndFiles) {
  const std::string dir = MakeTempDir();
  WritePng(dir + "/base.png", 2, 1, kBaseTexels);
  std::filesystem::create_directory(dir + "/tex");
  WritePng(dir + "/tex/mr.png", 1, 1, {188, 188, 64, 255});

  GltfBuilder gltf;
  const int node = gltf.AddTriangleMeshNode("Lit", kTriangle);
  gltf.json["meshes"][0]["primitives"][0]["material"] = 0;
  // A second primitive without a material: the default one.
  gltf.json["meshes"][0]["primitives"].push_back(gltf.json["meshes"][0]["primitives"][0]);
  gltf.json["meshes"][0]["primitives"][1].erase("material");
  gltf.AddRoot(node);
  gltf.json["extensionsUsed"] = {"KHR_materials_emissive_strength", "KHR_materials_ior",
                                 "KHR_materials_specular", "KHR_materials_transmission"};
  gltf.json["materials"] = {FullMaterial()};
  gltf.json["images"] = {
      {{"uri", "data:image/png;base64," + Base64(ReadBytes(dir + "/base.png"))}},
      {{"uri", "tex/mr.png"}},
      {{"uri", "missing.png"}},  // no such file: a warning, and the emissive factor alone
  };
  gltf.json["textures"] = {{{"source", 0}}, {{"source", 1}}, {{"source", 2}}};
  gltf.WriteGltf(dir + "/material.gltf");

  std::unique_ptr<SceneFile> scene = OpenOrFail(dir + "/material.gltf");
  ASSERT_NE(scene, nullptr);
  const Assets& assets = scene->assets();
  ASSERT_EQ(assets.meshes.size(), 2u);
  EXPECT_EQ(assets.meshes[0].material, 0);
  EXPECT_EQ(assets.meshes[1].material, -1);
  ASSERT_EQ(assets.materials.size(), 1u);
  const Material& m = assets.materials[0];
  EXPECT_EQ(m.name, "Everything");
  EXPECT_THAT(m.base_color, ElementsAre(0.5f, 0.6f, 0.7f, 0.8f));
  EXPECT_FLOAT_EQ(m.metallic, 0.25f);
  EXPECT_FLOAT_EQ(m.roughness, 0.75f);
  EXPECT_THAT(m.emissive, ElementsAre(4.f, 2.f, 0.f));  // factor times strength
  EXPECT_FLOAT_EQ(m.normal_scale, 0.5f);
  EXPECT_TRUE(m.double_sided);
  EXPECT_FLOAT_EQ(m.ior, 1.33f);
  EXPECT_FLOAT_EQ(m.transmission, 0.7f);
  EXPECT_FLOAT_EQ(m.specular, 0.4f);

  // Colour (sRGB) base colour; the metallic-roughness and normal maps share one linear image.
  ASSERT_EQ(assets.textures.size(), 2u);
  ASSERT_EQ(m.base_color_texture, 0);
  EXPECT_EQ(m.metallic_roughness_texture, 1);
  EXPECT_EQ(m.normal_texture, 1);
  EXPECT_EQ(m.emissive_texture, -1);
  const Texture& base = assets.textures[0];
  EXPECT_EQ(base.width, 2);
  EXPECT_EQ(base.height, 1);
  // Alpha is not sRGB-decoded, nor premultiplied into the colour.
  EXPECT_THAT(base.rgba, Pointwise(FloatNear(1e-5f),
                                   {kLinear188, kLinear64, 1.f, 128 / 255.f, 0.f, 0.f, 0.f, 1.f}));
  const Texture& mr = assets.textures[1];
  EXPECT_EQ(mr.name, "tex/mr.png");
  EXPECT_THAT(mr.rgba, Pointwise(FloatNear(1e-6f), {188 / 255.f, 188 / 255.f, 64 / 255.f, 1.f}));

  EXPECT_THAT(scene->warnings(),
              ElementsAre(AllOf(HasSubstr("material.gltf: material 0 'Everything' emissiveTexture"),
                                HasSubstr("'missing.png' cannot be read"),
                                HasSubstr("uses its factor alone"))));
}

TEST(RenderSceneGltfMaterialTest, GlbWithAnImageInABufferView) {
  const std::string dir = MakeTempDir();
  WritePng(dir + "/base.png", 2, 1, kBaseTexels);
  GltfBuilder gltf;
  gltf.AddRoot(gltf.AddTriangleMeshNode("Boxed", kTriangle, {0, 1, 2}));
  gltf.json["meshes"][0]["primitives"][0]["material"] = 0;
  gltf.json["materials"] = {{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}};
  gltf.json["images"] = {
      {{"bufferView", gltf.AddView(ReadBytes(dir + "/base.png"))}, {"mimeType", "image/png"}}};
  gltf.json["textures"] = {{{"source", 0}}};
  // The extension is matched without regard to case.
  gltf.WriteGlb(dir + "/boxed.GLB");

  std::unique_ptr<SceneFile> scene = OpenOrFail(dir + "/boxed.GLB");
  ASSERT_NE(scene, nullptr);
  EXPECT_THAT(scene->warnings(), ::testing::IsEmpty());
  const Assets& assets = scene->assets();
  ASSERT_EQ(assets.meshes.size(), 1u);
  EXPECT_THAT(assets.meshes[0].positions, Pointwise(FloatNear(0.f), kTriangle));
  EXPECT_THAT(assets.meshes[0].indices, ElementsAre(0, 1, 2));
  ASSERT_EQ(assets.materials.size(), 1u);
  // Defaults where the file says nothing.
  EXPECT_THAT(assets.materials[0].base_color, ElementsAre(1.f, 1.f, 1.f, 1.f));
  EXPECT_FLOAT_EQ(assets.materials[0].metallic, 1.f);
  EXPECT_FLOAT_EQ(assets.materials[0].ior, 1.5f);
  EXPECT_FLOAT_EQ(assets.materials[0].specular, 1.f);
  EXPECT_FALSE(assets.materials[0].double_sided);
  ASSERT_EQ(assets.materials[0].base_color_texture, 0);
  EXPECT_NEAR(assets.textures.at(0).rgba[0], kLinear188, 1e-5f);
  EXPECT_NEAR(assets.textures.at(0).rgba[1], kLinear64, 1e-5f);
}

TEST(RenderSceneGltfMaterialTest, UndecodableImageBytesAreAWarning) {
  GltfBuilder gltf;
  gltf.AddRoot(gltf.AddTriangleMeshNode("Broken", kTriangle));
  gltf.json["meshes"][0]["primitives"][0]["material"] = 0;
  gltf.json["materials"] = {{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}};
  // A real PNG whose compressed pixels are damaged: its header reads, its pixels do not. (A
  // truncated PNG would do too, but OpenImageIO 2.4 leaks its error message then: libpng
  // longjmps past it, which LeakSanitizer reports in tools/sanitize.sh.)
  const std::string dir = MakeTempDir();
  WritePng(dir + "/damaged.png", 2, 1, kBaseTexels);
  std::vector<unsigned char> png = ReadBytes(dir + "/damaged.png");
  const std::string idat = "IDAT";
  const auto chunk = std::search(png.begin(), png.end(), idat.begin(), idat.end());
  ASSERT_NE(chunk, png.end());
  chunk[6] ^= 0xFF;  // inside the zlib stream, past its 2-byte header
  chunk[7] ^= 0x55;
  gltf.json["images"] = {
      {{"name", "Garbage"}, {"bufferView", gltf.AddView(png)}, {"mimeType", "image/png"}}};
  gltf.json["textures"] = {{{"source", 0}}};
  gltf.WriteGltf(dir + "/garbage.gltf");

  std::unique_ptr<SceneFile> scene = OpenOrFail(dir + "/garbage.gltf");
  ASSERT_NE(scene, nullptr);
  EXPECT_EQ(scene->assets().materials.at(0).base_color_texture, -1);
  EXPECT_TRUE(scene->assets().textures.empty());
  ASSERT_EQ(scene->warnings().size(), 1u);
  EXPECT_THAT(scene->warnings()[0],
              AllOf(HasSubstr("garbage.gltf: material 0 '' baseColorTexture: Garbage"),
                    HasSubstr("cannot decode")));
}

TEST(RenderSceneGltfMaterialTest, OutOfRangeFactorsAreClampedAndATextureIndexPastTheEndIsAnError) {
  GltfBuilder gltf;
  gltf.AddRoot(gltf.AddTriangleMeshNode("Odd", kTriangle));
  gltf.json["meshes"][0]["primitives"][0]["material"] = 0;
  gltf.json["materials"] = {
      {{"name", "Odd"},
       {"pbrMetallicRoughness", {{"baseColorFactor", {2, -1, 0.5, 1}}, {"metallicFactor", 3}}}}};
  const std::string dir = MakeTempDir();
  gltf.WriteGltf(dir + "/odd.gltf");
  std::unique_ptr<SceneFile> scene = OpenOrFail(dir + "/odd.gltf");
  ASSERT_NE(scene, nullptr);
  EXPECT_THAT(scene->assets().materials.at(0).base_color, ElementsAre(1.f, 0.f, 0.5f, 1.f));
  EXPECT_FLOAT_EQ(scene->assets().materials.at(0).metallic, 1.f);

  gltf.json["materials"][0]["normalTexture"] = {{"index", 5}};
  gltf.WriteGltf(dir + "/odd.gltf");
  absl::StatusOr<std::unique_ptr<SceneFile>> bad = SceneFile::Open(dir + "/odd.gltf");
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(bad.status().message(),
              HasSubstr("odd.gltf: material 0 'Odd' normalTexture: texture 5 does not exist"));
}

}  // namespace
}  // namespace tessera::render::testing

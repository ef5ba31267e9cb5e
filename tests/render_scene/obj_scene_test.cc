// Wavefront OBJ/MTL: shapes split by material, vertices shared per (v, vt, vn), MTL materials
// converted, textures relative to the .obj, and the errors and warnings of broken files.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "scene/scene.h"
#include "scene_files.h"
#include "test_util.h"

namespace tessera::render::testing {
namespace {

using ::testing::AllOf;
using ::testing::Contains;
using ::testing::ElementsAre;
using ::testing::FloatNear;
using ::testing::HasSubstr;
using ::testing::IsEmpty;
using ::testing::Pointwise;

constexpr char kObj[] = R"(mtllib scene.mtl
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
v 0 0 2
vt 0 0
vt 1 0
vt 1 1
vt 0 1
vn 0 0 1
o Quad
usemtl red
f 1/1/1 2/2/1 3/3/1 4/4/1
o Mixed
usemtl lamp
f 1 2 5
usemtl textured
f 1/1 3/3 4/4
)";

constexpr char kMtl[] = R"(newmtl red
Kd 1 0 0
Ks 0.2 0.5 0.1
Ns 98
d 0.5
newmtl lamp
Kd 0 0 0
Ke 5 4 3
newmtl textured
Kd 1 1 1
map_Kd maps/checker.png
newmtl unused
map_Kd nowhere.png
)";

TEST(RenderSceneObjTest, ShapesMaterialsAndTextures) {
  const std::string dir = MakeTempDir();
  WriteText(dir + "/scene.obj", kObj);
  WriteText(dir + "/scene.mtl", kMtl);
  std::filesystem::create_directory(dir + "/maps");
  // Top row: sRGB 188 then black; bottom row: white.
  WritePng(dir + "/maps/checker.png", 2, 2,
           {188, 188, 188, 255, 0, 0, 0, 255, 255, 255, 255, 255, 255, 255, 255, 255});

  std::unique_ptr<SceneFile> scene = OpenOrFail(dir + "/scene.obj");
  ASSERT_NE(scene, nullptr);
  EXPECT_THAT(scene->warnings(), IsEmpty());
  EXPECT_EQ(scene->time_begin(), 0.0);
  EXPECT_EQ(scene->time_end(), 0.0);
  const Assets& assets = scene->assets();

  // One mesh per (shape, material); the quad's four corners shared by its two triangles.
  ASSERT_EQ(assets.meshes.size(), 3u);
  const Mesh& quad = assets.meshes[0];
  EXPECT_EQ(quad.name, "Quad");
  EXPECT_EQ(quad.positions.size(), 4u * 3);
  EXPECT_EQ(quad.indices.size(), 6u);
  EXPECT_THAT(quad.normals, ElementsAre(0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1));
  // The file's vt equal each vertex's x and y; OBJ's v is flipped, since texture row 0 is the
  // image's top, where OBJ's v = 1 points.
  ASSERT_EQ(quad.texcoords.size(), 4u * 2);
  for (size_t v = 0; v < 4; ++v) {
    EXPECT_EQ(quad.texcoords[v * 2], quad.positions[v * 3]) << v;
    EXPECT_EQ(quad.texcoords[v * 2 + 1], 1.f - quad.positions[v * 3 + 1]) << v;
  }
  const Mesh& lamp = assets.meshes[1];
  EXPECT_EQ(lamp.name, "Mixed/lamp");
  EXPECT_THAT(lamp.positions, ElementsAre(0, 0, 0, 1, 0, 0, 0, 0, 2));
  EXPECT_THAT(lamp.indices, ElementsAre(0, 1, 2));
  EXPECT_TRUE(lamp.normals.empty());
  EXPECT_TRUE(lamp.texcoords.empty());
  const Mesh& textured = assets.meshes[2];
  EXPECT_EQ(textured.name, "Mixed/textured");
  EXPECT_EQ(textured.texcoords.size(), 6u);
  EXPECT_TRUE(textured.normals.empty());

  ASSERT_EQ(assets.materials.size(), 3u);  // "unused" is not converted, nor its texture read
  const Material& red = assets.materials[quad.material];
  EXPECT_EQ(red.name, "red");
  EXPECT_THAT(red.base_color, ElementsAre(1.f, 0.f, 0.f, 0.5f));
  EXPECT_FLOAT_EQ(red.metallic, 0.f);
  EXPECT_FLOAT_EQ(red.roughness, std::sqrt(2.f / 100.f));
  EXPECT_FLOAT_EQ(red.specular, 0.5f);  // Ks's largest channel
  EXPECT_TRUE(red.double_sided);
  EXPECT_EQ(red.base_color_texture, -1);
  const Material& emitter = assets.materials[lamp.material];
  EXPECT_EQ(emitter.name, "lamp");
  EXPECT_THAT(emitter.emissive, ElementsAre(5.f, 4.f, 3.f));
  EXPECT_FLOAT_EQ(emitter.specular, 0.f);  // no Ks: Lambertian
  const Material& checker = assets.materials[textured.material];
  ASSERT_EQ(checker.base_color_texture, 0);
  ASSERT_EQ(assets.textures.size(), 1u);
  const Texture& texture = assets.textures[0];
  EXPECT_EQ(texture.name, "maps/checker.png");
  EXPECT_EQ(texture.width, 2);
  EXPECT_EQ(texture.height, 2);
  EXPECT_THAT(std::vector<float>(texture.rgba.begin(), texture.rgba.begin() + 8),
              Pointwise(FloatNear(1e-5f),
                        {0.50288646f, 0.50288646f, 0.50288646f, 1.f, 0.f, 0.f, 0.f, 1.f}));

  const Frame frame = scene->FrameAt(1.0);
  ASSERT_EQ(frame.instances.size(), 3u);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(frame.instances[i].mesh, i);
    ExpectAffineNear(frame.instances[i].to_world, {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0});
  }
  EXPECT_TRUE(frame.cameras.empty());
  EXPECT_TRUE(frame.lights.empty());
  EXPECT_THAT(frame.bounds, ElementsAre(0.f, 0.f, 0.f, 1.f, 1.f, 2.f));
}

TEST(RenderSceneObjTest, MissingTextureAndMaterialLibraryAreWarnings) {
  const std::string dir = MakeTempDir();
  WriteText(dir + "/textureless.obj",
            "mtllib textureless.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\n"
            "usemtl ghost\nf 1 2 3\n");
  WriteText(dir + "/textureless.mtl", "newmtl ghost\nKd 0.2 0.4 0.6\nmap_Kd gone.png\n");
  std::unique_ptr<SceneFile> scene = OpenOrFail(dir + "/textureless.obj");
  ASSERT_NE(scene, nullptr);
  EXPECT_EQ(scene->assets().materials.at(0).base_color_texture, -1);
  EXPECT_THAT(scene->assets().materials.at(0).base_color, ElementsAre(0.2f, 0.4f, 0.6f, 1.f));
  ASSERT_EQ(scene->warnings().size(), 1u);
  EXPECT_THAT(scene->warnings()[0],
              AllOf(HasSubstr("textureless.obj: material 'ghost' map_Kd"), HasSubstr("gone.png"),
                    HasSubstr("uses its factor alone")));

  WriteText(dir + "/nolib.obj", "mtllib absent.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  scene = OpenOrFail(dir + "/nolib.obj");
  ASSERT_NE(scene, nullptr);
  EXPECT_EQ(scene->assets().meshes.at(0).material, -1);
  EXPECT_THAT(scene->warnings(),
              Contains(AllOf(HasSubstr("nolib.obj: "), HasSubstr("absent.mtl"))));
}

TEST(RenderSceneObjTest, IndexPastTheVerticesIsAnError) {
  const std::string dir = MakeTempDir();
  WriteText(dir + "/bad.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\no Shard\nf 1 2 9\n");
  const absl::Status status = SceneFile::Open(dir + "/bad.obj").status();
  EXPECT_EQ(status.code(), absl::StatusCode::kInvalidArgument) << status;
  EXPECT_THAT(status.message(),
              HasSubstr("bad.obj: shape 0 'Shard' triangle 1: vertex 9 past its 3 vertices"));
}

TEST(RenderSceneObjTest, LinesOnlyIsUnimplemented) {
  const std::string dir = MakeTempDir();
  WriteText(dir + "/lines.obj", "v 0 0 0\nv 1 0 0\nl 1 2\n");
  const absl::Status status = SceneFile::Open(dir + "/lines.obj").status();
  EXPECT_EQ(status.code(), absl::StatusCode::kUnimplemented) << status;
  EXPECT_THAT(status.message(), HasSubstr("lines.obj: holds no triangles"));
}

}  // namespace
}  // namespace tessera::render::testing

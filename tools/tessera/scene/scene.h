// The scene `tessera render` renders, as its loaders leave it (glTF 2.0 through tinygltf, Wavefront
// OBJ/MTL through tinyobjloader): what does not change over an animation (meshes, materials,
// textures) in Assets, and what does (node transforms of instances, cameras and lights) sampled
// per frame time by SceneFile::FrameAt. Units are the file's; glTF's conventions throughout
// (right-handed, +Y up, cameras looking down -Z, linear colours, metallic-roughness PBR).
#ifndef TESSERA_TOOLS_TESSERA_SCENE_SCENE_H_
#define TESSERA_TOOLS_TESSERA_SCENE_SCENE_H_

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "absl/status/statusor.h"

namespace tessera::render {

// An image a material reads: RGBA floats, row 0 at the top (as files store them), bilinear
// filtered and wrapped (repeat) by the renderer. Colour textures (base colour, emissive) are
// converted from sRGB to linear when loaded; data textures (metallic-roughness, normal maps) are
// kept as stored, scaled to [0, 1].
struct Texture {
  std::string name;  // the file or glTF image name, for messages
  int width = 0, height = 0;
  std::vector<float> rgba;  // width * height * 4
};

// glTF 2.0 metallic-roughness (OBJ/MTL materials are converted: Kd -> base colour, Ke ->
// emissive, Ns -> roughness = sqrt(2 / (Ns + 2)), metallic 0, map_Kd -> base colour texture,
// d/Tr -> base_color[3]). Texture indices are into Assets::textures, -1 for none.
struct Material {
  std::string name;
  float base_color[4] = {1.f, 1.f, 1.f, 1.f};  // linear RGBA factor
  int base_color_texture = -1;
  float metallic = 1.f, roughness = 1.f;
  int metallic_roughness_texture = -1;  // B: metallic, G: roughness (glTF)
  float emissive[3] = {0.f, 0.f, 0.f};  // linear RGB, KHR_materials_emissive_strength applied
  int emissive_texture = -1;
  int normal_texture = -1;  // tangent-space normal map
  float normal_scale = 1.f;
  float ior = 1.5f;          // KHR_materials_ior
  float transmission = 0.f;  // KHR_materials_transmission factor
  // The dielectric specular layer's weight: KHR_materials_specular's specularFactor; for OBJ the
  // largest channel of Ks (0: Lambertian, as an MTL material with Kd alone means).
  float specular = 1.f;
  bool double_sided = false;  // glTF doubleSided (OBJ: true)
};

// One triangle mesh (a glTF primitive of mode TRIANGLES, an OBJ shape's faces of one material) in
// its own object space. Optional attributes are empty when the file has none.
struct Mesh {
  std::string name;
  std::vector<float> positions;   // xyz per vertex
  std::vector<float> normals;     // xyz per vertex, or empty
  std::vector<float> texcoords;   // uv per vertex (TEXCOORD_0), or empty
  std::vector<float> tangents;    // xyzw per vertex, or empty
  std::vector<uint32_t> indices;  // three per triangle
  int material = -1;              // into Assets::materials; -1: the default material
};

struct Assets {
  std::vector<Mesh> meshes;
  std::vector<Material> materials;
  std::vector<Texture> textures;
};

// 3x4 row-major affine matrix, object to world: x' = m[0]x + m[1]y + m[2]z + m[3], ...
using Affine = std::array<float, 12>;

struct Instance {
  int mesh = 0;  // into Assets::meshes
  Affine to_world{};
};

struct Camera {
  std::string name;   // glTF camera or node name ("" if neither has one)
  Affine to_world{};  // the camera looks down its -Z, +Y up
  bool orthographic = false;
  float yfov = 0.7f;             // perspective: vertical field of view, radians
  float aspect = 0.f;            // width / height from the file; 0: the image's
  float xmag = 1.f, ymag = 1.f;  // orthographic half extents
  float znear = 0.f;
};

// KHR_lights_punctual; intensity in the extension's units (candela for point and spot, lux for
// directional).
struct Light {
  enum class Type { kPoint, kSpot, kDirectional };
  std::string name;
  Type type = Type::kPoint;
  float color[3] = {1.f, 1.f, 1.f};
  float intensity = 1.f;
  float range = 0.f;  // 0: infinite
  float inner_cone = 0.f, outer_cone = 0.7853982f;
  Affine to_world{};  // spot and directional lights point down their -Z
};

// What changes with time: every mesh instance, camera and light with its node's world transform
// at that time.
struct Frame {
  double time = 0.0;  // seconds
  std::vector<Instance> instances;
  std::vector<Camera> cameras;
  std::vector<Light> lights;
  float bounds[6] = {0.f, 0.f, 0.f, 0.f, 0.f, 0.f};  // world box of the instances: min xyz, max
};

class SceneFile {
 public:
  // Loads `path` (.gltf, .glb, .obj; by extension, case-insensitive). Errors name the file and
  // what is wrong with it (INVALID_ARGUMENT for a bad file, NOT_FOUND for a missing one,
  // UNIMPLEMENTED for what the loaders do not support, e.g. a glTF without triangles).
  static absl::StatusOr<std::unique_ptr<SceneFile>> Open(const std::string& path);
  virtual ~SceneFile() = default;

  const Assets& assets() const { return assets_; }
  // The animation's time range in seconds (glTF animations' input accessors; 0, 0 when static).
  double time_begin() const { return time_begin_; }
  double time_end() const { return time_end_; }
  // Every instance, camera and light at `time`, animations sampled as glTF says (LINEAR, STEP,
  // CUBICSPLINE; rotations by slerp), clamped to the animation's range.
  virtual Frame FrameAt(double time) const = 0;
  // What the loaders skipped or could not read without failing (morph targets, skins, points and
  // lines, a texture file that is missing, ...), one line per kind of problem, each naming the
  // file; empty when everything in the file was loaded. For the user, not for the renderer.
  const std::vector<std::string>& warnings() const { return warnings_; }

 protected:
  Assets assets_;
  double time_begin_ = 0.0, time_end_ = 0.0;
  std::vector<std::string> warnings_;
};

}  // namespace tessera::render

#endif  // TESSERA_TOOLS_TESSERA_SCENE_SCENE_H_

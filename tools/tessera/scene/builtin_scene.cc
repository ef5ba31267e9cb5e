#include "tools/tessera/scene/builtin_scene.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "absl/status/status.h"
#include "absl/strings/str_join.h"

namespace tessera::render {
namespace {

constexpr float kPi = 3.14159265358979f;

struct V3 {
  float x, y, z;
};
V3 operator+(V3 a, V3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
V3 operator-(V3 a, V3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
V3 operator*(float s, V3 a) { return {s * a.x, s * a.y, s * a.z}; }
V3 Cross(V3 a, V3 b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
V3 Normalize(V3 a) {
  const float inv = 1.f / std::sqrt(a.x * a.x + a.y * a.y + a.z * a.z);
  return inv * a;
}

// ---- Meshes -------------------------------------------------------------------------------------

// Appends the quad `corner`, `corner + u`, `corner + u + v`, `corner + v` to `mesh`: two triangles
// winding counter-clockwise seen from the side u x v points to, texture coordinates (0, 0) to
// (uv_scale, uv_scale).
void AddQuad(Mesh& mesh, V3 corner, V3 u, V3 v, float uv_scale = 1.f) {
  const auto base = static_cast<uint32_t>(mesh.positions.size() / 3);
  const V3 n = Normalize(Cross(u, v));
  const V3 corners[4] = {corner, corner + u, corner + u + v, corner + v};
  const float uvs[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  for (int i = 0; i < 4; ++i) {
    mesh.positions.insert(mesh.positions.end(), {corners[i].x, corners[i].y, corners[i].z});
    mesh.normals.insert(mesh.normals.end(), {n.x, n.y, n.z});
    mesh.texcoords.insert(mesh.texcoords.end(), {uv_scale * uvs[i][0], uv_scale * uvs[i][1]});
  }
  mesh.indices.insert(mesh.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
}

Mesh Quad(std::string name, int material, V3 corner, V3 u, V3 v, float uv_scale = 1.f) {
  Mesh mesh;
  mesh.name = std::move(name);
  mesh.material = material;
  AddQuad(mesh, corner, u, v, uv_scale);
  return mesh;
}

// The cube [-0.5, 0.5]^3, faces outward, a flat normal per face.
Mesh Cube(std::string name, int material) {
  Mesh mesh;
  mesh.name = std::move(name);
  mesh.material = material;
  const V3 x{1, 0, 0}, y{0, 1, 0}, z{0, 0, 1};
  const V3 o{-0.5f, -0.5f, -0.5f};
  AddQuad(mesh, o, y, x);      // -Z
  AddQuad(mesh, o + z, x, y);  // +Z
  AddQuad(mesh, o, z, y);      // -X
  AddQuad(mesh, o + x, y, z);  // +X
  AddQuad(mesh, o, x, z);      // -Y
  AddQuad(mesh, o + y, z, x);  // +Y
  return mesh;
}

// A UV sphere of radius 1 around the origin with smooth normals.
Mesh Sphere(std::string name, int material, int slices, int stacks) {
  Mesh mesh;
  mesh.name = std::move(name);
  mesh.material = material;
  for (int j = 0; j <= stacks; ++j) {
    const float theta = kPi * static_cast<float>(j) / static_cast<float>(stacks);
    for (int i = 0; i <= slices; ++i) {
      const float phi = 2.f * kPi * static_cast<float>(i) / static_cast<float>(slices);
      const V3 p{std::sin(theta) * std::cos(phi), std::cos(theta),
                 -std::sin(theta) * std::sin(phi)};
      mesh.positions.insert(mesh.positions.end(), {p.x, p.y, p.z});
      mesh.normals.insert(mesh.normals.end(), {p.x, p.y, p.z});
      mesh.texcoords.insert(mesh.texcoords.end(),
                            {static_cast<float>(i) / static_cast<float>(slices),
                             static_cast<float>(j) / static_cast<float>(stacks)});
    }
  }
  const auto row = static_cast<uint32_t>(slices + 1);
  for (uint32_t j = 0; j < static_cast<uint32_t>(stacks); ++j) {
    for (uint32_t i = 0; i < static_cast<uint32_t>(slices); ++i) {
      const uint32_t a = j * row + i, b = a + row;  // b is one stack further down
      // Counter-clockwise seen from outside; the triangles at the poles are degenerate ones left
      // out.
      if (j != 0) mesh.indices.insert(mesh.indices.end(), {a, b, a + 1});
      if (j + 1 != static_cast<uint32_t>(stacks)) {
        mesh.indices.insert(mesh.indices.end(), {a + 1, b, b + 1});
      }
    }
  }
  return mesh;
}

// A grey checkerboard, 8 x 8 squares of 8 x 8 texels, linear values.
Texture Checker() {
  Texture t;
  t.name = "builtin:checker";
  t.width = t.height = 64;
  t.rgba.resize(64 * 64 * 4);
  for (int y = 0; y < 64; ++y) {
    for (int x = 0; x < 64; ++x) {
      const float v = ((x / 8 + y / 8) % 2 == 0) ? 0.80f : 0.45f;
      float* p = &t.rgba[4 * (y * 64 + x)];
      p[0] = p[1] = p[2] = v;
      p[3] = 1.f;
    }
  }
  return t;
}

Material Diffuse(std::string name, float r, float g, float b) {
  Material m;
  m.name = std::move(name);
  m.base_color[0] = r;
  m.base_color[1] = g;
  m.base_color[2] = b;
  m.metallic = 0.f;
  m.roughness = 1.f;
  return m;
}

// ---- Transforms ---------------------------------------------------------------------------------

Affine Identity() { return {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0}; }

// Scale by `s`, then turn by `angle` radians about +Y, then move by `t`.
Affine ScaleRotateYTranslate(V3 s, float angle, V3 t) {
  const float c = std::cos(angle), n = std::sin(angle);
  return {c * s.x, 0, n * s.z, t.x, 0, s.y, 0, t.y, -n * s.x, 0, c * s.z, t.z};
}

// A camera at `eye` looking at `target`: its -Z towards the target, +Y as near `up` as it goes.
Affine LookAt(V3 eye, V3 target, V3 up) {
  const V3 z = Normalize(eye - target);
  const V3 x = Normalize(Cross(up, z));
  const V3 y = Cross(z, x);
  return {x.x, y.x, z.x, eye.x, x.y, y.y, z.y, eye.y, x.z, y.z, z.z, eye.z};
}

// ---- The Cornell box ----------------------------------------------------------------------------

enum MeshIndex {
  kFloor,
  kCeiling,
  kBackWall,
  kLeftWall,
  kRightWall,
  kLight,
  kTallBox,
  kShortBox,
  kBall,
  kMeshCount
};

class CornellScene : public SceneFile {
 public:
  CornellScene() {
    std::vector<Material>& mats = assets_.materials;
    Material floor = Diffuse("floor", 1.f, 1.f, 1.f);  // the texture carries the colour
    floor.base_color_texture = 0;
    mats.push_back(floor);                                  // 0
    mats.push_back(Diffuse("white", 0.73f, 0.73f, 0.73f));  // 1
    mats.push_back(Diffuse("red", 0.65f, 0.05f, 0.05f));    // 2
    mats.push_back(Diffuse("green", 0.12f, 0.45f, 0.15f));  // 3
    Material light = Diffuse("light", 0.78f, 0.78f, 0.78f);
    light.emissive[0] = 6.8f;
    light.emissive[1] = 4.8f;
    light.emissive[2] = 1.6f;
    mats.push_back(light);  // 4
    Material copper;
    copper.name = "copper";
    copper.base_color[0] = 0.95f;
    copper.base_color[1] = 0.64f;
    copper.base_color[2] = 0.54f;
    copper.metallic = 1.f;
    copper.roughness = 0.35f;
    mats.push_back(copper);  // 5
    Material glass;
    glass.name = "glass";
    glass.metallic = 0.f;
    glass.roughness = 0.f;
    glass.transmission = 1.f;
    glass.ior = 1.5f;
    mats.push_back(glass);  // 6
    assets_.textures.push_back(Checker());

    // The room spans x in [-1, 1], y in [0, 2], z in [-1, 1]; every wall faces inside.
    std::vector<Mesh>& meshes = assets_.meshes;
    meshes.resize(kMeshCount);
    meshes[kFloor] = Quad("floor", 0, {-1, 0, 1}, {2, 0, 0}, {0, 0, -2}, 4.f);
    meshes[kCeiling] = Quad("ceiling", 1, {-1, 2, -1}, {2, 0, 0}, {0, 0, 2});
    meshes[kBackWall] = Quad("back wall", 1, {-1, 0, -1}, {2, 0, 0}, {0, 2, 0});
    meshes[kLeftWall] = Quad("left wall", 2, {-1, 0, 1}, {0, 0, -2}, {0, 2, 0});
    meshes[kRightWall] = Quad("right wall", 3, {1, 0, -1}, {0, 0, 2}, {0, 2, 0});
    // Just under the ceiling, facing down.
    meshes[kLight] = Quad("light", 4, {-0.4f, 1.98f, -0.32f}, {0.8f, 0, 0}, {0, 0, 0.64f});
    meshes[kTallBox] = Cube("tall box", 5);
    meshes[kShortBox] = Cube("short box", 1);
    meshes[kBall] = Sphere("glass ball", 6, 32, 16);
    time_begin_ = 0.0;
    time_end_ = 2.0;
  }

  Frame FrameAt(double time) const override {
    const float t = static_cast<float>(std::clamp(time, time_begin_, time_end_));
    Frame frame;
    frame.time = time;
    for (int m : {kFloor, kCeiling, kBackWall, kLeftWall, kRightWall, kLight}) {
      frame.instances.push_back({m, Identity()});
    }
    frame.instances.push_back(
        {kTallBox, ScaleRotateYTranslate({0.6f, 1.2f, 0.6f}, 0.3f, {-0.35f, 0.6f, -0.3f})});
    // The short box turns a quarter turn and slides towards the back over the animation.
    const float angle = -0.3f + 0.25f * kPi * t;
    const V3 box{0.35f, 0.3f, 0.3f - 0.15f * t};
    frame.instances.push_back({kShortBox, ScaleRotateYTranslate({0.6f, 0.6f, 0.6f}, angle, box)});
    frame.instances.push_back(
        {kBall, ScaleRotateYTranslate({0.22f, 0.22f, 0.22f}, 0.f, box + V3{0, 0.52f, 0})});

    const V3 eye{0, 1, 3.4f}, target{0, 1, 0}, up{0, 1, 0};
    Camera main;
    main.name = "main";
    main.to_world = LookAt(eye, target, up);
    main.yfov = 0.6858f;  // 39.3 degrees, the classic Cornell box camera
    frame.cameras.push_back(main);
    Camera ortho = main;
    ortho.name = "ortho";
    ortho.orthographic = true;
    ortho.xmag = ortho.ymag = 1.05f;
    frame.cameras.push_back(ortho);

    Light fill;
    fill.name = "fill";
    fill.type = Light::Type::kPoint;
    fill.color[0] = 1.f;
    fill.color[1] = 0.9f;
    fill.color[2] = 0.8f;
    fill.intensity = 0.5f;
    fill.to_world = {1, 0, 0, 0.2f, 0, 1, 0, 1.6f, 0, 0, 1, 0.6f};
    frame.lights.push_back(fill);

    const float bounds[6] = {-1, 0, -1, 1, 2, 1};
    std::copy(bounds, bounds + 6, frame.bounds);
    return frame;
  }
};

}  // namespace

std::vector<std::string> BuiltinSceneNames() { return {"cornell"}; }

absl::StatusOr<std::unique_ptr<SceneFile>> OpenBuiltinScene(const std::string& name) {
  if (name == "cornell") return std::make_unique<CornellScene>();
  return absl::NotFoundError("no built-in scene '" + std::string(kBuiltinPrefix) + name +
                             "' (there are: " +
                             absl::StrJoin(BuiltinSceneNames(), ", ",
                                           [](std::string* out, const std::string& n) {
                                             out->append(kBuiltinPrefix).append(n);
                                           }) +
                             ")");
}

}  // namespace tessera::render

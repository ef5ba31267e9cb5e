#include "obj_loader.h"

#include <tiny_obj_loader.h>

#include <algorithm>
#include <cmath>
#include <exception>
#include <filesystem>
#include <map>
#include <tuple>
#include <utility>
#include <vector>

#include "absl/container/flat_hash_map.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_split.h"
#include "loaded_scene.h"
#include "textures.h"
#include "warnings.h"

namespace tessera::render {
namespace {

float Clamp01(float v) { return v > 0.f ? std::min(v, 1.f) : 0.f; }

// One Mesh being built from the faces of one (shape, material) pair. OBJ indexes positions,
// normals and texture coordinates separately; a Mesh vertex is one distinct triple of them.
struct MeshBuilder {
  Mesh mesh;
  absl::flat_hash_map<std::tuple<int, int, int>, uint32_t> vertex_of;
  bool every_vertex_has_normal = true;
  bool some_vertex_has_texcoord = false;

  uint32_t Vertex(const tinyobj::attrib_t& attrib, const tinyobj::index_t& index) {
    const auto [it, added] =
        vertex_of.try_emplace({index.vertex_index, index.normal_index, index.texcoord_index},
                              static_cast<uint32_t>(mesh.positions.size() / 3));
    if (!added) return it->second;
    const size_t v = static_cast<size_t>(index.vertex_index) * 3;
    mesh.positions.insert(mesh.positions.end(), &attrib.vertices[v], &attrib.vertices[v] + 3);
    if (index.normal_index >= 0) {
      const size_t n = static_cast<size_t>(index.normal_index) * 3;
      mesh.normals.insert(mesh.normals.end(), &attrib.normals[n], &attrib.normals[n] + 3);
    } else {
      every_vertex_has_normal = false;
      mesh.normals.insert(mesh.normals.end(), {0.f, 0.f, 0.f});
    }
    if (index.texcoord_index >= 0) {
      some_vertex_has_texcoord = true;
      const size_t t = static_cast<size_t>(index.texcoord_index) * 2;
      // OBJ's v runs up from the image's bottom row; Texture rows (and glTF's v) run down from
      // the top, so the same texel is found at 1 - v.
      mesh.texcoords.insert(mesh.texcoords.end(),
                            {attrib.texcoords[t], 1.f - attrib.texcoords[t + 1]});
    } else {
      mesh.texcoords.insert(mesh.texcoords.end(), {0.f, 0.f});
    }
    return it->second;
  }

  Mesh Finish() && {
    // A normal for only some vertices would shade the others with a zero normal: the renderer's
    // geometric normal serves better. Missing texture coordinates stay (0, 0).
    if (!every_vertex_has_normal) mesh.normals.clear();
    if (!some_vertex_has_texcoord) mesh.texcoords.clear();
    return std::move(mesh);
  }
};

class ObjSceneBuilder {
 public:
  ObjSceneBuilder(const std::string& path, const tinyobj::ObjReader& reader)
      : path_(path),
        directory_(std::filesystem::path(path).parent_path()),
        attrib_(reader.GetAttrib()),
        shapes_(reader.GetShapes()),
        materials_(reader.GetMaterials()),
        warnings_(path) {
    for (absl::string_view line : absl::StrSplit(reader.Warning(), '\n', absl::SkipWhitespace())) {
      warnings_.Add(absl::StrCat("parser:", line), std::string(line));
    }
  }

  absl::StatusOr<std::unique_ptr<SceneFile>> Build() && {
    SceneNode root;  // identity: OBJ coordinates are world coordinates
    for (size_t s = 0; s < shapes_.size(); ++s) {
      absl::Status status = AddShape(s, root);
      if (!status.ok()) return status;
    }
    if (assets_.meshes.empty()) {
      return absl::UnimplementedError(
          absl::StrCat(path_, ": holds no triangles (tessera render renders faces only)"));
    }
    SceneGraphData graph;
    graph.nodes.push_back(std::move(root));
    return std::make_unique<LoadedScene>(std::move(assets_), std::move(graph), warnings_.Lines());
  }

 private:
  absl::Status AddShape(size_t s, SceneNode& root) {
    const tinyobj::shape_t& shape = shapes_[s];
    const std::string object = absl::StrCat("shape ", s, " '", shape.name, "'");
    if (!shape.lines.indices.empty() || !shape.points.indices.empty()) {
      warnings_.Add("lines", absl::StrCat(object, ": lines and points are not rendered; left out"));
    }
    const tinyobj::mesh_t& faces = shape.mesh;
    if (faces.material_ids.size() != faces.num_face_vertices.size()) {
      return absl::InvalidArgumentError(absl::StrCat(path_, ": ", object, ": ",
                                                     faces.num_face_vertices.size(), " faces but ",
                                                     faces.material_ids.size(), " material ids"));
    }
    std::vector<std::pair<int, MeshBuilder>> builders;  // by material, in order of first use
    size_t corner = 0;
    for (size_t f = 0; f < faces.num_face_vertices.size(); ++f) {
      const size_t corners = faces.num_face_vertices[f];
      if (corner + corners > faces.indices.size()) {
        return absl::InvalidArgumentError(
            absl::StrCat(path_, ": ", object, " triangle ", f + 1, ": runs past its indices"));
      }
      // Triangulation leaves triangles only; anything else is a degenerate face tinyobjloader
      // kept as it was.
      if (corners != 3) {
        corner += corners;
        continue;
      }
      int material = faces.material_ids[f];
      if (material < -1 || material >= static_cast<int>(materials_.size())) {
        return absl::InvalidArgumentError(absl::StrCat(path_, ": ", object, " triangle ", f + 1,
                                                       ": material ", material, " does not exist"));
      }
      auto builder = std::find_if(builders.begin(), builders.end(),
                                  [&](const auto& b) { return b.first == material; });
      if (builder == builders.end()) {
        builders.emplace_back(material, MeshBuilder{});
        builder = builders.end() - 1;
      }
      for (size_t k = 0; k < 3; ++k, ++corner) {
        const tinyobj::index_t& index = faces.indices[corner];
        absl::Status valid = CheckIndex(index, object, f);
        if (!valid.ok()) return valid;
        builder->second.mesh.indices.push_back(builder->second.Vertex(attrib_, index));
      }
    }
    for (auto& [material, builder] : builders) {
      Mesh mesh = std::move(builder).Finish();
      mesh.name = builders.size() == 1 ? shape.name
                  : material < 0       ? absl::StrCat(shape.name, "/default")
                                       : absl::StrCat(shape.name, "/", materials_[material].name);
      absl::StatusOr<int> converted = MaterialIndex(material);
      if (!converted.ok()) return converted.status();
      mesh.material = *converted;
      root.meshes.push_back(static_cast<int>(assets_.meshes.size()));
      assets_.meshes.push_back(std::move(mesh));
    }
    return absl::OkStatus();
  }

  absl::Status CheckIndex(const tinyobj::index_t& index, const std::string& object,
                          size_t face) const {
    // Messages count from 1, as OBJ indices do (triangles too, for consistency).
    const auto check = [&](int i, size_t available, const char* one, const char* many) {
      if (i < -1 || (i >= 0 && static_cast<size_t>(i) >= available)) {
        return absl::InvalidArgumentError(absl::StrCat(path_, ": ", object, " triangle ", face + 1,
                                                       ": ", one, " ", int64_t{i} + 1, " past its ",
                                                       available, " ", many));
      }
      return absl::OkStatus();
    };
    if (index.vertex_index < 0) {
      return absl::InvalidArgumentError(
          absl::StrCat(path_, ": ", object, " triangle ", face + 1, ": a corner without a vertex"));
    }
    absl::Status status =
        check(index.vertex_index, attrib_.vertices.size() / 3, "vertex", "vertices");
    if (status.ok()) {
      status = check(index.normal_index, attrib_.normals.size() / 3, "normal", "normals");
    }
    if (status.ok()) {
      status = check(index.texcoord_index, attrib_.texcoords.size() / 2, "texture coordinate",
                     "texture coordinates");
    }
    if (!status.ok()) return status;
    const float* p = &attrib_.vertices[static_cast<size_t>(index.vertex_index) * 3];
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) {
      // The renderer's bounds and acceleration structure assume finite coordinates.
      return absl::InvalidArgumentError(absl::StrCat(path_, ": ", object, " triangle ", face + 1,
                                                     ": vertex ", index.vertex_index,
                                                     " is not finite"));
    }
    return absl::OkStatus();
  }

  // Assets::materials index of MTL material `m` (-1 stays the default material).
  absl::StatusOr<int> MaterialIndex(int m) {
    if (m < 0) return -1;
    if (const auto it = material_of_.find(m); it != material_of_.end()) return it->second;
    const tinyobj::material_t& in = materials_[m];
    const std::string object = absl::StrCat("material '", in.name, "'");
    Material out;
    out.name = in.name;
    for (int c = 0; c < 3; ++c) {
      out.base_color[c] = Clamp01(in.diffuse[c]);
      // Ke may exceed 1: emitters are as bright as the file says.
      out.emissive[c] =
          in.emission[c] > 0.f && std::isfinite(in.emission[c]) ? in.emission[c] : 0.f;
    }
    out.base_color[3] = Clamp01(in.dissolve);  // tinyobjloader turns Tr into d = 1 - Tr
    out.metallic = 0.f;
    out.specular = Clamp01(std::max({in.specular[0], in.specular[1], in.specular[2]}));
    // The Blinn-Phong exponent's usual mapping to a microfacet roughness (alpha = sqrt(2 / (n +
    // 2)), as in Walter et al. 2007), taken as glTF's perceptual roughness.
    const float ns = std::isfinite(in.shininess) ? std::max(in.shininess, 0.f) : 0.f;
    out.roughness = Clamp01(std::sqrt(2.f / (ns + 2.f)));
    out.double_sided = true;  // OBJ has no notion of back faces
    absl::StatusOr<int> texture =
        TextureIndex(in.diffuse_texname, ColorSpace::kSrgb, object + " map_Kd");
    if (!texture.ok()) return texture.status();
    out.base_color_texture = *texture;
    texture = TextureIndex(in.emissive_texname, ColorSpace::kSrgb, object + " map_Ke");
    if (!texture.ok()) return texture.status();
    out.emissive_texture = *texture;

    assets_.materials.push_back(std::move(out));
    const int index = static_cast<int>(assets_.materials.size()) - 1;
    material_of_[m] = index;
    return index;
  }

  // The Assets::textures index of texture file `name` (relative to the .obj), or -1 for none and,
  // with a warning, for a file that cannot be read or decoded.
  absl::StatusOr<int> TextureIndex(std::string name, ColorSpace color_space,
                                   const std::string& object) {
    if (name.empty()) return -1;
    std::replace(name.begin(), name.end(), '\\', '/');  // MTL files written on Windows
    std::filesystem::path file(name);
    if (file.is_relative()) file = directory_ / file;
    const auto key = std::make_pair(file.string(), color_space);
    if (const auto it = texture_of_.find(key); it != texture_of_.end()) return it->second;
    absl::StatusOr<Texture> decoded = ReadImageFile(file.string(), color_space);
    int index = -1;
    if (decoded.ok()) {
      decoded->name = name;
      assets_.textures.push_back(*std::move(decoded));
      index = static_cast<int>(assets_.textures.size()) - 1;
    } else {
      // As for glTF: the geometry and the factors remain useful without the image.
      warnings_.Add(absl::StrCat("image:", file.string()),
                    absl::StrCat(object, ": ", decoded.status().message(),
                                 "; the material uses its factor alone"));
    }
    texture_of_[key] = index;
    return index;
  }

  const std::string& path_;
  const std::filesystem::path directory_;
  const tinyobj::attrib_t& attrib_;
  const std::vector<tinyobj::shape_t>& shapes_;
  const std::vector<tinyobj::material_t>& materials_;
  Assets assets_;
  WarningList warnings_;
  std::map<int, int> material_of_;  // MTL material -> Assets::materials
  std::map<std::pair<std::string, ColorSpace>, int> texture_of_;  // -> Assets::textures or -1
};

}  // namespace

absl::StatusOr<std::unique_ptr<SceneFile>> LoadObj(const std::string& path) {
  tinyobj::ObjReaderConfig config;
  config.triangulate = true;
  config.vertex_color = false;
  tinyobj::ObjReader reader;
  bool parsed = false;
  try {
    parsed = reader.ParseFromFile(path, config);
  } catch (const std::exception& e) {  // std::bad_alloc, or a number parser's exception
    return absl::InvalidArgumentError(absl::StrCat(path, ": not a valid OBJ file: ", e.what()));
  }
  if (!parsed) {
    return absl::InvalidArgumentError(
        absl::StrCat(path, ": not a valid OBJ file: ", reader.Error()));
  }
  return ObjSceneBuilder(path, reader).Build();
}

}  // namespace tessera::render

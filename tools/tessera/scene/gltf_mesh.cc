#include "gltf_mesh.h"

#include <cmath>
#include <string>
#include <utility>

#include "absl/strings/str_cat.h"
#include "gltf_accessor.h"

namespace tessera::render {
namespace {

// Triangle lists from a primitive's (possibly implicit) index sequence. Strips and fans follow
// the glTF 2.0 specification's vertex order (3.7.2.1), which keeps every triangle's winding.
absl::StatusOr<std::vector<uint32_t>> TriangleList(std::vector<uint32_t> order, int mode,
                                                   const std::string& what) {
  std::vector<uint32_t> triangles;
  switch (mode) {
    case TINYGLTF_MODE_TRIANGLES:
      if (order.size() % 3 != 0) {
        return absl::InvalidArgumentError(
            absl::StrCat(what, ": ", order.size(), " indices, not a multiple of 3"));
      }
      return order;
    case TINYGLTF_MODE_TRIANGLE_STRIP:
      for (size_t i = 0; i + 2 < order.size(); ++i) {
        triangles.insert(triangles.end(), {order[i], order[i + 1 + i % 2], order[i + 2 - i % 2]});
      }
      return triangles;
    default:  // TINYGLTF_MODE_TRIANGLE_FAN
      for (size_t i = 0; i + 2 < order.size(); ++i) {
        triangles.insert(triangles.end(), {order[i + 1], order[i + 2], order[0]});
      }
      return triangles;
  }
}

std::string ModeName(int mode) {
  switch (mode) {
    case TINYGLTF_MODE_POINTS:
      return "POINTS";
    case TINYGLTF_MODE_LINE:
      return "LINES";
    case TINYGLTF_MODE_LINE_LOOP:
      return "LINE_LOOP";
    case TINYGLTF_MODE_LINE_STRIP:
      return "LINE_STRIP";
    default:
      return absl::StrCat("mode ", mode);
  }
}

// Reads attribute `name` of a primitive into `out` when it has one, checking its type and that
// it has one element per vertex.
absl::Status ReadAttribute(const tinygltf::Model& model, const tinygltf::Primitive& primitive,
                           const std::string& name, int type, size_t vertices,
                           const std::string& what, std::vector<float>& out) {
  const auto it = primitive.attributes.find(name);
  if (it == primitive.attributes.end()) return absl::OkStatus();
  absl::StatusOr<FloatAccessor> values =
      ReadFloatAccessor(model, it->second, {type}, absl::StrCat(what, " ", name));
  if (!values.ok()) return values.status();
  if (values->count != vertices) {
    return absl::InvalidArgumentError(absl::StrCat(what, " ", name, ": ", values->count,
                                                   " elements for ", vertices, " vertices"));
  }
  out = std::move(values->values);
  return absl::OkStatus();
}

absl::Status ConvertPrimitive(const tinygltf::Model& model, const tinygltf::Primitive& primitive,
                              const std::string& what, Mesh& out) {
  const auto position = primitive.attributes.find("POSITION");
  if (position == primitive.attributes.end()) {
    return absl::InvalidArgumentError(absl::StrCat(what, ": no POSITION attribute"));
  }
  absl::StatusOr<FloatAccessor> positions =
      ReadFloatAccessor(model, position->second, {TINYGLTF_TYPE_VEC3}, what + " POSITION");
  if (!positions.ok()) return positions.status();
  for (size_t i = 0; i < positions->values.size(); ++i) {
    // The renderer's bounds and acceleration structure assume finite coordinates.
    if (!std::isfinite(positions->values[i])) {
      return absl::InvalidArgumentError(
          absl::StrCat(what, " POSITION: vertex ", i / 3, " is not finite"));
    }
  }
  const size_t vertices = positions->count;
  out.positions = std::move(positions->values);

  absl::Status status =
      ReadAttribute(model, primitive, "NORMAL", TINYGLTF_TYPE_VEC3, vertices, what, out.normals);
  if (status.ok()) {
    status = ReadAttribute(model, primitive, "TEXCOORD_0", TINYGLTF_TYPE_VEC2, vertices, what,
                           out.texcoords);
  }
  if (status.ok()) {
    status = ReadAttribute(model, primitive, "TANGENT", TINYGLTF_TYPE_VEC4, vertices, what,
                           out.tangents);
  }
  if (!status.ok()) return status;

  std::vector<uint32_t> order;
  if (primitive.indices >= 0) {
    absl::StatusOr<std::vector<uint32_t>> indices =
        ReadIndexAccessor(model, primitive.indices, what);
    if (!indices.ok()) return indices.status();
    for (uint32_t index : *indices) {
      if (index >= vertices) {
        return absl::InvalidArgumentError(
            absl::StrCat(what, ": index ", index, " past its ", vertices, " vertices"));
      }
    }
    order = *std::move(indices);
  } else {
    if (vertices > UINT32_MAX) {
      return absl::InvalidArgumentError(absl::StrCat(what, ": ", vertices, " vertices"));
    }
    order.resize(vertices);
    for (size_t i = 0; i < vertices; ++i) order[i] = static_cast<uint32_t>(i);
  }
  const int mode = primitive.mode < 0 ? TINYGLTF_MODE_TRIANGLES : primitive.mode;
  absl::StatusOr<std::vector<uint32_t>> triangles = TriangleList(std::move(order), mode, what);
  if (!triangles.ok()) return triangles.status();
  out.indices = *std::move(triangles);
  return absl::OkStatus();
}

}  // namespace

absl::StatusOr<std::vector<int>> ConvertGltfMesh(const GltfDocument& document, int mesh_index,
                                                 GltfMaterials& materials, Assets& assets,
                                                 WarningList& warnings) {
  const tinygltf::Model& model = document.model;
  const tinygltf::Mesh& mesh = model.meshes[mesh_index];
  std::vector<int> converted;
  for (size_t p = 0; p < mesh.primitives.size(); ++p) {
    const tinygltf::Primitive& primitive = mesh.primitives[p];
    const std::string object =
        absl::StrCat("mesh ", mesh_index, " '", mesh.name, "' primitive ", p);
    const std::string what = absl::StrCat(document.file, ": ", object);
    if (!primitive.targets.empty()) {
      warnings.Add("morph", absl::StrCat(object,
                                         ": morph targets are not supported; the mesh "
                                         "renders in its base shape"));
    }
    const int mode = primitive.mode < 0 ? TINYGLTF_MODE_TRIANGLES : primitive.mode;
    if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP &&
        mode != TINYGLTF_MODE_TRIANGLE_FAN) {
      warnings.Add(
          absl::StrCat("mode:", ModeName(mode)),
          absl::StrCat(object, ": ", ModeName(mode), " primitives are not rendered; left out"));
      continue;
    }
    Mesh out;
    out.name = mesh.primitives.size() == 1 ? mesh.name : absl::StrCat(mesh.name, "/", p);
    absl::Status status = ConvertPrimitive(model, primitive, what, out);
    if (!status.ok()) return status;
    if (out.indices.empty()) {
      warnings.Add("empty", absl::StrCat(object, ": no triangles; left out"));
      continue;
    }
    absl::StatusOr<int> material = materials.Get(primitive.material);
    if (!material.ok()) return material.status();
    out.material = *material;
    assets.meshes.push_back(std::move(out));
    converted.push_back(static_cast<int>(assets.meshes.size()) - 1);
  }
  return converted;
}

}  // namespace tessera::render

#include "gltf_loader.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>
#include <vector>

#include "absl/strings/str_cat.h"
#include "gltf_animation.h"
#include "gltf_document.h"
#include "gltf_material.h"
#include "gltf_mesh.h"
#include "loaded_scene.h"
#include "warnings.h"

namespace tessera::render {
namespace {

constexpr double kPi = 3.14159265358979323846;

bool AllFinite(const std::vector<double>& values) {
  for (double v : values) {
    if (!std::isfinite(v)) return false;
  }
  return true;
}

// The node's local transform: its matrix, or its translation, rotation and scale.
absl::Status LocalTransform(const tinygltf::Node& node, const std::string& what, SceneNode& out) {
  const auto check = [&](const std::vector<double>& v, size_t size, const char* name) {
    if ((!v.empty() && v.size() != size) || !AllFinite(v)) {
      return absl::InvalidArgumentError(
          absl::StrCat(what, ": ", name, " needs ", size, " finite numbers"));
    }
    return absl::OkStatus();
  };
  absl::Status status = check(node.matrix, 16, "matrix");
  if (status.ok()) status = check(node.translation, 3, "translation");
  if (status.ok()) status = check(node.rotation, 4, "rotation");
  if (status.ok()) status = check(node.scale, 3, "scale");
  if (!status.ok()) return status;
  if (!node.matrix.empty()) {
    out.has_matrix = true;
    out.matrix = ColumnMajorToAffine(node.matrix.data());
    return absl::OkStatus();
  }
  std::copy(node.translation.begin(), node.translation.end(), out.trs.translation.begin());
  std::copy(node.rotation.begin(), node.rotation.end(), out.trs.rotation.begin());
  std::copy(node.scale.begin(), node.scale.end(), out.trs.scale.begin());
  return absl::OkStatus();
}

absl::StatusOr<Camera> ConvertCamera(const tinygltf::Camera& in, const std::string& node_name,
                                     const std::string& what) {
  Camera out;
  out.name = !in.name.empty() ? in.name : node_name;
  if (in.type == "perspective") {
    const tinygltf::PerspectiveCamera& p = in.perspective;
    if (!(p.yfov > 0.0 && p.yfov < kPi) || !(p.aspectRatio >= 0.0) || !(p.znear >= 0.0)) {
      return absl::InvalidArgumentError(
          absl::StrCat(what, ": perspective yfov ", p.yfov, ", aspectRatio ", p.aspectRatio,
                       ", znear ", p.znear, " (yfov must lie in (0, pi), the others be >= 0)"));
    }
    out.yfov = static_cast<float>(p.yfov);
    out.aspect = static_cast<float>(p.aspectRatio);
    out.znear = static_cast<float>(p.znear);
  } else if (in.type == "orthographic") {
    const tinygltf::OrthographicCamera& o = in.orthographic;
    if (!(o.xmag != 0.0 && std::isfinite(o.xmag)) || !(o.ymag != 0.0 && std::isfinite(o.ymag)) ||
        !std::isfinite(o.znear)) {
      return absl::InvalidArgumentError(absl::StrCat(what, ": orthographic xmag ", o.xmag,
                                                     ", ymag ", o.ymag, ", znear ", o.znear));
    }
    out.orthographic = true;
    out.xmag = static_cast<float>(o.xmag);
    out.ymag = static_cast<float>(o.ymag);
    out.znear = static_cast<float>(o.znear);
  } else {
    return absl::InvalidArgumentError(absl::StrCat(what, ": camera type '", in.type,
                                                   "' (glTF has perspective and orthographic)"));
  }
  return out;
}

absl::StatusOr<Light> ConvertLight(const tinygltf::Light& in, const std::string& node_name,
                                   const std::string& what) {
  Light out;
  out.name = !in.name.empty() ? in.name : node_name;
  if (in.type == "point") {
    out.type = Light::Type::kPoint;
  } else if (in.type == "spot") {
    out.type = Light::Type::kSpot;
  } else if (in.type == "directional") {
    out.type = Light::Type::kDirectional;
  } else {
    return absl::InvalidArgumentError(absl::StrCat(what, ": light type '", in.type, "'"));
  }
  if ((!in.color.empty() && in.color.size() != 3) || !AllFinite(in.color)) {
    return absl::InvalidArgumentError(absl::StrCat(what, ": color needs 3 finite numbers"));
  }
  for (size_t c = 0; c < in.color.size(); ++c) {
    out.color[c] = static_cast<float>(std::max(in.color[c], 0.0));
  }
  if (!(in.intensity >= 0.0) || !std::isfinite(in.intensity) || !(in.range >= 0.0)) {
    return absl::InvalidArgumentError(absl::StrCat(what, ": intensity ", in.intensity, ", range ",
                                                   in.range, " (both must be finite and >= 0)"));
  }
  out.intensity = static_cast<float>(in.intensity);
  out.range = std::isfinite(in.range) ? static_cast<float>(in.range) : 0.f;
  if (out.type == Light::Type::kSpot) {
    const double inner = in.spot.innerConeAngle, outer = in.spot.outerConeAngle;
    if (!(inner >= 0.0 && inner < outer && outer <= kPi / 2)) {
      return absl::InvalidArgumentError(absl::StrCat(what, ": spot cone angles ", inner, " and ",
                                                     outer, " (need 0 <= inner < outer <= pi/2)"));
    }
    out.inner_cone = static_cast<float>(inner);
    out.outer_cone = static_cast<float>(outer);
  }
  return out;
}

// The KHR_lights_punctual light a node holds, -1 for none.
int NodeLight(const tinygltf::Node& node) {
  const auto it = node.extensions.find("KHR_lights_punctual");
  if (it == node.extensions.end() || !it->second.IsObject() || !it->second.Has("light")) return -1;
  const tinygltf::Value& light = it->second.Get("light");
  return light.IsInt() ? light.GetNumberAsInt() : -2;  // -2: present but not an index
}

// The root nodes to render: the default scene's, scene 0's, or (a file without scenes, which
// glTF leaves to the application) every node no other node names as a child.
absl::StatusOr<std::vector<int>> RootNodes(const GltfDocument& document, WarningList& warnings) {
  const tinygltf::Model& model = document.model;
  if (!model.scenes.empty()) {
    int scene = model.defaultScene;
    if (scene < 0) {
      scene = 0;
    } else if (static_cast<size_t>(scene) >= model.scenes.size()) {
      return absl::InvalidArgumentError(
          absl::StrCat(document.file, ": default scene ", scene, " does not exist"));
    }
    if (model.scenes.size() > 1) {
      warnings.Add("scenes", absl::StrCat("holds ", model.scenes.size(), " scenes; only scene ",
                                          scene, " '", model.scenes[scene].name, "' is loaded"));
    }
    return model.scenes[scene].nodes;
  }
  std::vector<bool> is_child(model.nodes.size(), false);
  for (const tinygltf::Node& node : model.nodes) {
    for (int child : node.children) {
      if (child >= 0 && static_cast<size_t>(child) < model.nodes.size()) is_child[child] = true;
    }
  }
  std::vector<int> roots;
  for (size_t n = 0; n < model.nodes.size(); ++n) {
    if (!is_child[n]) roots.push_back(static_cast<int>(n));
  }
  return roots;
}

class GltfSceneBuilder {
 public:
  explicit GltfSceneBuilder(const GltfDocument& document)
      : document_(document),
        model_(document.model),
        warnings_(document.file),
        materials_(document, &assets_, &warnings_),
        scene_node_of_(model_.nodes.size(), -1) {}

  absl::StatusOr<std::unique_ptr<SceneFile>> Build() && {
    for (const std::string& extension : model_.extensionsUsed) {
      if (!IsSupportedGltfExtension(extension)) {
        warnings_.Add(
            absl::StrCat("extension:", extension),
            absl::StrCat("uses glTF extension ", extension, ", which tessera render ignores"));
      }
    }
    absl::StatusOr<std::vector<int>> roots = RootNodes(document_, warnings_);
    if (!roots.ok()) return roots.status();
    absl::Status status = AddNodes(*roots);
    if (status.ok()) status = ConvertGltfAnimations(document_, scene_node_of_, graph_, warnings_);
    if (!status.ok()) return status;
    if (assets_.meshes.empty()) {
      return absl::UnimplementedError(
          absl::StrCat(document_.file,
                       ": its scene holds no triangles (tessera render renders triangle "
                       "meshes only)"));
    }
    return std::make_unique<LoadedScene>(std::move(assets_), std::move(graph_), warnings_.Lines());
  }

 private:
  // Every node below `roots`, parents before children, walked with an explicit stack: a
  // hostile file's hierarchy may be deeper than the thread's stack.
  absl::Status AddNodes(const std::vector<int>& roots) {
    std::vector<std::pair<int, int>> stack;  // glTF node, parent SceneNode
    for (auto it = roots.rbegin(); it != roots.rend(); ++it) stack.emplace_back(*it, -1);
    while (!stack.empty()) {
      const auto [index, parent] = stack.back();
      stack.pop_back();
      if (index < 0 || static_cast<size_t>(index) >= model_.nodes.size()) {
        return absl::InvalidArgumentError(absl::StrCat(document_.file, ": node ", index,
                                                       " does not exist (the file has ",
                                                       model_.nodes.size(), ")"));
      }
      if (scene_node_of_[index] >= 0) {
        // glTF nodes form disjoint trees; a second visit is a cycle or a shared child, and
        // following it would loop forever or instance a subtree twice.
        return absl::InvalidArgumentError(
            absl::StrCat(document_.file, ": node ", index, " '", model_.nodes[index].name,
                         "' is reached twice in the scene (a cycle, or a node with two "
                         "parents)"));
      }
      const int scene_node = static_cast<int>(graph_.nodes.size());
      scene_node_of_[index] = scene_node;
      absl::StatusOr<SceneNode> node = ConvertNode(index, parent);
      if (!node.ok()) return node.status();
      graph_.nodes.push_back(*std::move(node));
      const std::vector<int>& children = model_.nodes[index].children;
      for (auto it = children.rbegin(); it != children.rend(); ++it) {
        stack.emplace_back(*it, scene_node);
      }
    }
    return absl::OkStatus();
  }

  absl::StatusOr<SceneNode> ConvertNode(int index, int parent) {
    const tinygltf::Node& node = model_.nodes[index];
    const std::string object = absl::StrCat("node ", index, " '", node.name, "'");
    const std::string what = absl::StrCat(document_.file, ": ", object);
    SceneNode out;
    out.parent = parent;
    absl::Status status = LocalTransform(node, what, out);
    if (!status.ok()) return status;

    if (node.mesh >= 0) {
      if (static_cast<size_t>(node.mesh) >= model_.meshes.size()) {
        return absl::InvalidArgumentError(
            absl::StrCat(what, ": mesh ", node.mesh, " does not exist"));
      }
      auto [it, first_use] = meshes_.try_emplace(node.mesh);
      if (first_use) {
        absl::StatusOr<std::vector<int>> meshes =
            ConvertGltfMesh(document_, node.mesh, materials_, assets_, warnings_);
        if (!meshes.ok()) return meshes.status();
        it->second = *std::move(meshes);
      }
      out.meshes = it->second;
      if (node.skin >= 0) {
        warnings_.Add("skin", absl::StrCat(object,
                                           ": skins are not supported; the mesh renders "
                                           "in its bind pose"));
      }
    }
    if (node.camera >= 0) {
      if (static_cast<size_t>(node.camera) >= model_.cameras.size()) {
        return absl::InvalidArgumentError(
            absl::StrCat(what, ": camera ", node.camera, " does not exist"));
      }
      absl::StatusOr<Camera> camera = ConvertCamera(model_.cameras[node.camera], node.name,
                                                    absl::StrCat(what, " camera ", node.camera));
      if (!camera.ok()) return camera.status();
      out.camera = static_cast<int>(graph_.cameras.size());
      graph_.cameras.push_back(*std::move(camera));
    }
    const int light = NodeLight(node);
    if (light != -1) {
      if (light < 0 || static_cast<size_t>(light) >= model_.lights.size()) {
        return absl::InvalidArgumentError(
            absl::StrCat(what, ": KHR_lights_punctual light ", light, " does not exist"));
      }
      absl::StatusOr<Light> converted =
          ConvertLight(model_.lights[light], node.name, absl::StrCat(what, " light ", light));
      if (!converted.ok()) return converted.status();
      out.light = static_cast<int>(graph_.lights.size());
      graph_.lights.push_back(*std::move(converted));
    }
    return out;
  }

  const GltfDocument& document_;
  const tinygltf::Model& model_;
  Assets assets_;
  SceneGraphData graph_;
  WarningList warnings_;
  GltfMaterials materials_;
  std::vector<int> scene_node_of_;          // glTF node -> SceneGraphData::nodes, -1 if not there
  std::map<int, std::vector<int>> meshes_;  // glTF mesh -> Assets::meshes
};

}  // namespace

absl::StatusOr<std::unique_ptr<SceneFile>> LoadGltf(const std::string& path, bool binary) {
  absl::StatusOr<GltfDocument> document = ReadGltfDocument(path, binary);
  if (!document.ok()) return document.status();
  return GltfSceneBuilder(*document).Build();
}

}  // namespace tessera::render

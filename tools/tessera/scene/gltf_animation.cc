#include "gltf_animation.h"

#include <algorithm>
#include <string>

#include "absl/strings/str_cat.h"
#include "gltf_accessor.h"

namespace tessera::render {

absl::Status ConvertGltfAnimations(const GltfDocument& document,
                                   const std::vector<int>& scene_node_of, SceneGraphData& graph,
                                   WarningList& warnings) {
  const tinygltf::Model& model = document.model;
  bool any_key = false;
  for (size_t a = 0; a < model.animations.size(); ++a) {
    const tinygltf::Animation& animation = model.animations[a];
    const std::string object = absl::StrCat("animation ", a, " '", animation.name, "'");
    for (size_t c = 0; c < animation.channels.size(); ++c) {
      const tinygltf::AnimationChannel& in = animation.channels[c];
      const std::string what = absl::StrCat(document.file, ": ", object, " channel ", c);
      if (in.sampler < 0 || static_cast<size_t>(in.sampler) >= animation.samplers.size()) {
        return absl::InvalidArgumentError(
            absl::StrCat(what, ": sampler ", in.sampler, " does not exist"));
      }
      if (in.target_node < 0 || static_cast<size_t>(in.target_node) >= model.nodes.size()) {
        return absl::InvalidArgumentError(
            absl::StrCat(what, ": target node ", in.target_node, " does not exist"));
      }
      const tinygltf::AnimationSampler& sampler = animation.samplers[in.sampler];

      AnimationChannel out;
      if (in.target_path == "translation") {
        out.property = AnimatedProperty::kTranslation;
      } else if (in.target_path == "rotation") {
        out.property = AnimatedProperty::kRotation;
      } else if (in.target_path == "scale") {
        out.property = AnimatedProperty::kScale;
      } else if (in.target_path == "weights") {
        warnings.Add("morph-animation",
                     absl::StrCat(object,
                                  ": animated morph target weights are not supported; "
                                  "ignored"));
        continue;
      } else {
        return absl::InvalidArgumentError(
            absl::StrCat(what, ": unknown target path '", in.target_path, "'"));
      }
      if (sampler.interpolation == "LINEAR") {
        out.interpolation = Interpolation::kLinear;
      } else if (sampler.interpolation == "STEP") {
        out.interpolation = Interpolation::kStep;
      } else if (sampler.interpolation == "CUBICSPLINE") {
        out.interpolation = Interpolation::kCubicSpline;
      } else {
        return absl::InvalidArgumentError(
            absl::StrCat(what, ": unknown interpolation '", sampler.interpolation, "'"));
      }

      absl::StatusOr<FloatAccessor> times =
          ReadFloatAccessor(model, sampler.input, {TINYGLTF_TYPE_SCALAR}, what + " input");
      if (!times.ok()) return times.status();
      const int type =
          out.property == AnimatedProperty::kRotation ? TINYGLTF_TYPE_VEC4 : TINYGLTF_TYPE_VEC3;
      absl::StatusOr<FloatAccessor> values =
          ReadFloatAccessor(model, sampler.output, {type}, what + " output");
      if (!values.ok()) return values.status();
      out.times = std::move(times->values);
      out.values = std::move(values->values);
      absl::Status valid = ValidateChannel(out, what);
      if (!valid.ok()) return valid;

      // The range covers channels outside the scene too: they belong to the same animation, and
      // its clock does not depend on which scene shows it.
      const double first = out.times.front(), last = out.times.back();
      graph.time_begin = any_key ? std::min(graph.time_begin, first) : first;
      graph.time_end = any_key ? std::max(graph.time_end, last) : last;
      any_key = true;

      out.node = scene_node_of[in.target_node];
      if (out.node < 0) continue;
      if (graph.nodes[out.node].has_matrix) {
        // glTF forbids animating a node given by matrix: there is no TRS to change.
        warnings.Add("matrix-animation",
                     absl::StrCat(object, " channel ", c, " animates node ", in.target_node,
                                  ", which has a matrix; ignored"));
        continue;
      }
      graph.channels.push_back(std::move(out));
    }
  }
  return absl::OkStatus();
}

}  // namespace tessera::render

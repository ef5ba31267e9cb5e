#include "gltf_material.h"

#include <algorithm>
#include <cmath>

#include "absl/strings/ascii.h"
#include "absl/strings/str_cat.h"
#include "gltf_accessor.h"

namespace tessera::render {
namespace {

// A number from an extension's JSON object, or `fallback` when absent or not a number.
double ExtensionNumber(const tinygltf::ExtensionMap& extensions, const std::string& extension,
                       const std::string& key, double fallback) {
  const auto it = extensions.find(extension);
  if (it == extensions.end() || !it->second.IsObject() || !it->second.Has(key)) return fallback;
  const tinygltf::Value& value = it->second.Get(key);
  return value.IsNumber() ? value.GetNumberAsDouble() : fallback;
}

bool HasExtensionTexture(const tinygltf::ExtensionMap& extensions, const std::string& extension,
                         const std::string& key) {
  const auto it = extensions.find(extension);
  return it != extensions.end() && it->second.IsObject() && it->second.Has(key);
}

// OpenImageIO's reader for an image, from its mime type or URI, for bytes whose magic number
// does not say (see DecodeImage).
std::string ExtensionHint(const tinygltf::Image& image) {
  if (image.mimeType == "image/png") return "png";
  if (image.mimeType == "image/jpeg") return "jpg";
  const size_t dot = image.uri.rfind('.');
  if (image.uri.rfind("data:", 0) == 0 || dot == std::string::npos) return "";
  return absl::AsciiStrToLower(image.uri.substr(dot + 1));
}

// Factors outside their range would make the renderer's BSDF non-physical (negative or
// energy-creating); NaN compares false everywhere, so it becomes the lower bound.
float Clamp01(double v) { return v > 0.0 ? static_cast<float>(std::min(v, 1.0)) : 0.f; }

}  // namespace

absl::StatusOr<int> GltfMaterials::Get(int material) {
  if (material < 0) return -1;
  if (const auto it = materials_.find(material); it != materials_.end()) return it->second;
  if (static_cast<size_t>(material) >= document_.model.materials.size()) {
    return absl::InvalidArgumentError(absl::StrCat(document_.file, ": material ", material,
                                                   " does not exist (the file has ",
                                                   document_.model.materials.size(), ")"));
  }
  absl::StatusOr<Material> converted = Convert(material);
  if (!converted.ok()) return converted.status();
  assets_.materials.push_back(*std::move(converted));
  const int index = static_cast<int>(assets_.materials.size()) - 1;
  materials_[material] = index;
  return index;
}

absl::StatusOr<Material> GltfMaterials::Convert(int index) {
  const tinygltf::Material& m = document_.model.materials[index];
  const std::string object = absl::StrCat("material ", index, " '", m.name, "'");
  const std::string what = absl::StrCat(document_.file, ": ", object);
  Material out;
  out.name = m.name;
  const tinygltf::PbrMetallicRoughness& pbr = m.pbrMetallicRoughness;
  if (pbr.baseColorFactor.size() != 4) {
    return absl::InvalidArgumentError(absl::StrCat(
        what, ": baseColorFactor has ", pbr.baseColorFactor.size(), " components, not 4"));
  }
  for (int c = 0; c < 4; ++c) out.base_color[c] = Clamp01(pbr.baseColorFactor[c]);
  out.metallic = Clamp01(pbr.metallicFactor);
  out.roughness = Clamp01(pbr.roughnessFactor);

  // KHR_materials_emissive_strength exists because emissiveFactor stops at 1: the product may
  // exceed 1 (that is its purpose), but not be negative.
  const double strength =
      ExtensionNumber(m.extensions, "KHR_materials_emissive_strength", "emissiveStrength", 1.0);
  if (!m.emissiveFactor.empty() && m.emissiveFactor.size() != 3) {
    return absl::InvalidArgumentError(
        absl::StrCat(what, ": emissiveFactor has ", m.emissiveFactor.size(), " components, not 3"));
  }
  for (int c = 0; c < 3 && !m.emissiveFactor.empty(); ++c) {
    const double e = Clamp01(m.emissiveFactor[c]) * strength;
    out.emissive[c] = e > 0.0 && std::isfinite(e) ? static_cast<float>(e) : 0.f;
  }

  out.normal_scale = static_cast<float>(m.normalTexture.scale);
  out.double_sided = m.doubleSided;
  out.ior = static_cast<float>(ExtensionNumber(m.extensions, "KHR_materials_ior", "ior", 1.5));
  if (!(out.ior >= 1.f) && out.ior != 0.f) {  // KHR_materials_ior allows 0 (no refraction)
    return absl::InvalidArgumentError(absl::StrCat(what, ": ior ", out.ior, " below 1"));
  }
  out.specular =
      Clamp01(ExtensionNumber(m.extensions, "KHR_materials_specular", "specularFactor", 1.0));
  out.transmission = Clamp01(
      ExtensionNumber(m.extensions, "KHR_materials_transmission", "transmissionFactor", 0.0));
  if (HasExtensionTexture(m.extensions, "KHR_materials_transmission", "transmissionTexture")) {
    warnings_.Add("transmissionTexture",
                  absl::StrCat(object,
                               ": transmissionTexture is not supported; its factor applies "
                               "everywhere"));
  }

  struct Slot {
    int gltf_texture;
    int tex_coord;
    ColorSpace color_space;
    const char* name;
    int* target;
  };
  const Slot slots[] = {
      {pbr.baseColorTexture.index, pbr.baseColorTexture.texCoord, ColorSpace::kSrgb,
       "baseColorTexture", &out.base_color_texture},
      {pbr.metallicRoughnessTexture.index, pbr.metallicRoughnessTexture.texCoord,
       ColorSpace::kLinear, "metallicRoughnessTexture", &out.metallic_roughness_texture},
      {m.emissiveTexture.index, m.emissiveTexture.texCoord, ColorSpace::kSrgb, "emissiveTexture",
       &out.emissive_texture},
      {m.normalTexture.index, m.normalTexture.texCoord, ColorSpace::kLinear, "normalTexture",
       &out.normal_texture},
  };
  for (const Slot& slot : slots) {
    if (slot.gltf_texture < 0) continue;
    if (slot.tex_coord != 0) {
      warnings_.Add("texCoord",
                    absl::StrCat(object, " ", slot.name, " reads TEXCOORD_", slot.tex_coord,
                                 "; only TEXCOORD_0 is loaded, and used instead"));
    }
    absl::StatusOr<int> texture =
        TextureIndex(slot.gltf_texture, slot.color_space, absl::StrCat(object, " ", slot.name));
    if (!texture.ok()) return texture.status();
    *slot.target = *texture;
  }
  return out;
}

absl::StatusOr<int> GltfMaterials::TextureIndex(int texture, ColorSpace color_space,
                                                const std::string& object) {
  const tinygltf::Model& model = document_.model;
  const std::string what = absl::StrCat(document_.file, ": ", object);
  if (static_cast<size_t>(texture) >= model.textures.size()) {
    return absl::InvalidArgumentError(absl::StrCat(
        what, ": texture ", texture, " does not exist (the file has ", model.textures.size(), ")"));
  }
  const int image_index = model.textures[texture].source;
  if (image_index < 0) {
    // Images only an extension names (KHR_texture_basisu, EXT_texture_webp) have no source.
    warnings_.Add(absl::StrCat("texture-source:", texture),
                  absl::StrCat(object, ": texture ", texture,
                               " has no PNG or JPEG source; the material uses its factor alone"));
    return -1;
  }
  if (static_cast<size_t>(image_index) >= model.images.size()) {
    return absl::InvalidArgumentError(absl::StrCat(what, ": texture ", texture, " names image ",
                                                   image_index, ", which does not exist"));
  }
  const auto key = std::make_pair(image_index, color_space);
  if (const auto it = textures_.find(key); it != textures_.end()) return it->second;

  const tinygltf::Image& image = model.images[image_index];
  const std::string name = !image.name.empty() ? image.name
                           : (!image.uri.empty() && image.uri.rfind("data:", 0) != 0)
                               ? image.uri
                               : absl::StrCat("image ", image_index);
  ByteSpan bytes;
  if (image.bufferView >= 0) {
    absl::StatusOr<ByteSpan> view =
        BufferViewBytes(model, image.bufferView, absl::StrCat(what, " image ", image_index));
    if (!view.ok()) return view.status();
    bytes = *view;
  } else if (const auto it = document_.uri_image_bytes.find(image_index);
             it != document_.uri_image_bytes.end()) {
    bytes = {it->second.data(), it->second.size()};
  }

  absl::StatusOr<Texture> decoded =
      bytes.size == 0
          ? absl::NotFoundError("missing file")
          : DecodeImage(bytes.data, bytes.size, ExtensionHint(image), name, color_space);
  int index = -1;
  if (decoded.ok()) {
    assets_.textures.push_back(*std::move(decoded));
    index = static_cast<int>(assets_.textures.size()) - 1;
  } else {
    // A texture that cannot be read leaves the geometry and the other material inputs intact:
    // a warning and the material's factor alone, rather than no image at all.
    const std::string problem = bytes.size == 0
                                    ? absl::StrCat("image file '", image.uri, "' cannot be read")
                                    : std::string(decoded.status().message());
    warnings_.Add(absl::StrCat("image:", image_index),
                  absl::StrCat(object, ": ", problem, "; the material uses its factor alone"));
  }
  textures_[key] = index;
  return index;
}

}  // namespace tessera::render

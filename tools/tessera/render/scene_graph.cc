#include "tools/tessera/render/scene_graph.h"

#include <cmath>
#include <cstring>
#include <string>

#include "absl/strings/str_cat.h"
#include "tools/tessera/render/programs/path_tracer.h"

namespace tessera::render {
namespace {

using path_tracer::EmissiveTriangle;
using path_tracer::PunctualLight;

float Luminance(const float c[3]) { return 0.2126f * c[0] + 0.7152f * c[1] + 0.0722f * c[2]; }

// A 1D INPUT buffer holding `count` elements of `format` copied from `data`.
optix::Buffer MakeBuffer(optix::Context& context, RTformat format, size_t element_size,
                         const void* data, size_t count) {
  optix::Buffer buffer = context->createBuffer(RT_BUFFER_INPUT, format);
  if (format == RT_FORMAT_USER) buffer->setElementSize(element_size);
  buffer->setSize(count);
  if (count != 0) {
    std::memcpy(buffer->map(), data, count * element_size);
    buffer->unmap();
  }
  return buffer;
}

// Linear filtering, repeating, normalized coordinates, float texels: a glTF sampler's defaults.
int MakeTexture(optix::Context& context, const Texture& texture) {
  optix::Buffer buffer =
      context->createBuffer(RT_BUFFER_INPUT, RT_FORMAT_FLOAT4, static_cast<RTsize>(texture.width),
                            static_cast<RTsize>(texture.height));
  // Row 0 of the buffer is the image's top row: texture coordinate v = 0, as glTF has it.
  std::memcpy(buffer->map(), texture.rgba.data(), texture.rgba.size() * sizeof(float));
  buffer->unmap();
  optix::TextureSampler sampler = context->createTextureSampler();
  sampler->setWrapMode(0, RT_WRAP_REPEAT);
  sampler->setWrapMode(1, RT_WRAP_REPEAT);
  sampler->setFilteringModes(RT_FILTER_LINEAR, RT_FILTER_LINEAR, RT_FILTER_NONE);
  sampler->setIndexingMode(RT_TEXTURE_INDEX_NORMALIZED_COORDINATES);
  sampler->setReadMode(RT_TEXTURE_READ_ELEMENT_TYPE);
  sampler->setMaxAnisotropy(1.0f);
  sampler->setBuffer(buffer);
  return sampler->getId();
}

// 3x4 object-to-world as the 4x4 row-major matrix rtTransformSetMatrix takes.
void ToMatrix4(const Affine& a, float m[16]) {
  std::copy(a.begin(), a.end(), m);
  m[12] = m[13] = m[14] = 0.f;
  m[15] = 1.f;
}

double Determinant(const Affine& a) {
  const auto m = [&](int i) { return static_cast<double>(a[static_cast<size_t>(i)]); };
  return m(0) * (m(5) * m(10) - m(6) * m(9)) - m(1) * (m(4) * m(10) - m(6) * m(8)) +
         m(2) * (m(4) * m(9) - m(5) * m(8));
}

bool Invertible(const Affine& a) {
  for (float v : a) {
    if (!std::isfinite(v)) return false;
  }
  const double det = Determinant(a);
  return std::isfinite(det) && std::fabs(det) > 1e-30;
}

float3 Point(const Affine& a, const float* p) {
  return make_float3(a[0] * p[0] + a[1] * p[1] + a[2] * p[2] + a[3],
                     a[4] * p[0] + a[5] * p[1] + a[6] * p[2] + a[7],
                     a[8] * p[0] + a[9] * p[1] + a[10] * p[2] + a[11]);
}
float3 Sub(float3 a, float3 b) { return make_float3(a.x - b.x, a.y - b.y, a.z - b.z); }
float3 Cross(float3 a, float3 b) {
  return make_float3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}

int TextureId(const std::vector<int>& ids, int texture) {
  return texture >= 0 ? ids[static_cast<size_t>(texture)] : path_tracer::kNoTexture;
}

}  // namespace

absl::StatusOr<SceneGraph> SceneGraph::Build(optix::Context context, const Programs& programs,
                                             const Assets& assets) {
  SceneGraph graph;
  graph.context_ = context;
  graph.assets_ = &assets;
  graph.default_material_.name = "(default)";
  graph.default_material_.base_color[0] = graph.default_material_.base_color[1] =
      graph.default_material_.base_color[2] = 0.8f;
  graph.default_material_.metallic = 0.f;

  for (const Texture& texture : assets.textures) {
    if (texture.width <= 0 || texture.height <= 0 ||
        texture.rgba.size() != 4 * static_cast<size_t>(texture.width) * texture.height) {
      return absl::InvalidArgumentError("texture '" + texture.name +
                                        "' has no pixels or the "
                                        "wrong number of them");
    }
    graph.texture_ids_.push_back(MakeTexture(context, texture));
  }

  auto check_texture = [&](const Material& m, int texture) -> absl::Status {
    if (texture < -1 || texture >= static_cast<int>(assets.textures.size())) {
      return absl::InvalidArgumentError(absl::StrCat("material '", m.name, "' names texture ",
                                                     texture, " of ", assets.textures.size()));
    }
    return absl::OkStatus();
  };
  std::vector<optix::Material> materials;
  for (size_t i = 0; i <= assets.materials.size(); ++i) {
    const Material& m = i < assets.materials.size() ? assets.materials[i] : graph.default_material_;
    for (int t : {m.base_color_texture, m.metallic_roughness_texture, m.emissive_texture,
                  m.normal_texture}) {
      if (absl::Status s = check_texture(m, t); !s.ok()) return s;
    }
    optix::Material material = context->createMaterial();
    material->setClosestHitProgram(path_tracer::kRadianceRay, programs.closest_hit);
    const std::vector<int>& ids = graph.texture_ids_;
    material["base_color_factor"]->setFloat(m.base_color[0], m.base_color[1], m.base_color[2],
                                            m.base_color[3]);
    material["base_color_texture"]->setInt(TextureId(ids, m.base_color_texture));
    material["metallic_factor"]->setFloat(m.metallic);
    material["roughness_factor"]->setFloat(m.roughness);
    material["metallic_roughness_texture"]->setInt(TextureId(ids, m.metallic_roughness_texture));
    material["emissive_factor"]->setFloat(m.emissive[0], m.emissive[1], m.emissive[2]);
    material["emissive_texture"]->setInt(TextureId(ids, m.emissive_texture));
    material["normal_texture"]->setInt(TextureId(ids, m.normal_texture));
    material["normal_scale"]->setFloat(m.normal_scale);
    material["ior"]->setFloat(m.ior);
    material["transmission"]->setFloat(m.transmission);
    material["specular_factor"]->setFloat(m.specular);
    material["double_sided"]->setInt(m.double_sided ? 1 : 0);
    materials.push_back(material);
  }

  for (const Mesh& mesh : assets.meshes) {
    const size_t vertices = mesh.positions.size() / 3;
    const size_t triangles = mesh.indices.size() / 3;
    if (mesh.material < -1 || mesh.material >= static_cast<int>(assets.materials.size())) {
      return absl::InvalidArgumentError(absl::StrCat("mesh '", mesh.name, "' names material ",
                                                     mesh.material, " of ",
                                                     assets.materials.size()));
    }
    for (uint32_t index : mesh.indices) {
      if (index >= vertices) {
        return absl::InvalidArgumentError(absl::StrCat("mesh '", mesh.name, "' has index ", index,
                                                       " of ", vertices, " vertices"));
      }
    }
    auto optional = [&](const std::vector<float>& values, size_t per_vertex) {
      return values.size() == vertices * per_vertex ? values.size() / per_vertex : 0;
    };
    if (triangles == 0) {
      graph.mesh_groups_.emplace_back();  // nothing to hit
      continue;
    }
    optix::GeometryTriangles geometry = context->createGeometryTriangles();
    optix::Buffer positions =
        MakeBuffer(context, RT_FORMAT_FLOAT3, 12, mesh.positions.data(), vertices);
    optix::Buffer indices =
        MakeBuffer(context, RT_FORMAT_UNSIGNED_INT3, 12, mesh.indices.data(), triangles);
    geometry->setPrimitiveCount(static_cast<unsigned>(triangles));
    geometry->setVertices(static_cast<unsigned>(vertices), positions, RT_FORMAT_FLOAT3);
    geometry->setTriangleIndices(indices, RT_FORMAT_UNSIGNED_INT3);
    geometry->setAttributeProgram(programs.attributes);
    geometry["vertex_buffer"]->setBuffer(positions);
    geometry["index_buffer"]->setBuffer(indices);
    geometry["normal_buffer"]->setBuffer(
        MakeBuffer(context, RT_FORMAT_FLOAT3, 12, mesh.normals.data(), optional(mesh.normals, 3)));
    geometry["texcoord_buffer"]->setBuffer(MakeBuffer(
        context, RT_FORMAT_FLOAT2, 8, mesh.texcoords.data(), optional(mesh.texcoords, 2)));
    geometry["tangent_buffer"]->setBuffer(MakeBuffer(
        context, RT_FORMAT_FLOAT4, 16, mesh.tangents.data(), optional(mesh.tangents, 4)));
    optix::GeometryInstance instance = context->createGeometryInstance();
    instance->setGeometryTriangles(geometry);
    instance->addMaterial(materials[mesh.material >= 0 ? static_cast<size_t>(mesh.material)
                                                       : assets.materials.size()]);
    optix::GeometryGroup group = context->createGeometryGroup();
    group->setAcceleration(context->createAcceleration("Trbvh"));
    group->addChild(instance);
    graph.mesh_groups_.push_back(group);
  }

  graph.top_ = context->createGroup();
  graph.top_acceleration_ = context->createAcceleration("Trbvh");
  graph.top_->setAcceleration(graph.top_acceleration_);
  context["top_object"]->set(graph.top_);
  graph.lights_ = context->createBuffer(RT_BUFFER_INPUT, RT_FORMAT_USER);
  graph.lights_->setElementSize(sizeof(PunctualLight));
  graph.lights_->setSize(0);
  context["lights"]->setBuffer(graph.lights_);
  graph.emissive_triangles_ = context->createBuffer(RT_BUFFER_INPUT, RT_FORMAT_USER);
  graph.emissive_triangles_->setElementSize(sizeof(EmissiveTriangle));
  graph.emissive_triangles_->setSize(0);
  context["emissive_triangles"]->setBuffer(graph.emissive_triangles_);
  graph.emissive_cdf_ = context->createBuffer(RT_BUFFER_INPUT, RT_FORMAT_FLOAT, 0);
  context["emissive_cdf"]->setBuffer(graph.emissive_cdf_);
  context["emissive_power"]->setFloat(0.f);
  return graph;
}

const Material& SceneGraph::MaterialOf(const Mesh& mesh) const {
  return mesh.material >= 0 ? assets_->materials[static_cast<size_t>(mesh.material)]
                            : default_material_;
}

void SceneGraph::SetFrame(const Frame& frame) {
  std::vector<const Instance*> shown;
  for (const Instance& instance : frame.instances) {
    if (instance.mesh < 0 || static_cast<size_t>(instance.mesh) >= mesh_groups_.size()) continue;
    if (!mesh_groups_[static_cast<size_t>(instance.mesh)] || !Invertible(instance.to_world)) {
      continue;
    }
    shown.push_back(&instance);
  }
  // Transforms are kept and re-pointed: a frame usually differs from the last in matrices only.
  while (transforms_.size() < shown.size()) transforms_.push_back(context_->createTransform());
  top_->setChildCount(static_cast<unsigned>(shown.size()));
  for (size_t i = 0; i < shown.size(); ++i) {
    float m[16];
    ToMatrix4(shown[i]->to_world, m);
    transforms_[i]->setMatrix(false, m, nullptr);
    transforms_[i]->setChild(mesh_groups_[static_cast<size_t>(shown[i]->mesh)]);
    top_->setChild(static_cast<unsigned>(i), transforms_[i]);
  }
  top_acceleration_->markDirty();
  UpdateLights(frame);
  UpdateEmissiveTriangles(frame);
}

void SceneGraph::UpdateLights(const Frame& frame) {
  std::vector<PunctualLight> lights;
  for (const Light& l : frame.lights) {
    PunctualLight p{};
    const Affine& m = l.to_world;
    p.position = make_float3(m[3], m[7], m[11]);
    // Spot and directional lights shine down their -Z.
    float3 d = make_float3(-m[2], -m[6], -m[10]);
    const float len = std::sqrt(d.x * d.x + d.y * d.y + d.z * d.z);
    if (len > 0.f) d = make_float3(d.x / len, d.y / len, d.z / len);
    p.direction = d;
    p.range = l.range;
    p.intensity =
        make_float3(l.color[0] * l.intensity, l.color[1] * l.intensity, l.color[2] * l.intensity);
    switch (l.type) {
      case Light::Type::kPoint:
        p.type = path_tracer::kPointLight;
        break;
      case Light::Type::kSpot: {
        p.type = path_tracer::kSpotLight;
        // glTF's cone attenuation: 1 inside the inner cone, 0 outside the outer, smooth between.
        const float cos_outer = std::cos(l.outer_cone), cos_inner = std::cos(l.inner_cone);
        p.spot_scale = 1.f / std::max(1e-3f, cos_inner - cos_outer);
        p.spot_offset = -cos_outer * p.spot_scale;
        break;
      }
      case Light::Type::kDirectional:
        p.type = path_tracer::kDirectionalLight;
        break;
    }
    if (p.intensity.x > 0.f || p.intensity.y > 0.f || p.intensity.z > 0.f) lights.push_back(p);
  }
  lights_->setSize(lights.size());
  if (!lights.empty()) {
    std::memcpy(lights_->map(), lights.data(), lights.size() * sizeof(PunctualLight));
    lights_->unmap();
  }
}

void SceneGraph::UpdateEmissiveTriangles(const Frame& frame) {
  std::vector<EmissiveTriangle> triangles;
  std::vector<float> cdf;
  double power = 0.0;
  for (const Instance& instance : frame.instances) {
    if (instance.mesh < 0 || static_cast<size_t>(instance.mesh) >= mesh_groups_.size() ||
        !mesh_groups_[static_cast<size_t>(instance.mesh)] || !Invertible(instance.to_world)) {
      continue;
    }
    const Mesh& mesh = assets_->meshes[static_cast<size_t>(instance.mesh)];
    const Material& material = MaterialOf(mesh);
    const float luminance = Luminance(material.emissive);
    if (!(luminance > 0.f)) continue;
    const bool uvs = mesh.texcoords.size() == mesh.positions.size() / 3 * 2;
    // A mirroring transform turns the winding around, and with it the front face (glTF; and
    // rtTransformNormal, which the closest-hit program takes the front from, agrees).
    const float facing = Determinant(instance.to_world) < 0.0 ? -1.f : 1.f;
    for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
      const uint32_t* v = &mesh.indices[t];
      EmissiveTriangle e{};
      const float3 p0 = Point(instance.to_world, &mesh.positions[3 * v[0]]);
      e.p0 = p0;
      e.e1 = Sub(Point(instance.to_world, &mesh.positions[3 * v[1]]), p0);
      e.e2 = Sub(Point(instance.to_world, &mesh.positions[3 * v[2]]), p0);
      const float3 n = Cross(e.e1, e.e2);
      const float twice_area = std::sqrt(n.x * n.x + n.y * n.y + n.z * n.z);
      if (!(twice_area > 0.f) || !std::isfinite(twice_area)) continue;
      const float scale = facing / twice_area;
      e.normal = make_float3(n.x * scale, n.y * scale, n.z * scale);
      e.emission = make_float3(material.emissive[0], material.emissive[1], material.emissive[2]);
      e.emissive_texture = TextureId(texture_ids_, material.emissive_texture);
      if (uvs) {
        e.uv0 = make_float2(mesh.texcoords[2 * v[0]], mesh.texcoords[2 * v[0] + 1]);
        e.uv1 = make_float2(mesh.texcoords[2 * v[1]], mesh.texcoords[2 * v[1] + 1]);
        e.uv2 = make_float2(mesh.texcoords[2 * v[2]], mesh.texcoords[2 * v[2] + 1]);
      }
      e.double_sided = material.double_sided ? 1 : 0;
      triangles.push_back(e);
      power += 0.5 * twice_area * luminance;
      cdf.push_back(static_cast<float>(power));
    }
  }
  for (float& c : cdf) c = static_cast<float>(c / power);
  if (!cdf.empty()) cdf.back() = 1.f;  // whatever the rounding, u < 1 always finds a triangle
  emissive_count_ = triangles.size();
  emissive_triangles_->setSize(triangles.size());
  emissive_cdf_->setSize(cdf.size());
  if (!triangles.empty()) {
    std::memcpy(emissive_triangles_->map(), triangles.data(),
                triangles.size() * sizeof(EmissiveTriangle));
    emissive_triangles_->unmap();
    std::memcpy(emissive_cdf_->map(), cdf.data(), cdf.size() * sizeof(float));
    emissive_cdf_->unmap();
  }
  context_["emissive_power"]->setFloat(static_cast<float>(power));
}

}  // namespace tessera::render

// Bindless scenes from the host side, built with the OptiX C API as SDK samples and community
// path tracers build them: BSDF callables chosen per material through a buffer of
// RT_FORMAT_PROGRAM_ID (bsdf_callables.cu, bindless_closesthit.cu), and per-mesh buffers of
// face colours reached through a buffer of RT_FORMAT_BUFFER_ID (buffers_of_buffers.cu on the
// SDK's triangle_mesh.cu). Each renders on inproc, local:1 and local:3, once as built and once
// after the host rewrites the buffer of ids, and each pixel the host can place is checked.
#include <optix.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <utility>
#include <vector>

#include "material_parameter.h"
#include "port_corpus_fixture.h"

namespace tessera::testing {
namespace {

using optix::float3;
using optix::make_float3;

constexpr unsigned kWidth = 64, kHeight = 48;
using Image = std::vector<std::uint32_t>;

// Within `tolerance` in each channel (a host normal may round a byte the other way).
bool Near(std::uint32_t a, std::uint32_t b, int tolerance) {
  for (int c = 0; c < 3; ++c) {
    if (std::abs(Channel(a, c) - Channel(b, c)) > tolerance) return false;
  }
  return true;
}

// ---- Bindless BSDF callables ----------------------------------------------------------------

const PinholeCamera kCallableCamera = {make_float3(0.f, 0.f, -6.f), make_float3(0.7f, 0.f, 0.f),
                                       make_float3(0.f, 0.525f, 0.f), make_float3(0.f, 0.f, 1.f)};
const float3 kLightDirection = make_float3(-1.f, 1.f, -1.f);
const float3 kLightColor = make_float3(2.f, 2.f, 2.f);
constexpr float kSpacing = 2.2f;  // sphere k's centre is at x = (k - 1) * kSpacing
const MaterialParameter kMaterials[3] = {
    {make_float3(0.1f, 0.2f, 0.4f), INDEX_BSDF_EMISSIVE},
    {make_float3(0.9f, 0.6f, 0.3f), INDEX_BSDF_DIFFUSE_REFLECTION},
    {make_float3(0.3f, 0.5f, 0.7f), INDEX_BSDF_NORMAL_DEBUG}};

// What bsdf `function` gives for the light at a point of normal `n`, as bsdf_callables.cu and
// bindless_closesthit.cu compute it.
float3 Shade(int function, const MaterialParameter& m, const float3& n) {
  const float3 wi = optix::normalize(kLightDirection);
  switch (function) {
    case INDEX_BSDF_EMISSIVE:
      return m.albedo * kLightColor;
    case INDEX_BSDF_DIFFUSE_REFLECTION: {
      const float cos_theta = optix::dot(n, wi);
      return cos_theta <= 0.f ? make_float3(0.f) : m.albedo * (M_1_PIf * cos_theta) * kLightColor;
    }
    default:
      return (n * 0.5f + 0.5f) * kLightColor;
  }
}

class BindlessCallablesTest : public PortCorpusTest {
 protected:
  // Three spheres in a row, one closest-hit program, each instance's parMaterialIndex 0, 1 or 2.
  // Renders with the callables in the order of `order` (BSDF index -> callable), then again after
  // rewriting the buffer of program ids in the order of `reorder`.
  std::pair<Image, Image> Render(const char* spec, const std::array<int, 3>& order,
                                 const std::array<int, 3>& reorder) {
    UseDevices(spec, 1);
    Ok(rtContextSetRayGenerationProgram(ctx_, 0, Program("pinhole_camera", "pinhole_camera")));
    Ok(rtContextSetMissProgram(ctx_, 0, Program("buffers_of_buffers", "miss_black")));
    RTmaterial material = nullptr;
    Ok(rtMaterialCreate(ctx_, &material));
    Ok(rtMaterialSetClosestHitProgram(material, 0, Program("bindless_closesthit", "closesthit")));
    std::vector<RTgeometryinstance> instances;
    for (int k = 0; k < 3; ++k) {
      RTgeometry g = NewGeometry(Program("sphere_texcoord", "intersect"),
                                 Program("sphere_texcoord", "bounds"), 1);
      Ok(rtVariableSet4f(GeometryVar(g, "sphere"), (k - 1) * kSpacing, 0.f, 0.f, 1.f));
      instances.push_back(NewInstance(g, material));
      Ok(rtVariableSet1i(InstanceVar(instances.back(), "parMaterialIndex"), k));
    }
    Ok(rtVariableSetObject(ContextVar("top_object"), NewGroup(instances)));
    Fill(Buffer1D("sysMaterialParameters", RT_BUFFER_INPUT, RT_FORMAT_USER, 3,
                  sizeof(MaterialParameter)),
         std::vector<MaterialParameter>(kMaterials, kMaterials + 3));

    // The callables' ids, as a renderer collects them after loading its BSDF programs.
    const char* names[NUMBER_OF_BSDF_INDICES] = {
        "eval_bsdf_emissive", "eval_bsdf_diffuse_reflection", "eval_bsdf_normal_debug"};
    int ids[NUMBER_OF_BSDF_INDICES] = {};
    for (int k = 0; k < NUMBER_OF_BSDF_INDICES; ++k) {
      Ok(rtProgramGetId(Program("bsdf_callables", names[k]), &ids[k]));
    }
    RTbuffer eval_bsdf =
        Buffer1D("sysEvalBSDF", RT_BUFFER_INPUT, RT_FORMAT_PROGRAM_ID, NUMBER_OF_BSDF_INDICES);
    Fill(eval_bsdf, std::vector<int>{ids[order[0]], ids[order[1]], ids[order[2]]});

    SetFloat3(ContextVar("sysLightDirection"), kLightDirection);
    SetFloat3(ContextVar("sysLightColor"), kLightColor);
    SetCamera(kCallableCamera);
    Ok(rtVariableSet1f(ContextVar("scene_epsilon"), 1e-3f));
    Ok(rtVariableSet1ui(ContextVar("radiance_ray_type"), 0));
    RTbuffer out =
        Buffer2D("output_buffer", RT_BUFFER_OUTPUT, RT_FORMAT_UNSIGNED_BYTE4, kWidth, kHeight);
    Ok(rtContextLaunch2D(ctx_, 0, kWidth, kHeight));
    Image first = ReadAs<std::uint32_t>(out);
    Fill(eval_bsdf, std::vector<int>{ids[reorder[0]], ids[reorder[1]], ids[reorder[2]]});
    Ok(rtContextLaunch2D(ctx_, 0, kWidth, kHeight));
    return {first, ReadAs<std::uint32_t>(out)};
  }

  // Every pixel well inside sphere k shows material k shaded by callable order[indexBSDF]: the
  // emitter to the bit, the others within a byte. Returns how many pixels were checked.
  int ExpectShading(const Image& image, const std::array<int, 3>& order) {
    int checked = 0;
    for (unsigned y = 0; y < kHeight; ++y) {
      for (unsigned x = 0; x < kWidth; ++x) {
        const float3 dir = kCallableCamera.Direction(x, y, kWidth, kHeight);
        const std::uint32_t pixel = image[y * kWidth + x];
        bool near_any = false;
        for (int k = 0; k < 3; ++k) {
          const float3 c = make_float3((k - 1) * kSpacing, 0.f, 0.f);
          near_any = near_any || HitSphere(kCallableCamera.eye, dir, c, 1.05f) > 0.f;
          if (HitSphere(kCallableCamera.eye, dir, c, 0.95f) < 0.f) continue;
          const float t = HitSphere(kCallableCamera.eye, dir, c, 1.f);
          const float3 n = optix::normalize(kCallableCamera.eye + t * dir - c);
          const int function = order[kMaterials[k].indexBSDF];
          const std::uint32_t expected = Bgra8(Shade(function, kMaterials[k], n));
          if (function == INDEX_BSDF_EMISSIVE) {
            EXPECT_EQ(pixel, expected) << "sphere " << k << " at (" << x << ", " << y << ")";
          } else {
            EXPECT_TRUE(Near(pixel, expected, 1))
                << "sphere " << k << " at (" << x << ", " << y << "): " << std::hex << pixel
                << " for " << expected;
          }
          ++checked;
        }
        if (!near_any) {
          EXPECT_EQ(pixel, 0xFF000000u) << "background at (" << x << ", " << y << ")";
        }
      }
    }
    return checked;
  }
};

TEST_F(BindlessCallablesTest, EachMaterialGetsTheCallableItsIndexPicks) {
  const std::array<int, 3> as_built = {0, 1, 2}, rotated = {2, 0, 1};
  const std::pair<Image, Image> images =
      OnEveryDeviceSet([&](const char* spec) { return Render(spec, as_built, rotated); });
  ASSERT_EQ(images.first.size(), size_t{kWidth} * kHeight);
  EXPECT_GE(ExpectShading(images.first, as_built), 3 * 40);
  EXPECT_GE(ExpectShading(images.second, rotated), 3 * 40);
  EXPECT_NE(images.first, images.second);
}

// ---- Buffers of buffer ids ----------------------------------------------------------------

const PinholeCamera kMeshCamera = {make_float3(0.f, 0.f, -4.f), make_float3(0.6f, 0.f, 0.f),
                                   make_float3(0.f, 0.45f, 0.f), make_float3(0.f, 0.f, 1.f)};
// Mesh 0: a quad of two triangles at x in [-2.2, -0.2]; mesh 1: a quad of four triangles around
// its centre at x in [0.2, 2.2]; both y in [-1, 1], z = 0, facing the camera.
const std::vector<std::vector<float3>> kFaceColors = {
    {make_float3(1.f, 0.f, 0.f), make_float3(0.f, 1.f, 0.f)},
    {make_float3(0.f, 0.f, 1.f), make_float3(1.f, 1.f, 0.f), make_float3(0.f, 1.f, 1.f),
     make_float3(1.f, 0.f, 1.f)}};

// The mesh and face the camera ray of pixel (x, y) hits well inside of, or {-1, -1}; {-2, -2}
// well outside of both meshes.
std::pair<int, int> FaceAt(unsigned x, unsigned y) {
  const float3 dir = kMeshCamera.Direction(x, y, kWidth, kHeight);
  const float3 p = kMeshCamera.eye + (-kMeshCamera.eye.z / dir.z) * dir;
  constexpr float m = 0.02f;
  if (p.y < -1.f - m || p.y > 1.f + m || p.x < -2.2f - m || p.x > 2.2f + m ||
      (p.x > -0.2f + m && p.x < 0.2f - m)) {
    return {-2, -2};
  }
  if (p.y < -1.f + m || p.y > 1.f - m) return {-1, -1};
  if (p.x > -2.2f + m && p.x < -0.2f - m) {
    // Triangles (0, 1, 2) below the diagonal y = x + 1.2 and (0, 2, 3) above it.
    const float above = p.y - (p.x + 1.2f);
    if (std::fabs(above) < m) return {-1, -1};
    return {0, above < 0.f ? 0 : 1};
  }
  if (p.x > 0.2f + m && p.x < 2.2f - m) {
    // The fan around (1.2, 0): bottom, right, top, left.
    const float dx = p.x - 1.2f, dy = p.y;
    if (std::fabs(std::fabs(dx) - std::fabs(dy)) < m) return {-1, -1};
    if (std::fabs(dy) > std::fabs(dx)) return {1, dy < 0.f ? 0 : 2};
    return {1, dx > 0.f ? 1 : 3};
  }
  return {-1, -1};
}

class BuffersOfBuffersTest : public PortCorpusTest {
 protected:
  // One mesh as the SDK's OptiXMesh loader leaves it: vertex, index and material buffers, and
  // zero-sized normal and texcoord buffers for a mesh that has none.
  RTgeometry Mesh(const std::vector<float3>& vertices, const std::vector<int>& indices) {
    const unsigned faces = static_cast<unsigned>(indices.size() / 3);
    RTgeometry g = NewGeometry(Program("triangle_mesh", "mesh_intersect"),
                               Program("triangle_mesh", "mesh_bounds"), faces);
    RTbuffer v = Unbound1D(RT_BUFFER_INPUT, RT_FORMAT_FLOAT3, vertices.size());
    Fill(v, vertices);
    RTbuffer i = Unbound1D(RT_BUFFER_INPUT, RT_FORMAT_INT3, faces);
    Fill(i, indices);
    RTbuffer m = Unbound1D(RT_BUFFER_INPUT, RT_FORMAT_INT, faces);
    Fill(m, std::vector<int>(faces, 0));
    Ok(rtVariableSetObject(GeometryVar(g, "vertex_buffer"), v));
    Ok(rtVariableSetObject(GeometryVar(g, "index_buffer"), i));
    Ok(rtVariableSetObject(GeometryVar(g, "material_buffer"), m));
    Ok(rtVariableSetObject(GeometryVar(g, "normal_buffer"),
                           Unbound1D(RT_BUFFER_INPUT, RT_FORMAT_FLOAT3, 0)));
    Ok(rtVariableSetObject(GeometryVar(g, "texcoord_buffer"),
                           Unbound1D(RT_BUFFER_INPUT, RT_FORMAT_FLOAT2, 0)));
    return g;
  }

  // Renders with face_colors = {mesh 0's colours, mesh 1's}, then with the two ids swapped.
  std::pair<Image, Image> Render(const char* spec) {
    UseDevices(spec, 1);
    Ok(rtContextSetRayGenerationProgram(ctx_, 0, Program("pinhole_camera", "pinhole_camera")));
    Ok(rtContextSetMissProgram(ctx_, 0, Program("buffers_of_buffers", "miss_black")));
    RTmaterial material = nullptr;
    Ok(rtMaterialCreate(ctx_, &material));
    Ok(rtMaterialSetClosestHitProgram(material, 0,
                                      Program("buffers_of_buffers", "closest_hit_face_color")));
    const float3 quad0[4] = {make_float3(-2.2f, -1.f, 0.f), make_float3(-0.2f, -1.f, 0.f),
                             make_float3(-0.2f, 1.f, 0.f), make_float3(-2.2f, 1.f, 0.f)};
    RTgeometry mesh0 =
        Mesh(std::vector<float3>(quad0, quad0 + 4), std::vector<int>{0, 1, 2, 0, 2, 3});
    std::vector<float3> fan;
    for (const float3& v : quad0) fan.push_back(v + make_float3(2.4f, 0.f, 0.f));
    fan.push_back(make_float3(1.2f, 0.f, 0.f));
    RTgeometry mesh1 = Mesh(fan, std::vector<int>{4, 0, 1, 4, 1, 2, 4, 2, 3, 4, 3, 0});
    std::vector<RTgeometryinstance> instances = {NewInstance(mesh0, material),
                                                 NewInstance(mesh1, material)};
    int ids[2] = {};
    for (int k = 0; k < 2; ++k) {
      Ok(rtVariableSet1i(InstanceVar(instances[k], "mesh_id"), k));
      RTbuffer colors = Unbound1D(RT_BUFFER_INPUT, RT_FORMAT_FLOAT3, kFaceColors[k].size());
      Fill(colors, kFaceColors[k]);
      Ok(rtBufferGetId(colors, &ids[k]));
    }
    Ok(rtVariableSetObject(ContextVar("top_object"), NewGroup(instances)));
    RTbuffer face_colors = Buffer1D("face_colors", RT_BUFFER_INPUT, RT_FORMAT_BUFFER_ID, 2);
    Fill(face_colors, std::vector<int>{ids[0], ids[1]});

    SetCamera(kMeshCamera);
    Ok(rtVariableSet1f(ContextVar("scene_epsilon"), 1e-3f));
    Ok(rtVariableSet1ui(ContextVar("radiance_ray_type"), 0));
    RTbuffer out =
        Buffer2D("output_buffer", RT_BUFFER_OUTPUT, RT_FORMAT_UNSIGNED_BYTE4, kWidth, kHeight);
    Ok(rtContextLaunch2D(ctx_, 0, kWidth, kHeight));
    Image first = ReadAs<std::uint32_t>(out);
    Fill(face_colors, std::vector<int>{ids[1], ids[0]});
    Ok(rtContextLaunch2D(ctx_, 0, kWidth, kHeight));
    return {first, ReadAs<std::uint32_t>(out)};
  }

  // Every pixel well inside face f of mesh k shows colour f (modulo the buffer's size) of the
  // buffer the id at face_colors[k] names; pixels off both meshes are the miss program's black.
  // Returns the faces seen.
  int ExpectFaces(const Image& image, bool swapped) {
    std::vector<std::vector<int>> seen(2, std::vector<int>(4, 0));
    for (unsigned y = 0; y < kHeight; ++y) {
      for (unsigned x = 0; x < kWidth; ++x) {
        const std::uint32_t pixel = image[y * kWidth + x];
        const auto [mesh, face] = FaceAt(x, y);
        if (mesh == -2) {
          EXPECT_EQ(pixel, 0xFF000000u) << "background at (" << x << ", " << y << ")";
        } else if (mesh >= 0) {
          const std::vector<float3>& colors = kFaceColors[swapped ? 1 - mesh : mesh];
          EXPECT_EQ(pixel, Bgra8(colors[face % colors.size()]))
              << "mesh " << mesh << " face " << face << " at (" << x << ", " << y << ")";
          ++seen[mesh][face];
        }
      }
    }
    int faces = 0;
    for (int f = 0; f < 2; ++f) faces += seen[0][f] >= 10;
    for (int f = 0; f < 4; ++f) faces += seen[1][f] >= 10;
    return faces;
  }
};

TEST_F(BuffersOfBuffersTest, EachMeshReadsItsOwnBufferThroughTheBufferOfIds) {
  const std::pair<Image, Image> images =
      OnEveryDeviceSet([&](const char* spec) { return Render(spec); });
  ASSERT_EQ(images.first.size(), size_t{kWidth} * kHeight);
  EXPECT_EQ(ExpectFaces(images.first, false), 6) << "faces with at least 10 pixels checked";
  EXPECT_EQ(ExpectFaces(images.second, true), 6) << "faces with at least 10 pixels checked";
}

}  // namespace
}  // namespace tessera::testing

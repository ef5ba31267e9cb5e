#include "extremes_scene.h"

#include <cstring>

#include "tessera/rt_ext.h"

namespace tessera::testing {
namespace {
constexpr char kModule[] = "extremes_programs";
}  // namespace

void ExtremesScene::Build(const meshgen::Mesh& mesh, MeshKind kind, const Placement& placement,
                          uint32_t flags, bool any_hit, const char* builder,
                          const std::vector<std::pair<std::string, std::string>>& properties,
                          const char* devices) {
  if (ctx_ != nullptr) rtContextDestroy(ctx_);
  ASSERT_EQ(rtContextCreate(&ctx_), RT_SUCCESS);
  Ok(tesseraContextSetDeviceSpec(ctx_, devices));
  Ok(tesseraContextSetAccuracy(ctx_, flags));
  Ok(rtContextSetEntryPointCount(ctx_, 1));
  Ok(rtContextSetRayTypeCount(ctx_, 2));
  Ok(rtContextSetRayGenerationProgram(ctx_, 0, Program(kModule, "shoot")));

  stored_ = placement.by_transform ? meshgen::Placed(mesh, 1.0, {0, 0, 0})
                                   : meshgen::Placed(mesh, placement.scale, placement.offset);
  const auto nverts = static_cast<unsigned>(mesh.vertices.size());
  const auto ntris = static_cast<unsigned>(mesh.triangles.size());
  RTbuffer vb = nullptr, ib = nullptr;
  Ok(rtBufferCreate(ctx_, RT_BUFFER_INPUT, &vb));
  Ok(rtBufferSetFormat(vb, RT_FORMAT_FLOAT3));
  Ok(rtBufferSetSize1D(vb, nverts));
  void* p = nullptr;
  Ok(rtBufferMap(vb, &p));
  std::memcpy(p, stored_.data(), stored_.size() * sizeof(float));
  Ok(rtBufferUnmap(vb));
  vertex_buffer_ = vb;
  Ok(rtBufferCreate(ctx_, RT_BUFFER_INPUT, &ib));
  Ok(rtBufferSetFormat(
      ib, kind == MeshKind::kGeometryTriangles ? RT_FORMAT_UNSIGNED_INT3 : RT_FORMAT_INT3));
  Ok(rtBufferSetSize1D(ib, ntris));
  Ok(rtBufferMap(ib, &p));
  std::memcpy(p, mesh.triangles.data(), mesh.triangles.size() * 12);
  Ok(rtBufferUnmap(ib));

  RTmaterial material = nullptr;
  Ok(rtMaterialCreate(ctx_, &material));
  Ok(rtMaterialSetClosestHitProgram(material, 0, Program(kModule, "closest_hit")));
  Ok(rtMaterialSetClosestHitProgram(material, 1, Program(kModule, "shadow_closest_hit")));
  if (any_hit) Ok(rtMaterialSetAnyHitProgram(material, 0, Program(kModule, "counting_any_hit")));
  RTgeometryinstance instance = nullptr;
  Ok(rtGeometryInstanceCreate(ctx_, &instance));
  if (kind == MeshKind::kGeometryTriangles) {
    RTgeometrytriangles triangles = nullptr;
    Ok(rtGeometryTrianglesCreate(ctx_, &triangles));
    Ok(rtGeometryTrianglesSetPrimitiveCount(triangles, ntris));
    Ok(rtGeometryTrianglesSetVertices(triangles, nverts, vb, 0, 12, RT_FORMAT_FLOAT3));
    Ok(rtGeometryTrianglesSetTriangleIndices(triangles, ib, 0, 12, RT_FORMAT_UNSIGNED_INT3));
    Ok(rtGeometryInstanceSetGeometryTriangles(instance, triangles));
  } else {
    RTgeometry geometry = nullptr;
    Ok(rtGeometryCreate(ctx_, &geometry));
    Ok(rtGeometrySetPrimitiveCount(geometry, ntris));
    Ok(rtGeometrySetIntersectionProgram(geometry, Program(kModule, "mesh_intersect")));
    Ok(rtGeometrySetBoundingBoxProgram(geometry, Program(kModule, "mesh_bounds")));
    RTvariable v = nullptr;
    Ok(rtGeometryDeclareVariable(geometry, "vertex_buffer", &v));
    Ok(rtVariableSetObject(v, vb));
    Ok(rtGeometryDeclareVariable(geometry, "index_buffer", &v));
    Ok(rtVariableSetObject(v, ib));
    Ok(rtGeometryInstanceSetGeometry(instance, geometry));
  }
  Ok(rtGeometryInstanceSetMaterialCount(instance, 1));
  Ok(rtGeometryInstanceSetMaterial(instance, 0, material));
  RTacceleration accel = Accel(builder);
  if (kind == MeshKind::kApplicationMesh) {
    Ok(rtAccelerationSetProperty(accel, "vertex_buffer_name", "vertex_buffer"));
    Ok(rtAccelerationSetProperty(accel, "index_buffer_name", "index_buffer"));
  }
  for (const auto& [name, value] : properties) {
    Ok(rtAccelerationSetProperty(accel, name.c_str(), value.c_str()));
  }
  RTgeometrygroup group = nullptr;
  Ok(rtGeometryGroupCreate(ctx_, &group));
  Ok(rtGeometryGroupSetAcceleration(group, accel));
  Ok(rtGeometryGroupSetChildCount(group, 1));
  Ok(rtGeometryGroupSetChild(group, 0, instance));
  RTobject top = group;
  if (placement.by_transform) {
    RTtransform transform = nullptr;
    Ok(rtTransformCreate(ctx_, &transform));
    const float s = static_cast<float>(placement.scale);
    const float m[16] = {s, 0, 0, static_cast<float>(placement.offset[0]),
                         0, s, 0, static_cast<float>(placement.offset[1]),
                         0, 0, s, static_cast<float>(placement.offset[2]),
                         0, 0, 0, 1};
    Ok(rtTransformSetMatrix(transform, 0, m, nullptr));
    Ok(rtTransformSetChild(transform, group));
    top = transform;
  }
  Ok(rtVariableSetObject(ContextVar("top_object"), top));
}

std::vector<RayResult> ExtremesScene::Trace(const std::vector<Ray>& rays, unsigned spawn,
                                            float epsilon) {
  const size_t n = rays.size();
  auto buffer = [&](const char* name, unsigned type, RTformat format) {
    RTbuffer b = nullptr;
    EXPECT_EQ(rtBufferCreate(ctx_, type, &b), RT_SUCCESS);
    EXPECT_EQ(rtBufferSetFormat(b, format), RT_SUCCESS);
    EXPECT_EQ(
        rtBufferSetSize1D(b, format == RT_FORMAT_FLOAT4 && std::string(name) == "rays" ? 2 * n : n),
        RT_SUCCESS);
    EXPECT_EQ(rtVariableSetObject(ContextVar(name), b), RT_SUCCESS);
    return b;
  };
  RTbuffer in = buffer("rays", RT_BUFFER_INPUT, RT_FORMAT_FLOAT4);
  RTbuffer dirs = buffer("secondary_dirs", RT_BUFFER_INPUT, RT_FORMAT_FLOAT4);
  RTbuffer out = buffer("results", RT_BUFFER_OUTPUT, RT_FORMAT_UNSIGNED_INT4);
  float* r = nullptr;
  EXPECT_EQ(rtBufferMap(in, reinterpret_cast<void**>(&r)), RT_SUCCESS);
  float* d = nullptr;
  EXPECT_EQ(rtBufferMap(dirs, reinterpret_cast<void**>(&d)), RT_SUCCESS);
  for (size_t i = 0; i < n; ++i) {
    const Ray& ray = rays[i];
    const float words[12] = {ray.origin[0],    ray.origin[1],    ray.origin[2],    ray.tmin,
                             ray.direction[0], ray.direction[1], ray.direction[2], ray.tmax,
                             ray.secondary[0], ray.secondary[1], ray.secondary[2], 0.f};
    std::memcpy(r + 8 * i, words, 32);
    std::memcpy(d + 4 * i, words + 8, 16);
  }
  rtBufferUnmap(in);
  rtBufferUnmap(dirs);
  RTvariable v = ContextVar("spawn_mode");
  EXPECT_EQ(rtVariableSet1ui(v, spawn), RT_SUCCESS);
  EXPECT_EQ(rtVariableSet1f(ContextVar("scene_epsilon"), epsilon), RT_SUCCESS);
  const RTresult launched = rtContextLaunch1D(ctx_, 0, n);
  EXPECT_EQ(launched, RT_SUCCESS) << Error(launched);
  std::vector<RayResult> results(n);
  const uint32_t* words = nullptr;
  EXPECT_EQ(rtBufferMap(out, reinterpret_cast<void**>(const_cast<uint32_t**>(&words))), RT_SUCCESS);
  for (size_t i = 0; i < n && words != nullptr; ++i) {
    const uint32_t* w = words + 4 * i;
    RayResult& res = results[i];
    res.hit = w[0] != 0xFFFFFFFFu;
    std::memcpy(&res.t, w, 4);
    res.primitive = w[1];
    res.candidates = w[2];
    res.secondary_hit = w[3] != 0;
  }
  rtBufferUnmap(out);
  rtBufferDestroy(in);
  rtBufferDestroy(dirs);
  rtBufferDestroy(out);
  return results;
}

}  // namespace tessera::testing

#include "scene.h"

#include <cmath>
#include <cstring>
#include <stdexcept>

#include "tessera/rt_ext.h"

namespace tessera::bench {
void EyelightScene::Check(RTresult result, const char* call) {
  if (result == RT_SUCCESS) return;
  const char* message = nullptr;
  rtContextGetErrorString(context_, result, &message);
  throw std::runtime_error(std::string(call) + " failed: " + (message ? message : "?"));
}

RTprogram EyelightScene::Program(const char* function) {
  RTprogram program = nullptr;
  Check(rtProgramCreateFromPTXFile(context_, module_path_.c_str(), function, &program),
        "rtProgramCreateFromPTXFile");
  return program;
}

template <typename Declare>
std::pair<RTbuffer, RTbuffer> EyelightScene::MeshBuffers(const Mesh& mesh, Declare&& declare) {
  struct Upload {
    const char* name;
    RTformat format;
    const void* data;
    size_t count;
  };
  const Upload uploads[] = {
      {"vertex_buffer", RT_FORMAT_FLOAT3, mesh.positions.data(), mesh.VertexCount()},
      {"index_buffer", RT_FORMAT_INT3, mesh.indices.data(), mesh.TriangleCount()}};
  RTbuffer made[2] = {nullptr, nullptr};
  for (int i = 0; i < 2; ++i) {
    const Upload& up = uploads[i];
    RTbuffer buffer;
    Check(rtBufferCreate(context_, RT_BUFFER_INPUT, &buffer), "rtBufferCreate");
    Check(rtBufferSetFormat(buffer, up.format), "rtBufferSetFormat");
    Check(rtBufferSetSize1D(buffer, up.count), "rtBufferSetSize1D");
    void* dst = nullptr;
    Check(rtBufferMap(buffer, &dst), "rtBufferMap");
    std::memcpy(dst, up.data, up.count * 12);
    Check(rtBufferUnmap(buffer), "rtBufferUnmap");
    RTvariable v;
    Check(declare(up.name, &v), "rt*DeclareVariable");
    Check(rtVariableSetObject(v, buffer), "rtVariableSetObject");
    made[i] = buffer;
  }
  return {made[0], made[1]};
}

EyelightScene::EyelightScene(const Mesh& mesh, const Camera& camera, unsigned width,
                             unsigned height, const std::string& module_path,
                             const std::string& devices, int threads, bool builtin_triangles)
    : width_(width), height_(height), module_path_(module_path) {
  if (RTresult r = rtContextCreate(&context_); r != RT_SUCCESS) {
    context_ = nullptr;
    Check(r, "rtContextCreate");
  }
  if (threads > 0) {
    Check(rtContextSetAttribute(context_, RT_CONTEXT_ATTRIBUTE_CPU_NUM_THREADS, sizeof(threads),
                                &threads),
          "rtContextSetAttribute(CPU_NUM_THREADS)");
  }
  Check(tesseraContextSetDeviceSpec(context_, devices.c_str()), "tesseraContextSetDeviceSpec");
  Check(rtContextSetRayTypeCount(context_, 1), "rtContextSetRayTypeCount");
  Check(rtContextSetEntryPointCount(context_, 1), "rtContextSetEntryPointCount");
  Check(rtContextSetRayGenerationProgram(context_, 0, Program("pinhole_camera")),
        "rtContextSetRayGenerationProgram");
  Check(rtContextSetMissProgram(context_, 0, Program("miss")), "rtContextSetMissProgram");

  RTvariable v;
  const Pinhole pin = MakePinhole(camera, width, height);
  const std::pair<const char*, const float*> basis[] = {
      {"eye", pin.eye}, {"U", pin.u}, {"V", pin.v}, {"W", pin.w}};
  for (const auto& [name, value] : basis) {
    Check(rtContextDeclareVariable(context_, name, &v), "rtContextDeclareVariable");
    Check(rtVariableSet3fv(v, value), "rtVariableSet3fv");
  }

  Check(rtBufferCreate(context_, RT_BUFFER_OUTPUT, &output_), "rtBufferCreate");
  Check(rtBufferSetFormat(output_, RT_FORMAT_UNSIGNED_BYTE4), "rtBufferSetFormat");
  Check(rtBufferSetSize2D(output_, width, height), "rtBufferSetSize2D");
  Check(rtContextDeclareVariable(context_, "output_buffer", &v), "rtContextDeclareVariable");
  Check(rtVariableSetObject(v, output_), "rtVariableSetObject");

  const auto triangle_count = static_cast<unsigned>(mesh.TriangleCount());
  RTgeometry geometry = nullptr;
  RTgeometrytriangles triangles = nullptr;
  if (builtin_triangles) {
    Check(rtGeometryTrianglesCreate(context_, &triangles), "rtGeometryTrianglesCreate");
    Check(rtGeometryTrianglesSetPrimitiveCount(triangles, triangle_count),
          "rtGeometryTrianglesSetPrimitiveCount");
    auto [vertices, indices] = MeshBuffers(mesh, [&](const char* name, RTvariable* var) {
      return rtGeometryTrianglesDeclareVariable(triangles, name, var);
    });
    Check(rtGeometryTrianglesSetVertices(triangles, static_cast<unsigned>(mesh.VertexCount()),
                                         vertices, 0, 12, RT_FORMAT_FLOAT3),
          "rtGeometryTrianglesSetVertices");
    Check(rtGeometryTrianglesSetTriangleIndices(triangles, indices, 0, 12, RT_FORMAT_UNSIGNED_INT3),
          "rtGeometryTrianglesSetTriangleIndices");
    Check(rtGeometryTrianglesSetAttributeProgram(triangles, Program("mesh_attributes")),
          "rtGeometryTrianglesSetAttributeProgram");
  } else {
    // The mesh buffers are geometry variables, where the acceleration finds them.
    Check(rtGeometryCreate(context_, &geometry), "rtGeometryCreate");
    Check(rtGeometrySetPrimitiveCount(geometry, triangle_count), "rtGeometrySetPrimitiveCount");
    Check(rtGeometrySetIntersectionProgram(geometry, Program("mesh_intersect")),
          "rtGeometrySetIntersectionProgram");
    Check(rtGeometrySetBoundingBoxProgram(geometry, Program("mesh_bounds")),
          "rtGeometrySetBoundingBoxProgram");
    MeshBuffers(mesh, [&](const char* name, RTvariable* var) {
      return rtGeometryDeclareVariable(geometry, name, var);
    });
  }

  RTmaterial material;
  Check(rtMaterialCreate(context_, &material), "rtMaterialCreate");
  Check(rtMaterialSetClosestHitProgram(material, 0, Program("eyelight")),
        "rtMaterialSetClosestHitProgram");

  RTgeometryinstance instance;
  Check(rtGeometryInstanceCreate(context_, &instance), "rtGeometryInstanceCreate");
  if (builtin_triangles) {
    Check(rtGeometryInstanceSetGeometryTriangles(instance, triangles),
          "rtGeometryInstanceSetGeometryTriangles");
  } else {
    Check(rtGeometryInstanceSetGeometry(instance, geometry), "rtGeometryInstanceSetGeometry");
  }
  Check(rtGeometryInstanceSetMaterialCount(instance, 1), "rtGeometryInstanceSetMaterialCount");
  Check(rtGeometryInstanceSetMaterial(instance, 0, material), "rtGeometryInstanceSetMaterial");

  RTacceleration accel;
  Check(rtAccelerationCreate(context_, &accel), "rtAccelerationCreate");
  Check(rtAccelerationSetBuilder(accel, "Trbvh"), "rtAccelerationSetBuilder");
  Check(rtAccelerationSetTraverser(accel, "Bvh"), "rtAccelerationSetTraverser");
  if (!builtin_triangles) {
    Check(rtAccelerationSetProperty(accel, "vertex_buffer_name", "vertex_buffer"),
          "rtAccelerationSetProperty");
    Check(rtAccelerationSetProperty(accel, "index_buffer_name", "index_buffer"),
          "rtAccelerationSetProperty");
  }

  RTgeometrygroup group;
  Check(rtGeometryGroupCreate(context_, &group), "rtGeometryGroupCreate");
  Check(rtGeometryGroupSetAcceleration(group, accel), "rtGeometryGroupSetAcceleration");
  Check(rtGeometryGroupSetChildCount(group, 1), "rtGeometryGroupSetChildCount");
  Check(rtGeometryGroupSetChild(group, 0, instance), "rtGeometryGroupSetChild");
  Check(rtContextDeclareVariable(context_, "top_object", &v), "rtContextDeclareVariable");
  Check(rtVariableSetObject(v, group), "rtVariableSetObject");

  Check(rtContextValidate(context_), "rtContextValidate");
  Check(rtContextCompile(context_), "rtContextCompile");
}

EyelightScene::~EyelightScene() {
  if (context_ != nullptr) rtContextDestroy(context_);
}

void EyelightScene::Launch() {
  Check(rtContextLaunch2D(context_, 0, width_, height_), "rtContextLaunch2D");
}

Image EyelightScene::ReadImage() {
  Image image;
  image.width = width_;
  image.height = height_;
  image.rgba.resize(size_t{width_} * height_ * 4);
  void* data = nullptr;
  Check(rtBufferMap(output_, &data), "rtBufferMap");
  const size_t row = size_t{width_} * 4;
  for (unsigned y = 0; y < height_; ++y) {
    // The launch's row 0 is the bottom of the picture (OptiX convention).
    std::memcpy(image.rgba.data() + y * row,
                static_cast<const uint8_t*>(data) + (height_ - 1 - y) * row, row);
  }
  Check(rtBufferUnmap(output_), "rtBufferUnmap");
  return image;
}

int EyelightScene::ThreadCount() {
  int threads = 0;
  if (rtContextGetAttribute(context_, RT_CONTEXT_ATTRIBUTE_CPU_NUM_THREADS, sizeof(threads),
                            &threads) != RT_SUCCESS) {
    return 0;
  }
  return threads;
}

}  // namespace tessera::bench

#include "e2e_scene.h"

#include <cstring>

namespace tessera::e2e {
namespace {

#define E2E_TRY(call)                           \
  do {                                          \
    RTresult r_ = (call);                       \
    if (r_ != RT_SUCCESS) {                     \
      *error = #call ": " + ErrorText(ctx, r_); \
      return r_;                                \
    }                                           \
  } while (0)

RTresult Float4Buffer2D(RTcontext ctx, const char* name, unsigned type, unsigned w, unsigned h,
                        RTbuffer* buffer, std::string* error) {
  E2E_TRY(rtBufferCreate(ctx, type, buffer));
  E2E_TRY(rtBufferSetFormat(*buffer, RT_FORMAT_FLOAT4));
  E2E_TRY(rtBufferSetSize2D(*buffer, w, h));
  RTvariable v = nullptr;
  E2E_TRY(rtContextDeclareVariable(ctx, name, &v));
  E2E_TRY(rtVariableSetObject(v, *buffer));
  return RT_SUCCESS;
}

RTresult Fill(RTbuffer buffer, const float* values, size_t count) {
  void* p = nullptr;
  RTresult r = rtBufferMap(buffer, &p);
  if (r != RT_SUCCESS) return r;
  std::memcpy(p, values, count * sizeof(float));
  return rtBufferUnmap(buffer);
}

}  // namespace

std::string ErrorText(RTcontext ctx, RTresult code) {
  const char* s = nullptr;
  rtContextGetErrorString(ctx, code, &s);
  return s != nullptr ? s : "";
}

std::string ReadBytes(RTbuffer buffer) {
  RTsize element = 0, w = 0, h = 0;
  rtBufferGetElementSize(buffer, &element);
  rtBufferGetSize2D(buffer, &w, &h);
  std::string bytes(element * w * h, '\0');
  void* p = nullptr;
  if (rtBufferMap(buffer, &p) != RT_SUCCESS) return "";
  std::memcpy(bytes.data(), p, bytes.size());
  rtBufferUnmap(buffer);
  return bytes;
}

const char* ModulePath() { return TESSERA_E2E_MODULE; }

RTresult BuildScene(RTcontext ctx, unsigned width, unsigned height, Scene* scene,
                    std::string* error) {
  scene->ctx = ctx;
  scene->width = width;
  scene->height = height;
  const std::string module = TESSERA_E2E_MODULE;
  auto program = [&](const char* function, RTprogram* p) {
    return rtProgramCreateFromPTXFile(ctx, module.c_str(), function, p);
  };
  E2E_TRY(rtContextSetEntryPointCount(ctx, 2));
  E2E_TRY(rtContextSetRayTypeCount(ctx, 1));
  RTprogram render, render_slow, miss, shade, bounds, intersect;
  E2E_TRY(program("render", &render));
  E2E_TRY(program("render_slow", &render_slow));
  E2E_TRY(program("miss", &miss));
  E2E_TRY(program("shade", &shade));
  E2E_TRY(program("sphere_bounds", &bounds));
  E2E_TRY(program("sphere_intersect", &intersect));
  E2E_TRY(rtContextSetRayGenerationProgram(ctx, 0, render));
  E2E_TRY(rtContextSetRayGenerationProgram(ctx, 1, render_slow));
  E2E_TRY(rtContextSetMissProgram(ctx, 0, miss));

  // A 5×5 grid of spheres in front of the camera.
  constexpr int kGrid = 5;
  std::vector<float> spheres;
  for (int y = 0; y < kGrid; ++y) {
    for (int x = 0; x < kGrid; ++x) {
      spheres.insert(spheres.end(),
                     {(x - 2) * 1.1f, (y - 2) * 1.1f, 6.f + 0.3f * ((x + y) % 3), 0.45f});
    }
  }
  RTbuffer sphere_buffer = nullptr;
  E2E_TRY(rtBufferCreate(ctx, RT_BUFFER_INPUT, &sphere_buffer));
  E2E_TRY(rtBufferSetFormat(sphere_buffer, RT_FORMAT_FLOAT4));
  E2E_TRY(rtBufferSetSize1D(sphere_buffer, kGrid * kGrid));
  E2E_TRY(Fill(sphere_buffer, spheres.data(), spheres.size()));
  RTvariable v = nullptr;
  E2E_TRY(rtContextDeclareVariable(ctx, "spheres", &v));
  E2E_TRY(rtVariableSetObject(v, sphere_buffer));

  E2E_TRY(Float4Buffer2D(ctx, "image", RT_BUFFER_OUTPUT, width, height, &scene->image, error));
  E2E_TRY(
      Float4Buffer2D(ctx, "accum", RT_BUFFER_INPUT_OUTPUT, width, height, &scene->accum, error));
  E2E_TRY(Float4Buffer2D(ctx, "noise", RT_BUFFER_INPUT, width, height, &scene->noise, error));
  std::vector<float> zeros(size_t{4} * width * height, 0.f), noise(zeros.size());
  for (size_t i = 0; i < noise.size(); ++i) noise[i] = static_cast<float>((i * 2654435761u) % 1000);
  E2E_TRY(Fill(scene->accum, zeros.data(), zeros.size()));
  E2E_TRY(Fill(scene->noise, noise.data(), noise.size()));

  RTgeometry geometry;
  E2E_TRY(rtGeometryCreate(ctx, &geometry));
  E2E_TRY(rtGeometrySetPrimitiveCount(geometry, kGrid * kGrid));
  E2E_TRY(rtGeometrySetBoundingBoxProgram(geometry, bounds));
  E2E_TRY(rtGeometrySetIntersectionProgram(geometry, intersect));
  RTmaterial material;
  E2E_TRY(rtMaterialCreate(ctx, &material));
  E2E_TRY(rtMaterialSetClosestHitProgram(material, 0, shade));
  RTgeometryinstance instance;
  E2E_TRY(rtGeometryInstanceCreate(ctx, &instance));
  E2E_TRY(rtGeometryInstanceSetGeometry(instance, geometry));
  E2E_TRY(rtGeometryInstanceSetMaterialCount(instance, 1));
  E2E_TRY(rtGeometryInstanceSetMaterial(instance, 0, material));
  RTacceleration accel;
  E2E_TRY(rtAccelerationCreate(ctx, &accel));
  E2E_TRY(rtAccelerationSetBuilder(accel, "Bvh"));
  E2E_TRY(rtAccelerationSetTraverser(accel, "Bvh"));
  RTgeometrygroup group;
  E2E_TRY(rtGeometryGroupCreate(ctx, &group));
  E2E_TRY(rtGeometryGroupSetAcceleration(group, accel));
  E2E_TRY(rtGeometryGroupSetChildCount(group, 1));
  E2E_TRY(rtGeometryGroupSetChild(group, 0, instance));
  E2E_TRY(rtContextDeclareVariable(ctx, "top_object", &v));
  E2E_TRY(rtVariableSetObject(v, group));
  E2E_TRY(rtContextDeclareVariable(ctx, "eye", &v));
  E2E_TRY(rtVariableSet3f(v, 0.f, 0.f, -1.f));
  E2E_TRY(rtContextDeclareVariable(ctx, "iterations", &scene->iterations));
  E2E_TRY(rtVariableSet1i(scene->iterations, 1));
  return RT_SUCCESS;
}

}  // namespace tessera::e2e

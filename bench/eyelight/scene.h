// The eyelight scene through the OptiX 3 API: one GeometryGroup holding one GeometryInstance of
// a triangle mesh whose Trbvh acceleration names vertex_buffer / index_buffer, so Tessera traces
// native Embree triangles and runs the intersection program only for the closest hit.
#ifndef TESSERA_BENCH_EYELIGHT_SCENE_H_
#define TESSERA_BENCH_EYELIGHT_SCENE_H_

#include <tessera/rt.h>

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "mesh.h"

namespace tessera::bench {

// Embree viewer's camera flags (-vp, -vi, -vu, -fov): position, look-at point, up vector and
// vertical field of view in degrees, right-handed.
struct Camera {
  float from[3] = {278.f, 273.f, -800.f};
  float to[3] = {278.f, 273.f, 0.f};
  float up[3] = {0.f, 1.f, 0.f};
  float fov_degrees = 37.f;

  // The same flags for Embree's viewer, so both render one view.
  std::vector<std::string> ViewerFlags() const;
};

// The OptiX SDK pinhole camera for `camera` at width x height: W to the look-at point, U right,
// V up; |V| spans half the vertical field of view, |U| the same times the aspect ratio. A launch
// index (x, y), row 0 at the bottom, looks along U*dx + V*dy + W with d = (index+0.5)/size*2-1.
struct Pinhole {
  float eye[3], u[3], v[3], w[3];
};
Pinhole MakePinhole(const Camera& camera, unsigned width, unsigned height);

// One 8-bit RGBA image, rows top to bottom (as files and Embree's framebuffer keep them).
struct Image {
  unsigned width = 0, height = 0;
  std::vector<uint8_t> rgba;
};

class EyelightScene {
 public:
  // Builds the whole context on `devices` (a device spec); `module_path` is the bench_eyelight
  // program module; `threads` > 0 sets RT_CONTEXT_ATTRIBUTE_CPU_NUM_THREADS. Throws
  // std::runtime_error with rtContextGetErrorString's message on any failure.
  // `builtin_triangles`: the mesh as OptiX 6 GeometryTriangles with an attribute program;
  // otherwise as OptiX 3 geometry with an intersection program whose acceleration names the
  // vertex and index buffers (Embree triangles too, the program run for the closest hit).
  EyelightScene(const Mesh& mesh, const Camera& camera, unsigned width, unsigned height,
                const std::string& module_path, const std::string& devices, int threads = 0,
                bool builtin_triangles = false);
  ~EyelightScene();
  EyelightScene(const EyelightScene&) = delete;
  EyelightScene& operator=(const EyelightScene&) = delete;

  void Launch();
  Image ReadImage();
  // RT_CONTEXT_ATTRIBUTE_CPU_NUM_THREADS (0 if the context does not say).
  int ThreadCount();
  RTcontext context() const { return context_; }

 private:
  void Check(RTresult result, const char* call);
  RTprogram Program(const char* function);
  // The mesh's buffers, declared as `vertex_buffer` and `index_buffer` in `declare`'s scope.
  template <typename Declare>
  std::pair<RTbuffer, RTbuffer> MeshBuffers(const Mesh& mesh, Declare&& declare);

  RTcontext context_ = nullptr;
  RTbuffer output_ = nullptr;
  unsigned width_, height_;
  std::string module_path_;
};

}  // namespace tessera::bench

#endif  // TESSERA_BENCH_EYELIGHT_SCENE_H_

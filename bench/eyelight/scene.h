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

#include "camera.h"
#include "mesh.h"

namespace tessera::bench {

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

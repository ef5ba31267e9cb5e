// The eyelight view: Embree viewer's camera and the OptiX SDK pinhole that matches it, shared by
// the benchmarks that trace it (eyelight, optix7, batching); no Tessera API here.
#ifndef TESSERA_BENCH_EYELIGHT_CAMERA_H_
#define TESSERA_BENCH_EYELIGHT_CAMERA_H_

#include <string>
#include <vector>

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

}  // namespace tessera::bench

#endif  // TESSERA_BENCH_EYELIGHT_CAMERA_H_

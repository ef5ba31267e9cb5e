#include "tutorial/camera.h"

#include <cmath>

#include "tutorial/vec_math.h"

namespace tessera::tutorial {

PinholeCamera TutorialCamera() {
  return {make_float3(7.0f, 9.2f, -6.0f), make_float3(0.0f, 4.0f, 0.0f),
          make_float3(0.0f, 1.0f, 0.0f), 60.0f};
}

CameraFrame ComputeFrame(const PinholeCamera& camera, float aspect) {
  CameraFrame frame;
  frame.eye = camera.eye;
  frame.W = Sub(camera.lookat, camera.eye);
  const float wlen = Length(frame.W);
  const float3 u = Normalize(Cross(frame.W, camera.up));
  const float3 v = Normalize(Cross(u, frame.W));
  const float vlen =
      wlen * std::tan(0.5f * camera.vfov_degrees * static_cast<float>(M_PI) / 180.0f);
  frame.V = Scale(v, vlen);
  frame.U = Scale(u, vlen * aspect);
  return frame;
}

bool ProjectToImage(const CameraFrame& frame, const float3& p, float* fx, float* fy) {
  // U, V and W are orthogonal, so the screen coordinates are ratios of projections.
  const float3 d = Sub(p, frame.eye);
  const float w = Dot(d, frame.W) / Dot(frame.W, frame.W);
  if (w <= 0.0f) return false;
  const float u = Dot(d, frame.U) / Dot(frame.U, frame.U) / w;
  const float v = Dot(d, frame.V) / Dot(frame.V, frame.V) / w;
  *fx = 0.5f * (u + 1.0f);
  *fy = 1.0f - 0.5f * (v + 1.0f);  // launch row 0 is the bottom; image row 0 is the top
  return true;
}

}  // namespace tessera::tutorial

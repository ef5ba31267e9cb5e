// The tutorial's pinhole camera: the eye/U/V/W variables of the pinhole_camera program,
// computed on the host from eye, lookat, up and the vertical field of view.
#ifndef TESSERA_SAMPLES_TUTORIAL_CAMERA_H_
#define TESSERA_SAMPLES_TUTORIAL_CAMERA_H_

#include <optixu/optixu_vector_types.h>

namespace tessera::tutorial {

struct PinholeCamera {
  float3 eye;
  float3 lookat;
  float3 up;
  float vfov_degrees;
};

// What pinhole_camera reads: a ray through normalized screen position d in [-1, 1]^2 has the
// direction d.x * U + d.y * V + W. W is not normalized: its length is the distance to lookat.
struct CameraFrame {
  float3 eye;
  float3 U;
  float3 V;
  float3 W;
};

// The SDK tutorial's view of the scene.
PinholeCamera TutorialCamera();

// U, V, W for an image of width/height `aspect`.
CameraFrame ComputeFrame(const PinholeCamera& camera, float aspect);

// Where world point `p` lands in the image, as fractions of width and height from the top-left
// corner. Returns false for points behind the eye.
bool ProjectToImage(const CameraFrame& frame, const float3& p, float* fx, float* fy);

}  // namespace tessera::tutorial

#endif  // TESSERA_SAMPLES_TUTORIAL_CAMERA_H_

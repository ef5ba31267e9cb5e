// The camera a render looks through: chosen by `--camera`, or made up to frame a scene without
// one, and turned into the ray basis camera.cu takes.
#ifndef TESSERA_TOOLS_TESSERA_RENDER_CAMERA_SETUP_H_
#define TESSERA_TOOLS_TESSERA_RENDER_CAMERA_SETUP_H_

#include <string>

#include "absl/status/statusor.h"
#include "tools/tessera/scene/scene.h"

namespace tessera::render {

// `spec` names a camera of `frame` by index ("0", "1", ...) or by name; "" takes the first, or,
// in a scene without cameras, one looking down -Z at the middle of its bounds that fills an image
// of `image_aspect` (width / height) with them. NOT_FOUND lists the cameras there are.
absl::StatusOr<Camera> SelectCamera(const Frame& frame, const std::string& spec,
                                    float image_aspect = 16.f / 9.f);

// A perspective camera at `from` looking at `at`, +Y up (`--look-from`, `--look-at`), with the
// default field of view. INVALID_ARGUMENT when the two points are the same or the view is straight
// up or down.
absl::StatusOr<Camera> LookAtCamera(const float from[3], const float at[3]);

// The image size: what was asked for (0: not given). With neither given, 1280 wide and as high as
// the camera's aspect ratio says (720 without one); with one given, the other from the aspect
// ratio (16:9 without one).
void ResolveImageSize(const Camera& camera, int requested_width, int requested_height, int* width,
                      int* height);

// camera.cu's variables (eye, U, V, W, orthographic, near_distance) for an image of this size.
// The image's aspect ratio wins over the camera's; the vertical field of view (or half height,
// ymag) is kept.
struct CameraBasis {
  float eye[3], u[3], v[3], w[3];
  bool orthographic = false;
  float near_distance = 0.f;
};
CameraBasis ComputeCameraBasis(const Camera& camera, int width, int height);

}  // namespace tessera::render

#endif  // TESSERA_TOOLS_TESSERA_RENDER_CAMERA_SETUP_H_

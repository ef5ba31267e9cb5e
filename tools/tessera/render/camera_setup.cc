#include "tools/tessera/render/camera_setup.h"

#include <algorithm>
#include <cmath>

#include "absl/status/status.h"
#include "absl/strings/numbers.h"
#include "absl/strings/str_cat.h"

namespace tessera::render {
namespace {

struct Vec {
  float x, y, z;
};
Vec Cross(Vec a, Vec b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
Vec Normalize(Vec a) {
  const float len = std::sqrt(a.x * a.x + a.y * a.y + a.z * a.z);
  return len > 0.f ? Vec{a.x / len, a.y / len, a.z / len} : Vec{0.f, 0.f, 0.f};
}
void Store(Vec v, float scale, float out[3]) {
  out[0] = v.x * scale;
  out[1] = v.y * scale;
  out[2] = v.z * scale;
}

// Looks down -Z (glTF's front view) from as close as keeps all eight corners of the bounds inside
// an image of this aspect ratio, with a small margin: a bounding sphere would leave long or flat
// objects small in the frame.
Camera FramingCamera(const Frame& frame, float image_aspect) {
  const float* b = frame.bounds;
  const float cx = 0.5f * (b[0] + b[3]), cy = 0.5f * (b[1] + b[4]), cz = 0.5f * (b[2] + b[5]);
  const float hx = 0.5f * (b[3] - b[0]), hy = 0.5f * (b[4] - b[1]), hz = 0.5f * (b[5] - b[2]);
  Camera camera;
  camera.name = "(framing the scene)";
  const float tan_y = std::tan(0.5f * camera.yfov);
  const float tan_x = tan_y * (image_aspect > 0.f ? image_aspect : 16.f / 9.f);
  // The nearest corners (z = +hz) are the widest in the image; far ones never need more room.
  float distance = hz + std::max(hx / tan_x, hy / tan_y) * 1.08f;
  distance = std::max(distance, hz + std::max({hx, hy, hz, 1e-3f}));  // never inside the box
  camera.to_world = {1, 0, 0, cx, 0, 1, 0, cy, 0, 0, 1, cz + distance};
  return camera;
}

}  // namespace

absl::StatusOr<Camera> LookAtCamera(const float from[3], const float at[3]) {
  const Vec forward = Normalize({at[0] - from[0], at[1] - from[1], at[2] - from[2]});
  const Vec z{-forward.x, -forward.y, -forward.z};  // a camera looks down its -Z
  const Vec x = Normalize(Cross({0.f, 1.f, 0.f}, z));
  if ((z.x == 0.f && z.y == 0.f && z.z == 0.f) || (x.x == 0.f && x.y == 0.f && x.z == 0.f)) {
    return absl::InvalidArgumentError(
        "--look-from and --look-at: the two points must differ, and the view must not be "
        "straight up or down");
  }
  const Vec y = Cross(z, x);
  Camera camera;
  camera.name = absl::StrCat("look-from ", from[0], ",", from[1], ",", from[2], " at ", at[0], ",",
                             at[1], ",", at[2]);
  camera.to_world = {x.x, y.x, z.x, from[0], x.y, y.y, z.y, from[1], x.z, y.z, z.z, from[2]};
  return camera;
}

absl::StatusOr<Camera> SelectCamera(const Frame& frame, const std::string& spec,
                                    float image_aspect) {
  if (spec.empty()) {
    return frame.cameras.empty() ? FramingCamera(frame, image_aspect) : frame.cameras.front();
  }
  int index = -1;
  if (absl::SimpleAtoi(spec, &index)) {
    if (index >= 0 && static_cast<size_t>(index) < frame.cameras.size()) {
      return frame.cameras[static_cast<size_t>(index)];
    }
  } else {
    for (const Camera& camera : frame.cameras) {
      if (camera.name == spec) return camera;
    }
  }
  std::string there;
  for (size_t i = 0; i < frame.cameras.size(); ++i) {
    absl::StrAppend(&there, i == 0 ? "" : ", ", i, " \"", frame.cameras[i].name, "\"");
  }
  return absl::NotFoundError(absl::StrCat("--camera ", spec, ": no such camera (the scene has ",
                                          frame.cameras.empty() ? std::string("none") : there,
                                          ")"));
}

void ResolveImageSize(const Camera& camera, int requested_width, int requested_height, int* width,
                      int* height) {
  const float aspect = camera.aspect > 0.f ? camera.aspect : 16.f / 9.f;
  if (requested_width > 0 && requested_height > 0) {
    *width = requested_width;
    *height = requested_height;
  } else if (requested_width > 0) {
    *width = requested_width;
    *height =
        std::max(1, static_cast<int>(std::lround(static_cast<float>(requested_width) / aspect)));
  } else if (requested_height > 0) {
    *height = requested_height;
    *width =
        std::max(1, static_cast<int>(std::lround(static_cast<float>(requested_height) * aspect)));
  } else {
    *width = 1280;
    *height =
        camera.aspect > 0.f ? std::max(1, static_cast<int>(std::lround(1280.f / aspect))) : 720;
  }
}

CameraBasis ComputeCameraBasis(const Camera& camera, int width, int height) {
  const Affine& m = camera.to_world;
  const Vec y_column{m[1], m[5], m[9]};
  const Vec back = Normalize({m[2], m[6], m[10]});  // the camera looks down its -Z
  const Vec right = Normalize(Cross(y_column, back));
  const Vec up = Cross(back, right);
  const float aspect = static_cast<float>(width) / static_cast<float>(height);
  CameraBasis basis;
  basis.eye[0] = m[3];
  basis.eye[1] = m[7];
  basis.eye[2] = m[11];
  Store(back, -1.f, basis.w);
  basis.orthographic = camera.orthographic;
  const float half_height = camera.orthographic ? camera.ymag : std::tan(0.5f * camera.yfov);
  Store(right, half_height * aspect, basis.u);
  Store(up, half_height, basis.v);
  basis.near_distance = std::max(camera.znear, 0.f);
  return basis;
}

}  // namespace tessera::render

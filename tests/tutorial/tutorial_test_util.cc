#include "tutorial_test_util.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <memory>

#include "tutorial/camera.h"
#include "tutorial/render.h"
#include "tutorial/scene.h"
#include "tutorial/vec_math.h"

namespace tessera::tutorial::testing {

const Image& Rendered(int step) {
  static std::map<int, std::unique_ptr<Image>> cache;
  auto it = cache.find(step);
  if (it == cache.end()) {
    RenderOptions options;
    options.step = step;
    options.width = kWidth;
    options.height = kHeight;
    options.module_dir = ResolveModuleDir("");
    options.load_envmap = &LoadEnvmapFile;  // as tessera-tutorial renders
    it = cache.emplace(step, std::make_unique<Image>(RenderStep(options))).first;
  }
  return *it->second;
}

std::ostream& operator<<(std::ostream& os, const Rgb& c) {
  return os << "(" << c.r << ", " << c.g << ", " << c.b << ")";
}

Rgb At(const Image& image, float fx, float fy) {
  const int x = std::clamp(static_cast<int>(fx * image.width), 0, image.width - 1);
  const int y = std::clamp(static_cast<int>(fy * image.height), 0, image.height - 1);
  const float* p = image.Pixel(x, y);
  return {p[0], p[1], p[2]};
}

void Project(const float3& p, float* fx, float* fy) {
  const CameraFrame frame =
      ComputeFrame(TutorialCamera(), static_cast<float>(kWidth) / static_cast<float>(kHeight));
  *fx = *fy = -1.0f;
  ProjectToImage(frame, p, fx, fy);
}

float3 Eye() { return TutorialCamera().eye; }

float3 FloorPointAt(float fx, float fy) {
  const CameraFrame f =
      ComputeFrame(TutorialCamera(), static_cast<float>(kWidth) / static_cast<float>(kHeight));
  // The launch index At() reads (launch rows count from the bottom), as pinhole_camera maps it.
  const int x = std::clamp(static_cast<int>(fx * kWidth), 0, kWidth - 1);
  const int y = kHeight - 1 - std::clamp(static_cast<int>(fy * kHeight), 0, kHeight - 1);
  const float dx = static_cast<float>(x) / kWidth * 2.0f - 1.0f;
  const float dy = static_cast<float>(y) / kHeight * 2.0f - 1.0f;
  const float3 dir = Add(Add(Scale(f.U, dx), Scale(f.V, dy)), f.W);
  const float t = (kFloorHeight - f.eye.y) / dir.y;
  return Add(f.eye, Scale(dir, t));
}

Rgb AtWorld(const Image& image, const float3& p) {
  float fx = 0.0f;
  float fy = 0.0f;
  Project(p, &fx, &fy);
  EXPECT_TRUE(fx >= 0.0f && fx < 1.0f && fy >= 0.0f && fy < 1.0f)
      << "world point (" << p.x << ", " << p.y << ", " << p.z << ") projects to (" << fx << ", "
      << fy << "), outside the image";
  return At(image, fx, fy);
}

}  // namespace tessera::tutorial::testing

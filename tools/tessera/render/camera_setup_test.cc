#include "tools/tessera/render/camera_setup.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace tessera::render {
namespace {

Frame TwoCameras() {
  Frame frame;
  Camera a;
  a.name = "front";
  a.to_world = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 5};
  Camera b = a;
  b.name = "side";
  b.aspect = 2.f;
  frame.cameras = {a, b};
  return frame;
}

TEST(CameraSetupTest, SelectsByIndexOrNameAndListsThemOtherwise) {
  const Frame frame = TwoCameras();
  EXPECT_EQ(SelectCamera(frame, "")->name, "front");
  EXPECT_EQ(SelectCamera(frame, "1")->name, "side");
  EXPECT_EQ(SelectCamera(frame, "side")->name, "side");
  const auto missing = SelectCamera(frame, "top");
  ASSERT_TRUE(absl::IsNotFound(missing.status()));
  EXPECT_NE(missing.status().message().find("1 \"side\""), std::string::npos);
  EXPECT_FALSE(SelectCamera(frame, "2").ok());
}

TEST(CameraSetupTest, FramesASceneWithoutCameras) {
  Frame frame;
  const float bounds[6] = {-1, -1, -1, 1, 1, 1};
  std::copy(bounds, bounds + 6, frame.bounds);
  const auto camera = SelectCamera(frame, "");
  ASSERT_TRUE(camera.ok());
  EXPECT_FALSE(camera->orthographic);
  EXPECT_GT(camera->to_world[11], 2.f);  // in front of the box, looking down -Z at it
  EXPECT_EQ(camera->to_world[3], 0.f);
}

// The made-up camera fills the image with the bounds: every corner inside, the widest near an edge.
TEST(CameraSetupTest, FramingFillsTheImageWithALongBox) {
  Frame frame;
  const float bounds[6] = {-4, -0.5f, -0.5f, 4, 0.5f, 0.5f};
  std::copy(bounds, bounds + 6, frame.bounds);
  for (const float aspect : {16.f / 9.f, 1.f, 0.5f}) {
    const auto camera = SelectCamera(frame, "", aspect);
    ASSERT_TRUE(camera.ok());
    const float eye_z = camera->to_world[11];
    const float tan_y = std::tan(0.5f * camera->yfov), tan_x = tan_y * aspect;
    float widest = 0.f;
    for (const float x : {-4.f, 4.f}) {
      for (const float y : {-0.5f, 0.5f}) {
        for (const float z : {-0.5f, 0.5f}) {
          const float depth = eye_z - z;
          ASSERT_GT(depth, 0.f);
          const float ndc_x = x / depth / tan_x, ndc_y = y / depth / tan_y;
          EXPECT_LE(std::abs(ndc_x), 1.f) << aspect;
          EXPECT_LE(std::abs(ndc_y), 1.f) << aspect;
          widest = std::max({widest, std::abs(ndc_x), std::abs(ndc_y)});
        }
      }
    }
    EXPECT_GT(widest, 0.85f) << aspect;
  }
}

TEST(CameraSetupTest, ImageSizeFollowsTheAspectRatio) {
  Camera camera;
  int w = 0, h = 0;
  ResolveImageSize(camera, 0, 0, &w, &h);
  EXPECT_EQ(w, 1280);
  EXPECT_EQ(h, 720);
  camera.aspect = 2.f;
  ResolveImageSize(camera, 0, 0, &w, &h);
  EXPECT_EQ(h, 640);
  ResolveImageSize(camera, 0, 300, &w, &h);
  EXPECT_EQ(w, 600);
  ResolveImageSize(camera, 100, 0, &w, &h);
  EXPECT_EQ(h, 50);
  ResolveImageSize(camera, 100, 10, &w, &h);
  EXPECT_EQ(w, 100);
  EXPECT_EQ(h, 10);
}

TEST(CameraSetupTest, BasisLooksDownMinusZWithTheImagesAspect) {
  Camera camera;
  camera.yfov = 2.f * std::atan(0.5f);  // half height 0.5 at distance 1
  camera.to_world = {1, 0, 0, 1, 0, 1, 0, 2, 0, 0, 1, 3};
  const CameraBasis b = ComputeCameraBasis(camera, 200, 100);
  EXPECT_FLOAT_EQ(b.eye[0], 1.f);
  EXPECT_FLOAT_EQ(b.eye[2], 3.f);
  EXPECT_FLOAT_EQ(b.w[2], -1.f);
  EXPECT_NEAR(b.v[1], 0.5f, 1e-6f);
  EXPECT_NEAR(b.u[0], 1.0f, 1e-6f);  // twice as wide
}

TEST(CameraSetupTest, LookAtCameraLooksFromOnePointAtTheOther) {
  // Embree viewer's view of its Cornell box: from z = -800 towards the open side.
  const float from[3] = {278.f, 273.f, -800.f}, at[3] = {278.f, 273.f, 0.f};
  const absl::StatusOr<Camera> camera = LookAtCamera(from, at);
  ASSERT_TRUE(camera.ok()) << camera.status();
  const CameraBasis b = ComputeCameraBasis(*camera, 100, 100);
  EXPECT_FLOAT_EQ(b.eye[2], -800.f);
  EXPECT_GT(b.w[2], 0.f);  // towards +z
  EXPECT_NEAR(b.w[0], 0.f, 1e-6f);
  EXPECT_GT(b.v[1], 0.f);  // +Y up
  EXPECT_LT(b.u[0], 0.f);  // right is -x seen from -z, +Y up
  EXPECT_FALSE(LookAtCamera(from, from).ok());
  const float above[3] = {278.f, 1000.f, 0.f};
  EXPECT_FALSE(LookAtCamera(at, above).ok());  // straight up
}

}  // namespace
}  // namespace tessera::render

// Image tests of the tutorial steps: each test checks what its step adds, mostly by comparing a
// pixel with the same pixel of an earlier step. Pixels are found by projecting scene points
// through the tutorial camera (or as fractions of the image size), so the checks hold at any
// resolution.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "tutorial/camera.h"
#include "tutorial/render.h"
#include "tutorial/scene.h"
#include "tutorial/steps.h"
#include "tutorial/vec_math.h"
#include "tutorial_test_util.h"

namespace tessera::tutorial::testing {
namespace {

// Scene points the tests look at (see samples/tutorial/scene.h for the layout; the light is
// high up at -x, -z, so shadows fall towards +x, +z).
constexpr float3 kBoxTop = {0.0f, 7.0f, 0.0f};
constexpr float3 kBoxPlusXFace = {2.0f, 3.5f, 0.0f};    // faces away from the light
constexpr float3 kBoxMinusZFace = {0.0f, 3.5f, -2.0f};  // faces the light at a steep angle
constexpr float3 kFloorInBoxShadow = {2.4f, 0.01f, 2.5f};
constexpr float3 kFloorLitNearShadow = {3.5f, 0.01f, 2.5f};
constexpr float3 kFloorNear = {0.0f, 0.01f, -5.0f};   // seen steeply; reflects the sky
constexpr float3 kFloorFar = {-30.0f, 0.01f, 40.0f};  // seen at a grazing angle
constexpr float3 kChullCenter = {-1.4f, 1.5f, -3.7f};
constexpr float3 kFloorInChullShadow = {-1.2f, 0.01f, -2.3f};

float MaxAbsDiff(const Rgb& a, const Rgb& b) {
  return std::fmax(std::fabs(a.r - b.r), std::fmax(std::fabs(a.g - b.g), std::fabs(a.b - b.b)));
}

// The floor point at the center of tile (i, j) of the step 7 tiling.
float3 TileCenter(int i, int j) {
  // Solve dot(kTileV0, p) = i + 0.5, dot(kTileV1, p) = j + 0.5 for p = (x, floor, z).
  const float a = static_cast<float>(i) + 0.5f;
  const float b = static_cast<float>(j) + 0.5f;
  const float det = kTileV0.x * kTileV1.z - kTileV0.z * kTileV1.x;
  const float x = (a * kTileV1.z - b * kTileV0.z) / det;
  const float z = (b * kTileV0.x - a * kTileV1.x) / det;
  return make_float3(x, kFloorHeight, z);
}

float LumaVariance(const std::vector<Rgb>& samples) {
  float mean = 0.0f;
  for (const Rgb& c : samples) mean += c.Luma();
  mean /= static_cast<float>(samples.size());
  float var = 0.0f;
  for (const Rgb& c : samples) var += (c.Luma() - mean) * (c.Luma() - mean);
  return var / static_cast<float>(samples.size());
}

std::vector<Rgb> BoxTopSamples(const Image& image) {
  std::vector<Rgb> samples;
  for (int i = 0; i < 7; ++i) {
    for (int j = 0; j < 7; ++j) {
      samples.push_back(AtWorld(image, make_float3(-1.5f + 0.5f * static_cast<float>(i), kBoxMax.y,
                                                   -1.5f + 0.5f * static_cast<float>(j))));
    }
  }
  return samples;
}

// ---- Every step --------------------------------------------------------------------------------

class TutorialEveryStepTest : public ::testing::TestWithParam<int> {};

TEST_P(TutorialEveryStepTest, FiniteNoExceptionPixelsNotUniform) {
  const Image& image = Rendered(GetParam());
  ASSERT_EQ(image.width, kWidth);
  ASSERT_EQ(image.height, kHeight);
  float min_luma = 1e30f;
  float max_luma = -1e30f;
  int nonfinite = 0;
  int magenta = 0;
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      const float* p = image.Pixel(x, y);
      if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]) ||
          !std::isfinite(p[3])) {
        ++nonfinite;
        continue;
      }
      if (p[0] == kBadColor[0] && p[1] == kBadColor[1] && p[2] == kBadColor[2]) ++magenta;
      const float luma = Rgb{p[0], p[1], p[2]}.Luma();
      min_luma = std::fmin(min_luma, luma);
      max_luma = std::fmax(max_luma, luma);
    }
  }
  EXPECT_EQ(nonfinite, 0) << "pixels with NaN or infinite components";
  EXPECT_EQ(magenta, 0) << "pixels written by the exception program";
  EXPECT_GT(max_luma - min_luma, 0.2f) << "the image is (nearly) uniform";
}

INSTANTIATE_TEST_SUITE_P(Tutorial, TutorialEveryStepTest,
                         ::testing::Range(kFirstStep, kEnvironmentCameraStep + 1));

// ---- Step by step ------------------------------------------------------------------------------

TEST(TutorialStep0, NormalsMapToColors) {
  const Image& image = Rendered(0);
  const Rgb top = AtWorld(image, kBoxTop);  // normal (0, 1, 0) -> (0.5, 1, 0.5)
  EXPECT_GT(top.g, top.r) << top;
  EXPECT_GT(top.g, top.b) << top;
  EXPECT_NEAR(top.g, 1.0f, 1e-3f) << top;
  const Rgb plus_x = AtWorld(image, kBoxPlusXFace);  // normal (1, 0, 0) -> (1, 0.5, 0.5)
  EXPECT_NEAR(plus_x.r, 1.0f, 1e-3f) << plus_x;
  EXPECT_NEAR(plus_x.g, 0.5f, 1e-3f) << plus_x;
  const Rgb minus_z = AtWorld(image, kBoxMinusZFace);  // normal (0, 0, -1) -> (0.5, 0.5, 0)
  EXPECT_NEAR(minus_z.b, 0.0f, 1e-3f) << minus_z;
}

TEST(TutorialStep0, BackgroundIsMissColor) {
  const Image& image = Rendered(0);
  // Above the far edge of the floor, left and right.
  for (const float fx : {0.02f, 0.5f, 0.98f}) {
    const Rgb bg = At(image, fx, 0.02f);
    EXPECT_FLOAT_EQ(bg.r, kBackgroundColor[0]) << "at x fraction " << fx;
    EXPECT_FLOAT_EQ(bg.g, kBackgroundColor[1]) << "at x fraction " << fx;
    EXPECT_FLOAT_EQ(bg.b, kBackgroundColor[2]) << "at x fraction " << fx;
  }
}

TEST(TutorialStep1, LitFacesBrighterThanFacesAwayFromLight) {
  const Image& image = Rendered(1);
  const Rgb top = AtWorld(image, kBoxTop);
  const Rgb toward = AtWorld(image, kBoxMinusZFace);
  const Rgb away = AtWorld(image, kBoxPlusXFace);
  EXPECT_GT(top.Luma(), toward.Luma() + 0.1f) << top << " vs " << toward;
  EXPECT_GT(toward.Luma(), away.Luma() + 0.02f) << toward << " vs " << away;
  // A face turned away from the only light gets the ambient term alone: Ka * ambient.
  EXPECT_NEAR(away.r, 0.3f * 0.31f, 1e-3f) << away;
  EXPECT_NEAR(away.g, 0.3f * 0.33f, 1e-3f) << away;
}

TEST(TutorialStep2, PhongAddsHighlightsOnly) {
  const Image& lambert = Rendered(1);
  const Image& phong = Rendered(2);
  float max_gain = 0.0f;
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      const float* a = lambert.Pixel(x, y);
      const float* b = phong.Pixel(x, y);
      for (int c = 0; c < 3; ++c) {
        ASSERT_GE(b[c], a[c] - 1e-5f) << "Phong darkened pixel " << x << "," << y;
        max_gain = std::fmax(max_gain, b[c] - a[c]);
      }
    }
  }
  // With the SDK's light and phong_exp 88 the mirror highlight lies outside the view: only its
  // tail reaches the floor at the bottom of the image, right of the center.
  EXPECT_GT(max_gain, 0.003f);

  // There the gain is Ks * (N.H)^phong_exp (floor Ks 0.4, white light).
  for (const float fx : {0.55f, 0.7f, 0.85f}) {
    const float fy = 0.99f;
    const float3 p = FloorPointAt(fx, fy);
    const float3 l = Normalize(Sub(kLightPos, p));
    const float3 v = Normalize(Sub(Eye(), p));
    const float3 h = Normalize(Add(l, v));
    const float expected = 0.4f * std::pow(h.y, 88.0f);
    const float gain = At(phong, fx, fy).r - At(lambert, fx, fy).r;
    EXPECT_GT(expected, 1e-3f) << "test point too far from the highlight";
    EXPECT_NEAR(gain, expected, 0.05f * expected) << "at x fraction " << fx;
  }
}

TEST(TutorialStep3, BoxCastsShadowOnFloor) {
  const Rgb shadow = AtWorld(Rendered(3), kFloorInBoxShadow);
  const Rgb lit = AtWorld(Rendered(3), kFloorLitNearShadow);
  const Rgb unshadowed = AtWorld(Rendered(2), kFloorInBoxShadow);
  EXPECT_LT(shadow.Luma(), 0.5f * lit.Luma()) << shadow << " vs lit " << lit;
  EXPECT_LT(shadow.Luma(), 0.5f * unshadowed.Luma()) << shadow << " vs step 2 " << unshadowed;
}

TEST(TutorialStep4, FloorReflects) {
  // Step 4 adds 0.1 of a reflection ray to the floor; step 3 is the same scene without it.
  const Rgb before = AtWorld(Rendered(3), kFloorNear);
  const Rgb after = AtWorld(Rendered(4), kFloorNear);
  EXPECT_GT(after.b - before.b, 0.03f) << after << " vs step 3 " << before;
  const Rgb before_shadow = AtWorld(Rendered(3), kFloorLitNearShadow);
  const Rgb after_shadow = AtWorld(Rendered(4), kFloorLitNearShadow);
  EXPECT_GT(MaxAbsDiff(after_shadow, before_shadow), 0.02f);
}

TEST(TutorialStep5, EnvironmentMapReplacesConstantBackground) {
  const Rgb sky = At(Rendered(5), 0.5f, 0.02f);
  const Rgb constant = At(Rendered(4), 0.5f, 0.02f);
  EXPECT_GT(MaxAbsDiff(sky, constant), 0.1f) << sky << " vs " << constant;
}

TEST(TutorialStep6, ReflectionGrowsTowardsGrazingAngles) {
  // Steps 5 and 6 reflect the same surroundings; step 5 with a constant 0.1, step 6 with
  // Schlick's term. Their ratio to step 3 (no reflection) isolates the reflection weight.
  auto weight_ratio = [](const float3& p) {
    const float none = AtWorld(Rendered(3), p).Luma();
    const float constant = AtWorld(Rendered(5), p).Luma() - none;
    const float schlick = AtWorld(Rendered(6), p).Luma() - none;
    EXPECT_GT(constant, 0.01f) << "no reflection at step 5";
    return schlick / constant;
  };
  const float near = weight_ratio(kFloorNear);
  const float far = weight_ratio(kFloorFar);
  EXPECT_LT(near, 1.0f) << "Schlick weight at a steep angle should be below 0.1";
  EXPECT_GT(far, 2.0f * near) << "near " << near << ", far " << far;
}

TEST(TutorialStep7, AdjacentTilesAlternate) {
  // Tiles right of the box in the image, clear of its shadow and reflection.
  for (int step : {6, 7}) {
    const Image& image = Rendered(step);
    const float l00 = AtWorld(image, TileCenter(-3, -1)).Luma();
    const float l01 = AtWorld(image, TileCenter(-3, 0)).Luma();
    const float l02 = AtWorld(image, TileCenter(-3, 1)).Luma();
    const float l10 = AtWorld(image, TileCenter(-2, -1)).Luma();
    const float l11 = AtWorld(image, TileCenter(-2, 0)).Luma();
    auto differ = [](float a, float b) { return std::fabs(a - b) > 0.1f * std::fmax(a, b); };
    if (step == 6) {
      // No tiles yet.
      EXPECT_FALSE(differ(l00, l01)) << l00 << " vs " << l01;
      EXPECT_FALSE(differ(l00, l10)) << l00 << " vs " << l10;
      continue;
    }
    // Neighbours along either tile axis differ, diagonal neighbours match.
    EXPECT_TRUE(differ(l00, l01)) << l00 << " vs " << l01;
    EXPECT_TRUE(differ(l01, l02)) << l01 << " vs " << l02;
    EXPECT_TRUE(differ(l00, l10)) << l00 << " vs " << l10;
    EXPECT_TRUE(differ(l10, l11)) << l10 << " vs " << l11;
    EXPECT_FALSE(differ(l00, l02)) << l00 << " vs " << l02;
    EXPECT_FALSE(differ(l00, l11)) << l00 << " vs " << l11;
    EXPECT_FALSE(differ(l01, l10)) << l01 << " vs " << l10;
  }
}

TEST(TutorialStep8, RustNoiseVariesAcrossBoxTop) {
  const float rusty = LumaVariance(BoxTopSamples(Rendered(8)));
  const float plain = LumaVariance(BoxTopSamples(Rendered(7)));
  EXPECT_GT(rusty, 1e-3f);
  EXPECT_GT(rusty, 10.0f * plain) << "rusty " << rusty << ", plain " << plain;
}

TEST(TutorialStep9, ConvexHullVisible) {
  const Rgb with = AtWorld(Rendered(9), kChullCenter);
  const Rgb without = AtWorld(Rendered(8), kChullCenter);
  EXPECT_GT(MaxAbsDiff(with, without), 0.05f) << with << " vs step 8 " << without;
}

TEST(TutorialStep10, GlassShadowLighterThanOpaqueShadows) {
  const Rgb glass_shadow = AtWorld(Rendered(10), kFloorInChullShadow);
  const Rgb box_shadow = AtWorld(Rendered(10), kFloorInBoxShadow);
  const Rgb opaque_chull_shadow = AtWorld(Rendered(9), kFloorInChullShadow);
  EXPECT_GT(glass_shadow.Luma(), box_shadow.Luma() + 0.05f)
      << glass_shadow << " vs box shadow " << box_shadow;
  EXPECT_GT(glass_shadow.Luma(), opaque_chull_shadow.Luma() + 0.05f)
      << glass_shadow << " vs step 9 " << opaque_chull_shadow;
}

TEST(TutorialStep11, EnvironmentCameraSeesTheSkyAtTheTopAndTheFloorBelow) {
  // The top row looks along the camera's up vector, into the blue sky of the environment map
  // (samples/tutorial/make_sky.cc); the bottom row looks down at the floor, which is not blue.
  const Image& image = Rendered(11);
  for (float fx : {0.1f, 0.5f, 0.9f}) {
    const Rgb up = At(image, fx, 0.0f);
    EXPECT_GT(up.b, up.r + 0.3f) << up << " at x fraction " << fx;
    EXPECT_GT(up.b, up.g + 0.1f) << up << " at x fraction " << fx;
    const Rgb down = At(image, fx, 0.99f);
    EXPECT_LT(down.b, down.r) << down << " at x fraction " << fx;
  }
}

TEST(TutorialCamera, ProjectsLookatToImageCenter) {
  float fx = 0.0f;
  float fy = 0.0f;
  Project(TutorialCamera().lookat, &fx, &fy);
  EXPECT_NEAR(fx, 0.5f, 1e-5f);
  EXPECT_NEAR(fy, 0.5f, 1e-5f);
}

}  // namespace
}  // namespace tessera::tutorial::testing

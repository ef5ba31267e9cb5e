// glTF animation sampling through SceneFile::FrameAt: each interpolation at and between keys,
// and clamped outside the keys.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

#include "scene/scene.h"
#include "scene_files.h"
#include "test_util.h"

namespace tessera::render::testing {
namespace {

using ::testing::HasSubstr;

const std::vector<float> kTriangle = {0, 0, 0, 1, 0, 0, 0, 1, 0};
const float kHalfSqrt2 = std::sqrt(0.5f);

// One animated node per interpolation, each with a mesh so that its transform shows in the
// frame's instances (in this order).
class RenderSceneGltfAnimationTest : public ::testing::Test {
 protected:
  enum Node { kLinearTranslation, kStepScale, kSlerpRotation, kCubicTranslation, kCubicRotation };

  void SetUp() override {
    GltfBuilder gltf;
    for (const char* name : {"Linear", "Step", "Slerp", "Cubic", "CubicRotation"}) {
      gltf.AddRoot(gltf.AddTriangleMeshNode(name, kTriangle));
    }
    nlohmann::json samplers, channels;
    auto animate = [&](int node, const char* path, const char* interpolation,
                       const std::vector<float>& times, const std::vector<float>& values) {
      const char* type = std::string(path) == "rotation" ? "VEC4" : "VEC3";
      samplers.push_back({{"input", gltf.AddFloats(times, "SCALAR")},
                          {"output", gltf.AddFloats(values, type)},
                          {"interpolation", interpolation}});
      channels.push_back(
          {{"sampler", samplers.size() - 1}, {"target", {{"node", node}, {"path", path}}}});
    };
    animate(kLinearTranslation, "translation", "LINEAR", {0.5f, 1.5f, 3.5f},
            {0, 0, 0, 10, 0, 0, 10, 20, 0});
    animate(kStepScale, "scale", "STEP", {1, 2}, {1, 1, 1, 3, 3, 3});
    // Identity to 90 degrees about +Y.
    animate(kSlerpRotation, "rotation", "LINEAR", {0.5f, 1.5f},
            {0, 0, 0, 1, 0, kHalfSqrt2, 0, kHalfSqrt2});
    // Per key: in-tangent, value, out-tangent. The tangents outside [0, 2] must not matter.
    animate(kCubicTranslation, "translation", "CUBICSPLINE", {0, 2},
            {9, 9, 9, 0, 0, 0, 1, 0, 0, /**/ 3, 0, 0, 4, 0, 0, 9, 9, 9});
    // Zero tangents: the Hermite blend of two unit quaternions is not unit until normalized.
    animate(kCubicRotation, "rotation", "CUBICSPLINE", {0, 1},
            {0,      0, 0, 0, 0, 0,          0, 1,          0, 0, 0, 0,
             /**/ 0, 0, 0, 0, 0, kHalfSqrt2, 0, kHalfSqrt2, 0, 0, 0, 0});
    gltf.json["animations"] = {
        {{"name", "Everything"}, {"samplers", samplers}, {"channels", channels}}};
    const std::string dir = MakeTempDir();
    gltf.WriteGltf(dir + "/animated.gltf");
    scene_ = OpenOrFail(dir + "/animated.gltf");
    ASSERT_NE(scene_, nullptr);
  }

  Affine At(double time, Node node) const {
    const Frame frame = scene_->FrameAt(time);
    EXPECT_EQ(frame.time, time);
    EXPECT_EQ(frame.instances.size(), 5u);
    return frame.instances.at(node).to_world;
  }
  // The translation column of a node's world transform.
  std::array<float, 3> Translation(double time, Node node) const {
    const Affine m = At(time, node);
    return {m[3], m[7], m[11]};
  }

  std::unique_ptr<SceneFile> scene_;
};

TEST_F(RenderSceneGltfAnimationTest, TimeRangeSpansEveryAnimationInput) {
  EXPECT_EQ(scene_->time_begin(), 0.0);
  EXPECT_EQ(scene_->time_end(), 3.5);
}

TEST_F(RenderSceneGltfAnimationTest, NanTimeTakesTheFirstKeys) {
  const Frame frame = scene_->FrameAt(std::nan(""));
  ASSERT_EQ(frame.instances.size(), 5u);
  const Affine& m = frame.instances[kCubicTranslation].to_world;
  EXPECT_EQ(m[3], 0.f);
  EXPECT_EQ(frame.instances[kStepScale].to_world[0], 1.f);
}

TEST_F(RenderSceneGltfAnimationTest, LinearTranslationAtBetweenAndOutsideKeys) {
  using T = std::array<float, 3>;
  EXPECT_EQ(Translation(0.5, kLinearTranslation), (T{0, 0, 0}));
  EXPECT_EQ(Translation(1.5, kLinearTranslation), (T{10, 0, 0}));
  EXPECT_EQ(Translation(3.5, kLinearTranslation), (T{10, 20, 0}));
  EXPECT_EQ(Translation(1.0, kLinearTranslation), (T{5, 0, 0}));
  EXPECT_EQ(Translation(2.5, kLinearTranslation), (T{10, 10, 0}));
  EXPECT_EQ(Translation(0.0, kLinearTranslation), (T{0, 0, 0}));    // before the first key
  EXPECT_EQ(Translation(100, kLinearTranslation), (T{10, 20, 0}));  // after the last
}

TEST_F(RenderSceneGltfAnimationTest, StepHoldsEachKeyUntilTheNext) {
  EXPECT_FLOAT_EQ(At(0.0, kStepScale)[0], 1.f);
  EXPECT_FLOAT_EQ(At(1.0, kStepScale)[0], 1.f);
  EXPECT_FLOAT_EQ(At(1.99, kStepScale)[0], 1.f);
  EXPECT_FLOAT_EQ(At(2.0, kStepScale)[0], 3.f);
  EXPECT_FLOAT_EQ(At(9.0, kStepScale)[10], 3.f);
}

TEST_F(RenderSceneGltfAnimationTest, LinearRotationIsSlerpNotNormalizedLerp) {
  // A quarter of the way from 0 to 90 degrees about +Y: 22.5 degrees. Normalized lerp of the
  // quaternions would give 21.6 degrees (cos 0.9298).
  const float angle = 22.5f * static_cast<float>(M_PI) / 180.f;
  ExpectAffineNear(At(0.75, kSlerpRotation), {std::cos(angle), 0, std::sin(angle), 0, 0, 1, 0, 0,
                                              -std::sin(angle), 0, std::cos(angle), 0});
  ExpectAffineNear(At(1.5, kSlerpRotation), {0, 0, 1, 0, 0, 1, 0, 0, -1, 0, 0, 0});
  ExpectAffineNear(At(0.0, kSlerpRotation), {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0});
  ExpectAffineNear(At(7.0, kSlerpRotation), {0, 0, 1, 0, 0, 1, 0, 0, -1, 0, 0, 0});
}

TEST_F(RenderSceneGltfAnimationTest, CubicSplineFollowsTheHermiteBasisWithScaledTangents) {
  // Keys at 0 and 2 (interval 2): value 0, out-tangent 1; value 4, in-tangent 3.
  // s = 0.5: 0.5 * 0 + 0.125 * 2 * 1 + 0.5 * 4 - 0.125 * 2 * 3 = 1.5.
  EXPECT_NEAR(Translation(1.0, kCubicTranslation)[0], 1.5f, 1e-6f);
  // s = 0.25: 0.140625 * 2 * 1 + 0.15625 * 4 - 0.046875 * 2 * 3 = 0.625.
  EXPECT_NEAR(Translation(0.5, kCubicTranslation)[0], 0.625f, 1e-6f);
  EXPECT_FLOAT_EQ(Translation(0.0, kCubicTranslation)[0], 0.f);
  EXPECT_FLOAT_EQ(Translation(2.0, kCubicTranslation)[0], 4.f);
  EXPECT_FLOAT_EQ(Translation(3.0, kCubicTranslation)[0], 4.f);
  EXPECT_FLOAT_EQ(Translation(1.0, kCubicTranslation)[1], 0.f);
}

TEST_F(RenderSceneGltfAnimationTest, CubicSplineRotationIsNormalized) {
  // Halfway with zero tangents: (identity + 90 degrees) / 2, normalized: exactly 45 degrees, a
  // rotation (no shrinking) only if normalized.
  const float c = kHalfSqrt2;
  ExpectAffineNear(At(0.5, kCubicRotation), {c, 0, c, 0, 0, 1, 0, 0, -c, 0, c, 0});
}

TEST(RenderSceneGltfAnimationErrorTest, KeysOutOfOrderAndMissingOutputsAreErrors) {
  for (bool out_of_order : {true, false}) {
    GltfBuilder gltf;
    gltf.AddRoot(gltf.AddTriangleMeshNode("Mover", kTriangle));
    const std::vector<float> times =
        out_of_order ? std::vector<float>{0, 2, 1} : std::vector<float>{0, 1, 2};
    const std::vector<float> values = out_of_order ? std::vector<float>{0, 0, 0, 1, 1, 1, 2, 2, 2}
                                                   : std::vector<float>{0, 0, 0, 1, 1, 1};
    gltf.json["animations"] = {
        {{"samplers",
          {{{"input", gltf.AddFloats(times, "SCALAR")},
            {"output", gltf.AddFloats(values, "VEC3")}}}},
         {"channels", {{{"sampler", 0}, {"target", {{"node", 0}, {"path", "translation"}}}}}}}};
    const std::string dir = MakeTempDir();
    gltf.WriteGltf(dir + "/bad_keys.gltf");
    absl::StatusOr<std::unique_ptr<SceneFile>> scene = SceneFile::Open(dir + "/bad_keys.gltf");
    ASSERT_FALSE(scene.ok());
    EXPECT_EQ(scene.status().code(), absl::StatusCode::kInvalidArgument);
    EXPECT_THAT(scene.status().message(), HasSubstr("bad_keys.gltf: animation 0 '' channel 0"));
    EXPECT_THAT(scene.status().message(),
                HasSubstr(out_of_order ? "key 2 at 1 s comes before key 1 at 2 s"
                                       : "3 key times but 2 output values"));
  }
}

}  // namespace
}  // namespace tessera::render::testing

// Assertions shared by the scene loader tests.
#ifndef TESSERA_TESTS_RENDER_SCENE_TEST_UTIL_H_
#define TESSERA_TESTS_RENDER_SCENE_TEST_UTIL_H_

#include <gtest/gtest.h>

#include <array>
#include <memory>
#include <string>

#include "scene/scene.h"

namespace tessera::render::testing {

// Opens `path`, failing the test (with the loader's message) when it does not load.
inline std::unique_ptr<SceneFile> OpenOrFail(const std::string& path) {
  absl::StatusOr<std::unique_ptr<SceneFile>> scene = SceneFile::Open(path);
  EXPECT_TRUE(scene.ok()) << scene.status();
  return scene.ok() ? *std::move(scene) : nullptr;
}

inline void ExpectAffineNear(const Affine& actual, const std::array<float, 12>& expected,
                             float tolerance = 1e-5f) {
  for (int i = 0; i < 12; ++i) {
    EXPECT_NEAR(actual[i], expected[i], tolerance) << "element " << i;
  }
}

}  // namespace tessera::render::testing

#endif  // TESSERA_TESTS_RENDER_SCENE_TEST_UTIL_H_

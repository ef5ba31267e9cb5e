// Helpers for the tutorial image tests: cached renders and pixel lookups by image fraction or
// by projecting a world point through the tutorial camera.
#ifndef TESSERA_TESTS_TUTORIAL_TUTORIAL_TEST_UTIL_H_
#define TESSERA_TESTS_TUTORIAL_TUTORIAL_TEST_UTIL_H_

#include <optixu/optixu_vector_types.h>

#include <ostream>

#include "tutorial/image.h"

namespace tessera::tutorial::testing {

// Small enough to stay fast on two cores, large enough for the features the tests look at.
inline constexpr int kWidth = 160;
inline constexpr int kHeight = 120;

// Renders `step` at kWidth x kHeight once per process.
const Image& Rendered(int step);

struct Rgb {
  float r, g, b;
  float Luma() const { return 0.30f * r + 0.59f * g + 0.11f * b; }
};
std::ostream& operator<<(std::ostream& os, const Rgb& c);

// The pixel at fractions (fx, fy) of width and height, from the top-left corner.
Rgb At(const Image& image, float fx, float fy);

// The pixel where world point `p` appears. Fails the test if it lands outside the image.
Rgb AtWorld(const Image& image, const float3& p);

// Image fractions where `p` appears (through the tutorial camera, at kWidth/kHeight).
void Project(const float3& p, float* fx, float* fy);

// The point of the floor plane that the camera ray of pixel At(fx, fy) hits, and that ray's
// origin (the eye).
float3 FloorPointAt(float fx, float fy);
float3 Eye();

}  // namespace tessera::tutorial::testing

#endif  // TESSERA_TESTS_TUTORIAL_TUTORIAL_TEST_UTIL_H_

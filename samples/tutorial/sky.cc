#include "tutorial/sky.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace tessera::tutorial {
namespace {

constexpr float kPi = 3.14159265358979f;

struct Rgb {
  float r, g, b;
};

Rgb Mix(Rgb a, Rgb b, float t) {
  return {a.r + (b.r - a.r) * t, a.g + (b.g - a.g) * t, a.b + (b.b - a.b) * t};
}

float Smoothstep(float e0, float e1, float x) {
  const float t = std::clamp((x - e0) / (e1 - e0), 0.0f, 1.0f);
  return t * t * (3 - 2 * t);
}

// Radiance arriving from direction (x, y, z), y up.
Rgb Sky(float x, float y, float z) {
  const Rgb zenith = {0.34f, 0.55f, 0.85f};  // the tutorial's bg_color
  const Rgb horizon = {0.85f, 0.88f, 0.92f};
  const Rgb ground = {0.3f, 0.28f, 0.25f};
  Rgb c = y >= 0 ? Mix(horizon, zenith, Smoothstep(0.0f, 0.6f, y))
                 : Mix(horizon, ground, Smoothstep(0.0f, 0.5f, -y));
  // A sun high in the sky behind the camera's left shoulder, with a glow around it.
  const float sx = -0.45f, sy = 0.75f, sz = 0.48f;
  const float norm = std::sqrt(sx * sx + sy * sy + sz * sz);
  const float cos_angle = std::max(0.0f, (x * sx + y * sy + z * sz) / norm);
  const float sun = 40.0f * std::pow(cos_angle, 4000.0f) + 0.6f * std::pow(cos_angle, 64.0f);
  if (y > -0.02f) c = {c.r + sun, c.g + sun * 0.95f, c.b + sun * 0.85f};
  return c;
}

}  // namespace

std::vector<float> SkyPixels() {
  std::vector<float> pixels(size_t{kSkyWidth} * kSkyHeight * 3);
  for (int row = 0; row < kSkyHeight; ++row) {
    const float y = 1.0f - 2.0f * (static_cast<float>(row) + 0.5f) / kSkyHeight;  // top row: zenith
    const float ring = std::sqrt(std::max(0.0f, 1.0f - y * y));
    for (int col = 0; col < kSkyWidth; ++col) {
      const float theta = 2.0f * kPi * (static_cast<float>(col) + 0.5f) / kSkyWidth - kPi;
      const Rgb c = Sky(std::sin(theta) * ring, y, std::cos(theta) * ring);
      float* p = &pixels[(static_cast<size_t>(row) * kSkyWidth + col) * 3];
      p[0] = c.r;
      p[1] = c.g;
      p[2] = c.b;
    }
  }
  return pixels;
}

}  // namespace tessera::tutorial

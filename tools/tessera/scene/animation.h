// Keyframe sampling of node translation, rotation and scale, as glTF 2.0 defines it (Appendix C
// of the specification: LINEAR, STEP, CUBICSPLINE; rotations by slerp and normalized).
#ifndef TESSERA_TOOLS_TESSERA_SCENE_ANIMATION_H_
#define TESSERA_TOOLS_TESSERA_SCENE_ANIMATION_H_

#include <string>
#include <vector>

#include "absl/status/status.h"

namespace tessera::render {

enum class Interpolation { kLinear, kStep, kCubicSpline };
enum class AnimatedProperty { kTranslation, kRotation, kScale };

// One property of one node over time: a glTF animation channel with its sampler's keys.
struct AnimationChannel {
  int node = 0;  // into the scene's nodes (SceneNode), not the file's
  AnimatedProperty property = AnimatedProperty::kTranslation;
  Interpolation interpolation = Interpolation::kLinear;
  std::vector<float> times;  // seconds, non-decreasing, at least one
  // Width() floats per key; CUBICSPLINE: in-tangent, value, out-tangent per key.
  std::vector<float> values;

  int Width() const { return property == AnimatedProperty::kRotation ? 4 : 3; }
};

// OK when `channel` can be sampled: keys exist, times are finite and non-decreasing, and values
// hold as many keys as times. Messages start with `what`.
absl::Status ValidateChannel(const AnimationChannel& channel, const std::string& what);

// The property's value at `time`, clamped to the channel's first and last keys. `out` receives
// Width() values; rotations are unit quaternions (x, y, z, w).
void SampleChannel(const AnimationChannel& channel, double time, double* out);

}  // namespace tessera::render

#endif  // TESSERA_TOOLS_TESSERA_SCENE_ANIMATION_H_

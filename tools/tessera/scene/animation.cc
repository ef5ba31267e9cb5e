#include "animation.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "absl/strings/str_cat.h"
#include "transform.h"

namespace tessera::render {
namespace {

// Where key k's value starts in `values`: CUBICSPLINE keys carry tangents either side.
size_t ValueAt(const AnimationChannel& c, size_t key) {
  const size_t width = static_cast<size_t>(c.Width());
  return c.interpolation == Interpolation::kCubicSpline ? (key * 3 + 1) * width : key * width;
}

void CopyKey(const AnimationChannel& c, size_t key, double* out) {
  const size_t at = ValueAt(c, key);
  for (int i = 0; i < c.Width(); ++i) out[i] = c.values[at + i];
}

std::array<double, 4> Quaternion(const float* q) { return {q[0], q[1], q[2], q[3]}; }

}  // namespace

absl::Status ValidateChannel(const AnimationChannel& c, const std::string& what) {
  if (c.times.empty()) return absl::InvalidArgumentError(absl::StrCat(what, ": no keyframes"));
  for (size_t k = 0; k < c.times.size(); ++k) {
    if (!std::isfinite(c.times[k])) {
      return absl::InvalidArgumentError(absl::StrCat(what, ": key ", k, " has no finite time"));
    }
    if (k > 0 && c.times[k] < c.times[k - 1]) {
      return absl::InvalidArgumentError(absl::StrCat(what, ": key ", k, " at ", c.times[k],
                                                     " s comes before key ", k - 1, " at ",
                                                     c.times[k - 1], " s"));
    }
  }
  const size_t per_key =
      static_cast<size_t>(c.Width()) * (c.interpolation == Interpolation::kCubicSpline ? 3 : 1);
  if (c.values.size() != c.times.size() * per_key) {
    return absl::InvalidArgumentError(
        absl::StrCat(what, ": ", c.times.size(), " key times but ", c.values.size() / c.Width(),
                     " output values (expected ", c.times.size() * per_key / c.Width(), ")"));
  }
  return absl::OkStatus();
}

void SampleChannel(const AnimationChannel& c, double time, double* out) {
  const size_t last = c.times.size() - 1;
  // Negated, so that a NaN time takes the first key instead of reaching the search below with a
  // value every comparison rejects.
  if (!(time > c.times.front())) return CopyKey(c, 0, out);
  if (time >= c.times[last]) return CopyKey(c, last, out);
  // times[k] <= time < times[k + 1]; both exist since time lies strictly inside the range.
  const size_t k = static_cast<size_t>(std::upper_bound(c.times.begin(), c.times.end(), time) -
                                       c.times.begin()) -
                   1;
  const double t0 = c.times[k], t1 = c.times[k + 1];
  const double dt = t1 - t0;
  // upper_bound skips keys of equal time, so dt > 0 here; the check keeps a division safe anyway.
  const double s = dt > 0.0 ? (time - t0) / dt : 1.0;
  const int width = c.Width();
  const float* a = &c.values[ValueAt(c, k)];
  const float* b = &c.values[ValueAt(c, k + 1)];

  switch (c.interpolation) {
    case Interpolation::kStep:
      return CopyKey(c, k, out);
    case Interpolation::kLinear:
      if (c.property == AnimatedProperty::kRotation) {
        const std::array<double, 4> q =
            Slerp(NormalizeQuaternion(Quaternion(a)), NormalizeQuaternion(Quaternion(b)), s);
        std::copy(q.begin(), q.end(), out);
        return;
      }
      for (int i = 0; i < width; ++i) out[i] = a[i] + s * (b[i] - a[i]);
      return;
    case Interpolation::kCubicSpline: {
      // Hermite spline, the tangents scaled by the key interval (glTF 2.0, Appendix C).
      const float* out_tangent = a + width;  // key k's out-tangent follows its value
      const float* in_tangent = b - width;   // key k+1's in-tangent precedes its value
      const double s2 = s * s, s3 = s2 * s;
      const double h00 = 2 * s3 - 3 * s2 + 1, h10 = s3 - 2 * s2 + s;
      const double h01 = -2 * s3 + 3 * s2, h11 = s3 - s2;
      for (int i = 0; i < width; ++i) {
        out[i] = h00 * a[i] + h10 * dt * out_tangent[i] + h01 * b[i] + h11 * dt * in_tangent[i];
      }
      if (c.property == AnimatedProperty::kRotation) {
        const std::array<double, 4> q = NormalizeQuaternion({out[0], out[1], out[2], out[3]});
        std::copy(q.begin(), q.end(), out);
      }
      return;
    }
  }
}

}  // namespace tessera::render

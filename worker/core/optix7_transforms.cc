#include "optix7_transforms.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "absl/strings/str_cat.h"
#include "optix_types.h"

namespace tessera::worker {

bool Optix7Motion::Vanished(float time) const {
  if (keys < 2) return false;
  return ((flags & OPTIX_MOTION_FLAG_START_VANISH) && time < begin) ||
         ((flags & OPTIX_MOTION_FLAG_END_VANISH) && time > end);
}

float Optix7Motion::Normalized(float time) const {
  if (keys < 2 || !(end > begin)) return 0.f;
  const float n = (time - begin) / (end - begin);
  return n <= 0.f ? 0.f : n >= 1.f ? 1.f : n;
}

void Compose(const float a[12], const float b[12], float c[12]) {
  float out[12];
  for (int r = 0; r < 3; ++r) {
    for (int k = 0; k < 4; ++k) {
      out[r * 4 + k] = a[r * 4] * b[k] + a[r * 4 + 1] * b[4 + k] + a[r * 4 + 2] * b[8 + k] +
                       (k == 3 ? a[r * 4 + 3] : 0.f);
    }
  }
  std::memcpy(c, out, sizeof(out));
}

void InvertAffine(const float m[12], float out[12]) {
  const double a = m[0], b = m[1], c = m[2], d = m[4], e = m[5], f = m[6], g = m[8], h = m[9],
               i = m[10];
  const double co[9] = {e * i - f * h, c * h - b * i, b * f - c * e, f * g - d * i, a * i - c * g,
                        c * d - a * f, d * h - e * g, b * g - a * h, a * e - b * d};
  const double det = a * co[0] + b * co[3] + c * co[6];
  if (det == 0) {
    std::memset(out, 0, 12 * sizeof(float));
    return;
  }
  const double t[3] = {m[3], m[7], m[11]};
  for (int r = 0; r < 3; ++r) {
    double translation = 0;
    for (int k = 0; k < 3; ++k) {
      out[r * 4 + k] = static_cast<float>(co[r * 3 + k] / det);
      translation -= co[r * 3 + k] / det * t[k];
    }
    out[r * 4 + 3] = static_cast<float>(translation);
  }
}

namespace {

// The two keys around `time` and the fraction between them (guide 5.10.1: keys evenly spaced,
// time clamped to the range).
void Keys(const Optix7Motion& m, float time, uint32_t& k, float& f) {
  const float s = m.Normalized(time) * static_cast<float>(m.keys - 1);
  k = std::min(static_cast<uint32_t>(s), m.keys - 2);
  f = s - static_cast<float>(k);
}

// OptixSRTData (sx, a, b, pvx, sy, c, pvy, sz, pvz, qx, qy, qz, qw, tx, ty, tz) as C = T * R * S
// (guide 5.10.5), the quaternion normalized.
void SrtMatrix(const float v[16], float out[12]) {
  const float sx = v[0], a = v[1], b = v[2], pvx = v[3], sy = v[4], c = v[5], pvy = v[6], sz = v[7],
              pvz = v[8];
  float qx = v[9], qy = v[10], qz = v[11], qw = v[12];
  const float n = std::sqrt(qx * qx + qy * qy + qz * qz + qw * qw);
  if (n > 0.f) {
    qx /= n;
    qy /= n;
    qz /= n;
    qw /= n;
  }
  const float r[9] = {
      1 - 2 * (qy * qy + qz * qz), 2 * (qx * qy - qz * qw),     2 * (qx * qz + qy * qw),
      2 * (qx * qy + qz * qw),     1 - 2 * (qx * qx + qz * qz), 2 * (qy * qz - qx * qw),
      2 * (qx * qz - qy * qw),     2 * (qy * qz + qx * qw),     1 - 2 * (qx * qx + qy * qy)};
  const float s[12] = {sx, a, b, pvx, 0, sy, c, pvy, 0, 0, sz, pvz};
  const float rt[12] = {r[0], r[1], r[2], v[13], r[3], r[4], r[5], v[14], r[6], r[7], r[8], v[15]};
  Compose(rt, s, out);
}

}  // namespace

void Optix7Transform::At(float time, float to_world[12], float to_object[12]) const {
  if (type == OPTIX_TRANSFORM_TYPE_STATIC_TRANSFORM) {
    // OptiX takes both matrices from the application; so does the engine.
    std::memcpy(to_world, data.data(), 12 * sizeof(float));
    std::memcpy(to_object, data.data() + 12, 12 * sizeof(float));
    return;
  }
  uint32_t k;
  float f;
  Keys(motion, time, k, f);
  if (type == OPTIX_TRANSFORM_TYPE_MATRIX_MOTION_TRANSFORM) {
    const float* a = data.data() + 12 * k;
    for (int i = 0; i < 12; ++i) to_world[i] = (1.f - f) * a[i] + f * a[12 + i];
  } else {
    const float* a = data.data() + 16 * k;
    float v[16];
    for (int i = 0; i < 16; ++i) v[i] = (1.f - f) * a[i] + f * a[16 + i];
    SrtMatrix(v, to_world);
  }
  InvertAffine(to_world, to_object);
}

absl::StatusOr<Optix7Transform> ReadTransform(uint64_t handle, size_t readable) {
  Optix7Transform t;
  t.handle = handle;
  t.type = TransformTag(handle);
  const uint64_t address = TransformAddress(handle);
  const auto* bytes = reinterpret_cast<const unsigned char*>(address);
  size_t need = 0;
  switch (t.type) {
    case OPTIX_TRANSFORM_TYPE_STATIC_TRANSFORM:
      need = sizeof(OptixStaticTransform);
      break;
    case OPTIX_TRANSFORM_TYPE_MATRIX_MOTION_TRANSFORM:
    case OPTIX_TRANSFORM_TYPE_SRT_MOTION_TRANSFORM:
      need = 32;  // child and motion options first
      break;
    default:
      return absl::InvalidArgumentError(
          absl::StrCat("traversable handle 0x", absl::Hex(handle), " is no transform"));
  }
  if (readable < need) {
    return absl::InvalidArgumentError(absl::StrCat("transform traversable 0x", absl::Hex(handle),
                                                   " does not lie in device memory"));
  }
  std::memcpy(&t.child, bytes, sizeof(t.child));
  if (t.type == OPTIX_TRANSFORM_TYPE_STATIC_TRANSFORM) {
    t.data.resize(24);
    std::memcpy(t.data.data(), bytes + offsetof(OptixStaticTransform, transform),
                24 * sizeof(float));
    return t;
  }
  OptixMotionOptions mo;
  std::memcpy(&mo, bytes + 8, sizeof(mo));
  if (mo.numKeys < 2 || !(mo.timeBegin < mo.timeEnd)) {
    return absl::InvalidArgumentError(
        absl::StrCat("motion transform 0x", absl::Hex(handle), ": motionOptions of ", mo.numKeys,
                     " keys from time ", mo.timeBegin, " to ", mo.timeEnd,
                     " (a motion transform needs two keys or more and timeBegin < timeEnd)"));
  }
  t.motion = Optix7Motion{mo.numKeys, mo.flags, mo.timeBegin, mo.timeEnd};
  const size_t per_key = t.type == OPTIX_TRANSFORM_TYPE_MATRIX_MOTION_TRANSFORM ? 12 : 16;
  need = 32 + per_key * sizeof(float) * mo.numKeys;
  if (readable < need) {
    return absl::InvalidArgumentError(
        absl::StrCat("motion transform 0x", absl::Hex(handle), " of ", mo.numKeys, " keys needs ",
                     need, " bytes of device memory, ", readable, " are there"));
  }
  t.data.resize(per_key * mo.numKeys);
  std::memcpy(t.data.data(), bytes + 32, t.data.size() * sizeof(float));
  return t;
}

}  // namespace tessera::worker

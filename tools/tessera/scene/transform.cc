#include "transform.h"

#include <cmath>

namespace tessera::render {

AffineD IdentityAffine() { return {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0}; }

AffineD Compose(const AffineD& a, const AffineD& b) {
  AffineD r{};
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 4; ++j) {
      double v = j == 3 ? a[i * 4 + 3] : 0.0;
      for (int k = 0; k < 3; ++k) v += a[i * 4 + k] * b[k * 4 + j];
      r[i * 4 + j] = v;
    }
  }
  return r;
}

std::array<double, 4> NormalizeQuaternion(const std::array<double, 4>& q) {
  const double length = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  if (!(length > 0.0) || !std::isfinite(length)) return {0.0, 0.0, 0.0, 1.0};
  return {q[0] / length, q[1] / length, q[2] / length, q[3] / length};
}

AffineD TrsToAffine(const Trs& trs) {
  const auto [x, y, z, w] = NormalizeQuaternion(trs.rotation);
  const double r[3][3] = {
      {1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)},
      {2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)},
      {2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)},
  };
  AffineD m{};
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) m[i * 4 + j] = r[i][j] * trs.scale[j];
    m[i * 4 + 3] = trs.translation[i];
  }
  return m;
}

AffineD ColumnMajorToAffine(const double* m16) {
  AffineD m{};
  for (int row = 0; row < 3; ++row) {
    for (int col = 0; col < 4; ++col) m[row * 4 + col] = m16[col * 4 + row];
  }
  return m;
}

Affine ToFloat(const AffineD& m) {
  Affine f{};
  for (int i = 0; i < 12; ++i) f[i] = static_cast<float>(m[i]);
  return f;
}

std::array<double, 3> TransformPoint(const AffineD& m, const std::array<double, 3>& p) {
  std::array<double, 3> r{};
  for (int i = 0; i < 3; ++i) {
    r[i] = m[i * 4] * p[0] + m[i * 4 + 1] * p[1] + m[i * 4 + 2] * p[2] + m[i * 4 + 3];
  }
  return r;
}

std::array<double, 4> Slerp(const std::array<double, 4>& a, const std::array<double, 4>& b,
                            double t) {
  std::array<double, 4> to = b;
  double cosine = a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3];
  // q and -q are the same rotation; the shorter arc is the one of positive dot product.
  if (cosine < 0.0) {
    cosine = -cosine;
    for (double& c : to) c = -c;
  }
  double wa = 1.0 - t, wb = t;
  // Nearly equal rotations: sin(angle) is too small to divide by, and lerp is as good.
  if (cosine < 0.9995) {
    const double angle = std::acos(cosine);
    const double sine = std::sin(angle);
    wa = std::sin((1.0 - t) * angle) / sine;
    wb = std::sin(t * angle) / sine;
  }
  std::array<double, 4> r{};
  for (int i = 0; i < 4; ++i) r[i] = wa * a[i] + wb * to[i];
  return NormalizeQuaternion(r);
}

}  // namespace tessera::render

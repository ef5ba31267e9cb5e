#include "matrix4.h"

#include <cmath>
#include <utility>

namespace tessera::api {

Matrix4 IdentityMatrix4() {
  Matrix4 m{};
  m[0] = m[5] = m[10] = m[15] = 1.0f;
  return m;
}

Matrix4 Transpose(const Matrix4& m) {
  Matrix4 t;
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) t[c * 4 + r] = m[r * 4 + c];
  }
  return t;
}

bool Invert(const Matrix4& m, Matrix4* out) {
  // Gauss-Jordan with partial pivoting, in double so that near-singular scales stay accurate.
  double a[4][8];
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) {
      if (!std::isfinite(m[r * 4 + c])) return false;
      a[r][c] = m[r * 4 + c];
      a[r][c + 4] = r == c ? 1.0 : 0.0;
    }
  }
  double scale = 0.0;
  for (float v : m) scale = std::fmax(scale, std::fabs(v));
  if (scale == 0.0) return false;
  for (int col = 0; col < 4; ++col) {
    int pivot = col;
    for (int r = col + 1; r < 4; ++r) {
      if (std::fabs(a[r][col]) > std::fabs(a[pivot][col])) pivot = r;
    }
    if (std::fabs(a[pivot][col]) <= 1e-12 * scale) return false;
    if (pivot != col) std::swap(a[pivot], a[col]);
    double inv = 1.0 / a[col][col];
    for (double& v : a[col]) v *= inv;
    for (int r = 0; r < 4; ++r) {
      if (r == col) continue;
      double f = a[r][col];
      if (f == 0.0) continue;
      for (int c = 0; c < 8; ++c) a[r][c] -= f * a[col][c];
    }
  }
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) (*out)[r * 4 + c] = static_cast<float>(a[r][c + 4]);
  }
  return true;
}

}  // namespace tessera::api

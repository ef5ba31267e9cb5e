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
  // Rows, then columns, scaled by powers of two to a largest magnitude in [1, 2) (equilibration,
  // as LAPACK's dgeequ): singularity is then judged whatever the units, so that a translation by
  // 1e13 or a scale by 1e-20, both exactly invertible, are not taken for singular. With
  // A = R * m * C, m^-1 = C * A^-1 * R.
  double row_scale[4], col_scale[4];
  for (int r = 0; r < 4; ++r) {
    double big = 0.0;
    for (int c = 0; c < 4; ++c) {
      if (!std::isfinite(m[r * 4 + c])) return false;
      big = std::fmax(big, std::fabs(m[r * 4 + c]));
    }
    if (big == 0.0) return false;  // a zero row
    row_scale[r] = std::ldexp(1.0, -std::ilogb(big));
  }
  for (int c = 0; c < 4; ++c) {
    double big = 0.0;
    for (int r = 0; r < 4; ++r) big = std::fmax(big, std::fabs(m[r * 4 + c] * row_scale[r]));
    if (big == 0.0) return false;  // a zero column
    col_scale[c] = std::ldexp(1.0, -std::ilogb(big));
  }
  // Gauss-Jordan with partial pivoting, in double so that near-singular scales stay accurate.
  double a[4][8];
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) {
      a[r][c] = m[r * 4 + c] * row_scale[r] * col_scale[c];
      a[r][c + 4] = r == c ? 1.0 : 0.0;
    }
  }
  for (int k = 0; k < 4; ++k) {
    int pivot = k;
    for (int r = k + 1; r < 4; ++r) {
      if (std::fabs(a[r][k]) > std::fabs(a[pivot][k])) pivot = r;
    }
    if (std::fabs(a[pivot][k]) <= 1e-12) return false;  // entries of A are at most 2
    if (pivot != k) std::swap(a[pivot], a[k]);
    double inv = 1.0 / a[k][k];
    for (double& v : a[k]) v *= inv;
    for (int r = 0; r < 4; ++r) {
      if (r == k) continue;
      double f = a[r][k];
      if (f == 0.0) continue;
      for (int c = 0; c < 8; ++c) a[r][c] -= f * a[k][c];
    }
  }
  Matrix4 result;
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) {
      const float v = static_cast<float>(col_scale[r] * a[r][c + 4] * row_scale[c]);
      if (!std::isfinite(v)) return false;  // the inverse does not fit in floats
      result[r * 4 + c] = v;
    }
  }
  *out = result;
  return true;
}

}  // namespace tessera::api

// optix::Matrix<M, N>: a small dense M-row, N-column float matrix as OptiX 3 programs and hosts
// use it for transforms (rtGetTransform hands out the 16 floats of a Matrix4x4).
//
// Storage is row-major, M * N floats and nothing else, so getData() can go straight to
// rtGetTransform, rtTransformSetMatrix or a buffer. Vectors are columns: m * v transforms v,
// and v * m treats v as a row. The default constructor leaves the elements uninitialized, as
// OptiX's does, which keeps Matrix trivially copyable; use identity() for a defined start.
#ifndef OPTIXU_OPTIXU_MATRIX_NAMESPACE_H_
#define OPTIXU_OPTIXU_MATRIX_NAMESPACE_H_

// clang-format off: before every other #include (see there)
#include "../tessera/detail/program_prelude.h"
// clang-format on

#include <cmath>

#include "optixu_math_namespace.h"
#include "optixu_vector_types.h"

namespace optix {

// The float vector with D components, for a matrix's rows and columns. Matrices with more than
// four rows or columns work, except for the row and column accessors of those dimensions (and
// so for explicit instantiation of the whole class).
template <unsigned int D>
struct VectorDim {
  struct NoVectorOfThisSize;  // Incomplete: using it is a compile error, declaring it is not.
  using VectorType = NoVectorOfThisSize;
};
template <>
struct VectorDim<1> {
  using VectorType = float1;
};
template <>
struct VectorDim<2> {
  using VectorType = float2;
};
template <>
struct VectorDim<3> {
  using VectorType = float3;
};
template <>
struct VectorDim<4> {
  using VectorType = float4;
};

template <unsigned int M, unsigned int N>
class Matrix {
  static_assert(M > 0 && N > 0, "a Matrix needs at least one row and one column");

 public:
  using floatN = typename VectorDim<N>::VectorType;  // A row.
  using floatM = typename VectorDim<M>::VectorType;  // A column.

  Matrix() = default;
  // Copies M * N floats, row-major.
  explicit Matrix(const float data[M * N]) {
    for (unsigned int i = 0; i < M * N; ++i) data_[i] = data[i];
  }

  // Element i of the row-major storage.
  float operator[](unsigned int i) const { return data_[i]; }
  float& operator[](unsigned int i) { return data_[i]; }
  // Element in row `row` and column `col`.
  float operator()(unsigned int row, unsigned int col) const { return data_[row * N + col]; }
  float& operator()(unsigned int row, unsigned int col) { return data_[row * N + col]; }

  float* getData() { return data_; }
  const float* getData() const { return data_; }

  floatN getRow(unsigned int m) const {
    floatN r{};
    for (unsigned int n = 0; n < N; ++n) setByIndex(r, static_cast<int>(n), data_[m * N + n]);
    return r;
  }
  floatM getCol(unsigned int n) const {
    floatM c{};
    for (unsigned int m = 0; m < M; ++m) setByIndex(c, static_cast<int>(m), data_[m * N + n]);
    return c;
  }
  void setRow(unsigned int m, const floatN& r) {
    for (unsigned int n = 0; n < N; ++n) data_[m * N + n] = getByIndex(r, static_cast<int>(n));
  }
  void setCol(unsigned int n, const floatM& c) {
    for (unsigned int m = 0; m < M; ++m) data_[m * N + n] = getByIndex(c, static_cast<int>(m));
  }

  Matrix<N, M> transpose() const {
    Matrix<N, M> t{};
    for (unsigned int m = 0; m < M; ++m) {
      for (unsigned int n = 0; n < N; ++n) t(n, m) = (*this)(m, n);
    }
    return t;
  }

  // Members that exist only for some shapes are templates on a defaulted parameter: their
  // static_asserts then fire when they are called on the wrong shape, not when someone
  // explicitly instantiates, say, Matrix<3, 3>.

  // Determinant, by cofactor expansion; square matrices up to 4x4.
  template <unsigned int R = M>
  float det() const;

  // Inverse of a square matrix, by Gauss-Jordan elimination with partial pivoting. A singular
  // matrix yields infinities and NaNs rather than an error, as on the GPU; check det() first
  // where that can happen.
  template <unsigned int R = M>
  Matrix inverse() const;

  // Ones on the diagonal, zeros elsewhere (also for non-square shapes).
  static Matrix identity() {
    Matrix r{};
    for (unsigned int m = 0; m < M; ++m) {
      for (unsigned int n = 0; n < N; ++n) r(m, n) = m == n ? 1.0f : 0.0f;
    }
    return r;
  }

  // 4x4 homogeneous transforms of column vectors.
  // Rotation by `radians` about `axis` (any length), counterclockwise when the axis points at
  // the viewer (right-handed): rotate(M_PI_2f, z) maps x to y.
  template <unsigned int R = M>
  static Matrix rotate(float radians, const float3& axis);
  template <unsigned int R = M>
  static Matrix translate(const float3& offset);
  template <unsigned int R = M>
  static Matrix scale(const float3& factors);
  // The matrix whose columns are u, v, w and the origin c: maps the frame's local coordinates to
  // the space u, v, w and c are given in.
  template <unsigned int R = M>
  static Matrix fromBasis(const float3& u, const float3& v, const float3& w, const float3& c);

  // Lexicographic on the elements, so matrices can key ordered containers.
  bool operator<(const Matrix& rhs) const {
    for (unsigned int i = 0; i < M * N; ++i) {
      if (data_[i] != rhs.data_[i]) return data_[i] < rhs.data_[i];
    }
    return false;
  }

 private:
  float data_[M * N];
};

using Matrix2x2 = Matrix<2, 2>;
using Matrix2x3 = Matrix<2, 3>;
using Matrix2x4 = Matrix<2, 4>;
using Matrix3x2 = Matrix<3, 2>;
using Matrix3x3 = Matrix<3, 3>;
using Matrix3x4 = Matrix<3, 4>;
using Matrix4x2 = Matrix<4, 2>;
using Matrix4x3 = Matrix<4, 3>;
using Matrix4x4 = Matrix<4, 4>;

// The upper-left 3x3 block of a 4x4 transform: its linear part, without the translation.
inline Matrix3x3 make_matrix3x3(const Matrix4x4& m) {
  Matrix3x3 r;
  for (unsigned int row = 0; row < 3; ++row) {
    for (unsigned int col = 0; col < 3; ++col) r(row, col) = m(row, col);
  }
  return r;
}

template <unsigned int M, unsigned int N>
template <unsigned int R>
float Matrix<M, N>::det() const {
  static_assert(R == N && N <= 4, "det() is defined for square matrices up to 4x4");
  const Matrix& a = *this;
  if constexpr (N == 1) {
    return a[0];
  } else if constexpr (N == 2) {
    return a(0, 0) * a(1, 1) - a(0, 1) * a(1, 0);
  } else if constexpr (N == 3) {
    return a(0, 0) * (a(1, 1) * a(2, 2) - a(1, 2) * a(2, 1)) -
           a(0, 1) * (a(1, 0) * a(2, 2) - a(1, 2) * a(2, 0)) +
           a(0, 2) * (a(1, 0) * a(2, 1) - a(1, 1) * a(2, 0));
  } else {
    // Laplace expansion along the first two rows: each 2x2 minor of rows 0-1 pairs with the
    // complementary 2x2 minor of rows 2-3.
    const auto minor01 = [&a](unsigned int i, unsigned int j) {
      return a(0, i) * a(1, j) - a(0, j) * a(1, i);
    };
    const auto minor23 = [&a](unsigned int i, unsigned int j) {
      return a(2, i) * a(3, j) - a(2, j) * a(3, i);
    };
    return minor01(0, 1) * minor23(2, 3) - minor01(0, 2) * minor23(1, 3) +
           minor01(0, 3) * minor23(1, 2) + minor01(1, 2) * minor23(0, 3) -
           minor01(1, 3) * minor23(0, 2) + minor01(2, 3) * minor23(0, 1);
  }
}

template <unsigned int M, unsigned int N>
template <unsigned int R>
Matrix<M, N> Matrix<M, N>::inverse() const {
  static_assert(R == N, "inverse() is defined for square matrices");
  Matrix a = *this;
  Matrix inv = identity();
  for (unsigned int col = 0; col < N; ++col) {
    // Pivot on the largest remaining entry of the column: keeps the elimination stable for
    // matrices like rotations whose diagonal can be zero.
    unsigned int pivot = col;
    for (unsigned int row = col + 1; row < N; ++row) {
      if (std::fabs(a(row, col)) > std::fabs(a(pivot, col))) pivot = row;
    }
    if (pivot != col) {
      for (unsigned int k = 0; k < N; ++k) {
        const float t = a(col, k);
        a(col, k) = a(pivot, k);
        a(pivot, k) = t;
        const float u = inv(col, k);
        inv(col, k) = inv(pivot, k);
        inv(pivot, k) = u;
      }
    }
    const float scale = 1.0f / a(col, col);
    for (unsigned int k = 0; k < N; ++k) {
      a(col, k) *= scale;
      inv(col, k) *= scale;
    }
    for (unsigned int row = 0; row < N; ++row) {
      if (row == col) continue;
      const float f = a(row, col);
      for (unsigned int k = 0; k < N; ++k) {
        a(row, k) -= f * a(col, k);
        inv(row, k) -= f * inv(col, k);
      }
    }
  }
  return inv;
}

template <unsigned int M, unsigned int N>
template <unsigned int R>
Matrix<M, N> Matrix<M, N>::rotate(float radians, const float3& axis) {
  static_assert(R == 4 && N == 4, "rotate() builds a 4x4 transform");
  const float3 a = normalize(axis);
  const float c = std::cos(radians);
  const float s = std::sin(radians);
  const float t = 1.0f - c;
  // Rodrigues' formula: c * I + s * [a]x + t * a a^T.
  // clang-format off
  const float data[16] = {
      t * a.x * a.x + c,       t * a.x * a.y - s * a.z, t * a.x * a.z + s * a.y, 0.0f,
      t * a.x * a.y + s * a.z, t * a.y * a.y + c,       t * a.y * a.z - s * a.x, 0.0f,
      t * a.x * a.z - s * a.y, t * a.y * a.z + s * a.x, t * a.z * a.z + c,       0.0f,
      0.0f,                    0.0f,                    0.0f,                    1.0f};
  // clang-format on
  return Matrix(data);
}

template <unsigned int M, unsigned int N>
template <unsigned int R>
Matrix<M, N> Matrix<M, N>::translate(const float3& offset) {
  static_assert(R == 4 && N == 4, "translate() builds a 4x4 transform");
  Matrix r = identity();
  r(0, 3) = offset.x;
  r(1, 3) = offset.y;
  r(2, 3) = offset.z;
  return r;
}

template <unsigned int M, unsigned int N>
template <unsigned int R>
Matrix<M, N> Matrix<M, N>::scale(const float3& factors) {
  static_assert(R == 4 && N == 4, "scale() builds a 4x4 transform");
  Matrix r = identity();
  r(0, 0) = factors.x;
  r(1, 1) = factors.y;
  r(2, 2) = factors.z;
  return r;
}

template <unsigned int M, unsigned int N>
template <unsigned int R>
Matrix<M, N> Matrix<M, N>::fromBasis(const float3& u, const float3& v, const float3& w,
                                     const float3& c) {
  static_assert(R == 4 && N == 4, "fromBasis() builds a 4x4 transform");
  // clang-format off
  const float data[16] = {u.x,  v.x,  w.x,  c.x,
                          u.y,  v.y,  w.y,  c.y,
                          u.z,  v.z,  w.z,  c.z,
                          0.0f, 0.0f, 0.0f, 1.0f};
  // clang-format on
  return Matrix(data);
}

// ---- Operators ----------------------------------------------------------------------------------
// Vector operands come second in the parameter list as a non-deduced type, so a vector of the
// wrong size is a compile error instead of a silent conversion.
template <unsigned int M, unsigned int N>
bool operator==(const Matrix<M, N>& a, const Matrix<M, N>& b) {
  for (unsigned int i = 0; i < M * N; ++i) {
    if (a[i] != b[i]) return false;
  }
  return true;
}
template <unsigned int M, unsigned int N>
bool operator!=(const Matrix<M, N>& a, const Matrix<M, N>& b) {
  return !(a == b);
}

template <unsigned int M, unsigned int N>
Matrix<M, N> operator+(const Matrix<M, N>& a, const Matrix<M, N>& b) {
  Matrix<M, N> r{};
  for (unsigned int i = 0; i < M * N; ++i) r[i] = a[i] + b[i];
  return r;
}
template <unsigned int M, unsigned int N>
Matrix<M, N> operator-(const Matrix<M, N>& a, const Matrix<M, N>& b) {
  Matrix<M, N> r{};
  for (unsigned int i = 0; i < M * N; ++i) r[i] = a[i] - b[i];
  return r;
}
template <unsigned int M, unsigned int N>
Matrix<M, N> operator-(const Matrix<M, N>& a) {
  Matrix<M, N> r{};
  for (unsigned int i = 0; i < M * N; ++i) r[i] = -a[i];
  return r;
}
template <unsigned int M, unsigned int N>
Matrix<M, N>& operator+=(Matrix<M, N>& a, const Matrix<M, N>& b) {
  return a = a + b;
}
template <unsigned int M, unsigned int N>
Matrix<M, N>& operator-=(Matrix<M, N>& a, const Matrix<M, N>& b) {
  return a = a - b;
}

template <unsigned int M, unsigned int N>
Matrix<M, N> operator*(const Matrix<M, N>& a, float s) {
  Matrix<M, N> r{};
  for (unsigned int i = 0; i < M * N; ++i) r[i] = a[i] * s;
  return r;
}
template <unsigned int M, unsigned int N>
Matrix<M, N> operator*(float s, const Matrix<M, N>& a) {
  return a * s;
}
template <unsigned int M, unsigned int N>
Matrix<M, N>& operator*=(Matrix<M, N>& a, float s) {
  return a = a * s;
}
// Division by a scalar multiplies by its reciprocal, as OptiX does.
template <unsigned int M, unsigned int N>
Matrix<M, N> operator/(const Matrix<M, N>& a, float s) {
  return a * (1.0f / s);
}
template <unsigned int M, unsigned int N>
Matrix<M, N>& operator/=(Matrix<M, N>& a, float s) {
  return a = a / s;
}

template <unsigned int M, unsigned int N, unsigned int R>
Matrix<M, R> operator*(const Matrix<M, N>& a, const Matrix<N, R>& b) {
  Matrix<M, R> r{};
  for (unsigned int i = 0; i < M; ++i) {
    for (unsigned int j = 0; j < R; ++j) {
      float sum = 0.0f;
      for (unsigned int k = 0; k < N; ++k) sum += a(i, k) * b(k, j);
      r(i, j) = sum;
    }
  }
  return r;
}
template <unsigned int N>
Matrix<N, N>& operator*=(Matrix<N, N>& a, const Matrix<N, N>& b) {
  return a = a * b;
}

// Matrix times column vector: an M-vector from an N-vector.
template <unsigned int M, unsigned int N>
typename Matrix<M, N>::floatM operator*(const Matrix<M, N>& a,
                                        const typename Matrix<M, N>::floatN& v) {
  typename Matrix<M, N>::floatM r{};
  for (unsigned int i = 0; i < M; ++i) {
    float sum = 0.0f;
    for (unsigned int k = 0; k < N; ++k) sum += a(i, k) * getByIndex(v, static_cast<int>(k));
    setByIndex(r, static_cast<int>(i), sum);
  }
  return r;
}

// Row vector times matrix: an N-vector from an M-vector.
template <unsigned int M, unsigned int N>
typename Matrix<M, N>::floatN operator*(const typename Matrix<M, N>::floatM& v,
                                        const Matrix<M, N>& a) {
  typename Matrix<M, N>::floatN r{};
  for (unsigned int j = 0; j < N; ++j) {
    float sum = 0.0f;
    for (unsigned int k = 0; k < M; ++k) sum += getByIndex(v, static_cast<int>(k)) * a(k, j);
    setByIndex(r, static_cast<int>(j), sum);
  }
  return r;
}

}  // namespace optix

#endif  // OPTIXU_OPTIXU_MATRIX_NAMESPACE_H_

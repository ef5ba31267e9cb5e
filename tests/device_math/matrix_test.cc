// Numeric tests of optix::Matrix.
#include <gtest/gtest.h>

#include <random>
#include <type_traits>

#include "optixu/optixu_matrix.h"
#include "optixu/optixu_matrix_namespace.h"

namespace {

using optix::Matrix;
using optix::Matrix2x2;
using optix::Matrix2x3;
using optix::Matrix3x2;
using optix::Matrix3x3;
using optix::Matrix3x4;
using optix::Matrix4x3;
using optix::Matrix4x4;

// The 16 floats of a Matrix4x4 are what rtGetTransform and rtTransformSetMatrix exchange.
static_assert(sizeof(Matrix4x4) == 16 * sizeof(float));
static_assert(sizeof(Matrix3x4) == 12 * sizeof(float));
static_assert(std::is_trivially_copyable_v<Matrix4x4>);
static_assert(std::is_standard_layout_v<Matrix4x4>);
static_assert(std::is_same_v<optix::Matrix2x4, Matrix<2, 4>> &&
              std::is_same_v<optix::Matrix4x2, Matrix<4, 2>>);
static_assert(std::is_same_v<Matrix3x4::floatN, float4> &&
              std::is_same_v<Matrix3x4::floatM, float3>);

template <unsigned int M, unsigned int N>
Matrix<M, N> RandomMatrix(std::mt19937& rng) {
  std::uniform_real_distribution<float> dist(-2.0f, 2.0f);
  Matrix<M, N> m;
  for (unsigned int i = 0; i < M * N; ++i) m[i] = dist(rng);
  return m;
}

template <unsigned int N>
void ExpectNearIdentity(const Matrix<N, N>& m, float eps) {
  for (unsigned int i = 0; i < N; ++i) {
    for (unsigned int j = 0; j < N; ++j) {
      EXPECT_NEAR(m(i, j), i == j ? 1.0f : 0.0f, eps) << "at (" << i << ", " << j << ")";
    }
  }
}

TEST(MatrixTest, StorageIsRowMajor) {
  const float data[6] = {1, 2, 3, 4, 5, 6};
  Matrix2x3 m(data);
  EXPECT_EQ(m(0, 2), 3.0f);
  EXPECT_EQ(m(1, 0), 4.0f);
  EXPECT_EQ(m[4], 5.0f);
  EXPECT_EQ(m.getData()[5], 6.0f);
  m(1, 1) = 50.0f;
  EXPECT_EQ(m[4], 50.0f);
  m[0] = -1.0f;
  EXPECT_EQ(m(0, 0), -1.0f);
  const Matrix2x3& cm = m;
  EXPECT_EQ(cm.getData()[4], 50.0f);
}

TEST(MatrixTest, RowsAndColumns) {
  const float data[12] = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12};
  Matrix3x4 m(data);
  const float4 row = m.getRow(1);
  EXPECT_EQ(row.x, 5.0f);
  EXPECT_EQ(row.w, 8.0f);
  const float3 col = m.getCol(2);
  EXPECT_EQ(col.x, 3.0f);
  EXPECT_EQ(col.y, 7.0f);
  EXPECT_EQ(col.z, 11.0f);
  m.setRow(0, make_float4(-1.0f, -2.0f, -3.0f, -4.0f));
  EXPECT_EQ(m(0, 3), -4.0f);
  m.setCol(3, make_float3(0.5f, 1.5f, 2.5f));
  EXPECT_EQ(m(0, 3), 0.5f);
  EXPECT_EQ(m(2, 3), 2.5f);
  EXPECT_EQ(m(2, 2), 11.0f);
}

TEST(MatrixTest, IdentityAndTranspose) {
  const Matrix4x4 id = Matrix4x4::identity();
  ExpectNearIdentity(id, 0.0f);
  const Matrix3x2 rect = Matrix3x2::identity();
  EXPECT_EQ(rect(0, 0), 1.0f);
  EXPECT_EQ(rect(1, 1), 1.0f);
  EXPECT_EQ(rect(2, 0), 0.0f);
  EXPECT_EQ(rect(2, 1), 0.0f);

  const float data[6] = {1, 2, 3, 4, 5, 6};
  const Matrix2x3 m(data);
  const Matrix3x2 t = m.transpose();
  for (unsigned int i = 0; i < 2; ++i) {
    for (unsigned int j = 0; j < 3; ++j) EXPECT_EQ(t(j, i), m(i, j));
  }
  EXPECT_TRUE(t.transpose() == m);
}

TEST(MatrixTest, ArithmeticAndComparison) {
  const float a_data[4] = {1, 2, 3, 4};
  const float b_data[4] = {5, 6, 7, 8};
  const Matrix2x2 a(a_data);
  const Matrix2x2 b(b_data);
  const Matrix2x2 sum = a + b;
  EXPECT_EQ(sum(1, 1), 12.0f);
  const Matrix2x2 diff = b - a;
  EXPECT_EQ(diff(0, 1), 4.0f);
  EXPECT_EQ((-a)(1, 0), -3.0f);
  EXPECT_EQ((a * 2.0f)(1, 1), 8.0f);
  EXPECT_EQ((0.5f * a)(0, 1), 1.0f);
  // [1 2; 3 4] * [5 6; 7 8] = [19 22; 43 50].
  const Matrix2x2 prod = a * b;
  EXPECT_EQ(prod(0, 0), 19.0f);
  EXPECT_EQ(prod(0, 1), 22.0f);
  EXPECT_EQ(prod(1, 0), 43.0f);
  EXPECT_EQ(prod(1, 1), 50.0f);

  Matrix2x2 c = a;
  c += b;
  EXPECT_TRUE(c == sum);
  c -= b;
  EXPECT_TRUE(c == a);
  c *= 3.0f;
  EXPECT_EQ(c(1, 1), 12.0f);
  c = a;
  c *= b;
  EXPECT_TRUE(c == prod);
  EXPECT_TRUE(a != b);
  EXPECT_FALSE(a != a);
  EXPECT_TRUE(a < b);
  EXPECT_FALSE(b < a);
  EXPECT_FALSE(a < a);
}

TEST(MatrixTest, DivisionByScalar) {
  Matrix2x2 m = Matrix2x2::identity() * 4.0f;
  EXPECT_EQ((m / 2.0f)[0], 2.0f);
  m /= 4.0f;
  EXPECT_TRUE(m == Matrix2x2::identity());
}

TEST(MatrixTest, NonSquareProductShapes) {
  const float a_data[6] = {1, 2, 3, 4, 5, 6};
  const float b_data[6] = {7, 8, 9, 10, 11, 12};
  const Matrix2x3 a(a_data);
  const Matrix3x2 b(b_data);
  // [1 2 3; 4 5 6] * [7 8; 9 10; 11 12] = [58 64; 139 154].
  const Matrix2x2 ab = a * b;
  EXPECT_EQ(ab(0, 0), 58.0f);
  EXPECT_EQ(ab(0, 1), 64.0f);
  EXPECT_EQ(ab(1, 0), 139.0f);
  EXPECT_EQ(ab(1, 1), 154.0f);
  const Matrix3x3 ba = b * a;
  EXPECT_EQ(ba(0, 0), 39.0f);   // 7 * 1 + 8 * 4.
  EXPECT_EQ(ba(2, 2), 105.0f);  // 11 * 3 + 12 * 6.
}

TEST(MatrixTest, MatrixTimesVector) {
  const float data[16] = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16};
  const Matrix4x4 m(data);
  const float4 v = make_float4(1.0f, 0.0f, -1.0f, 2.0f);
  const float4 mv = m * v;
  EXPECT_EQ(mv.x, 1.0f - 3.0f + 8.0f);
  EXPECT_EQ(mv.y, 5.0f - 7.0f + 16.0f);
  EXPECT_EQ(mv.z, 9.0f - 11.0f + 24.0f);
  EXPECT_EQ(mv.w, 13.0f - 15.0f + 32.0f);
  // Row vector times matrix uses the columns.
  const float4 vm = v * m;
  EXPECT_EQ(vm.x, 1.0f - 9.0f + 26.0f);
  EXPECT_EQ(vm.w, 4.0f - 12.0f + 32.0f);

  const float d34[12] = {1, 0, 0, 10, 0, 1, 0, 20, 0, 0, 1, 30};
  const Matrix3x4 affine(d34);
  const float3 p = affine * make_float4(1.0f, 2.0f, 3.0f, 1.0f);
  EXPECT_EQ(p.x, 11.0f);
  EXPECT_EQ(p.y, 22.0f);
  EXPECT_EQ(p.z, 33.0f);

  const float d2[4] = {0, -1, 1, 0};
  const float2 r = Matrix2x2(d2) * make_float2(1.0f, 0.0f);
  EXPECT_EQ(r.x, 0.0f);
  EXPECT_EQ(r.y, 1.0f);

  const float3 q = Matrix3x3::identity() * make_float3(4.0f, 5.0f, 6.0f);
  EXPECT_EQ(q.y, 5.0f);
  // A 4x3 matrix takes a float3 to a float4.
  const float4 lifted = Matrix4x3::identity() * make_float3(1.0f, 2.0f, 3.0f);
  EXPECT_EQ(lifted.z, 3.0f);
  EXPECT_EQ(lifted.w, 0.0f);
}

TEST(MatrixTest, Determinants) {
  const float d2[4] = {3, 8, 4, 6};
  EXPECT_FLOAT_EQ(Matrix2x2(d2).det(), -14.0f);
  const float d3[9] = {6, 1, 1, 4, -2, 5, 2, 8, 7};
  EXPECT_FLOAT_EQ(Matrix3x3(d3).det(), -306.0f);
  const float d4[16] = {1, 0, 2, -1, 3, 0, 0, 5, 2, 1, 4, -3, 1, 0, 5, 0};
  EXPECT_FLOAT_EQ(Matrix4x4(d4).det(), 30.0f);
  EXPECT_FLOAT_EQ(Matrix4x4::identity().det(), 1.0f);
  EXPECT_FLOAT_EQ(Matrix4x4::scale(make_float3(2.0f, 3.0f, 4.0f)).det(), 24.0f);

  // det(AB) = det(A) det(B) on random matrices.
  std::mt19937 rng(7);
  for (int trial = 0; trial < 20; ++trial) {
    const Matrix4x4 a = RandomMatrix<4, 4>(rng);
    const Matrix4x4 b = RandomMatrix<4, 4>(rng);
    EXPECT_NEAR((a * b).det(), a.det() * b.det(), 1e-3f * (1.0f + std::fabs(a.det() * b.det())));
    const Matrix3x3 c = RandomMatrix<3, 3>(rng);
    EXPECT_NEAR(c.transpose().det(), c.det(), 1e-4f);
  }
}

TEST(MatrixTest, InverseTimesMatrixIsIdentity) {
  std::mt19937 rng(42);
  for (int trial = 0; trial < 50; ++trial) {
    const Matrix4x4 m4 = RandomMatrix<4, 4>(rng);
    if (std::fabs(m4.det()) < 0.1f) continue;  // Too ill-conditioned to judge float accuracy.
    ExpectNearIdentity(m4.inverse() * m4, 1e-4f);
    ExpectNearIdentity(m4 * m4.inverse(), 1e-4f);
    const Matrix3x3 m3 = RandomMatrix<3, 3>(rng);
    if (std::fabs(m3.det()) < 0.1f) continue;
    ExpectNearIdentity(m3.inverse() * m3, 1e-4f);
    const Matrix2x2 m2 = RandomMatrix<2, 2>(rng);
    if (std::fabs(m2.det()) < 0.1f) continue;
    ExpectNearIdentity(m2.inverse() * m2, 1e-5f);
  }
  // A permutation has zeros on the diagonal: only pivoting gets this right.
  const float perm[16] = {0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 1, 0, 0, 0};
  const Matrix4x4 p(perm);
  EXPECT_TRUE(p.inverse() == p.transpose());
  // An affine transform's inverse undoes it.
  const Matrix4x4 xf = Matrix4x4::translate(make_float3(1.0f, -2.0f, 3.0f)) *
                       Matrix4x4::rotate(0.7f, make_float3(1.0f, 1.0f, 0.0f)) *
                       Matrix4x4::scale(make_float3(2.0f, 0.5f, 3.0f));
  const float4 point = make_float4(0.3f, -0.6f, 2.0f, 1.0f);
  const float4 back = xf.inverse() * (xf * point);
  EXPECT_NEAR(back.x, point.x, 1e-5f);
  EXPECT_NEAR(back.y, point.y, 1e-5f);
  EXPECT_NEAR(back.z, point.z, 1e-5f);
  EXPECT_NEAR(back.w, 1.0f, 1e-6f);
}

TEST(MatrixTest, SingularInverseIsNotFinite) {
  const float zero[4] = {1, 2, 2, 4};
  const Matrix2x2 singular(zero);
  EXPECT_EQ(singular.det(), 0.0f);
  const Matrix2x2 inv = singular.inverse();
  EXPECT_FALSE(std::isfinite(inv[0]) && std::isfinite(inv[1]) && std::isfinite(inv[2]) &&
               std::isfinite(inv[3]));
}

TEST(MatrixTest, RotateIsRightHanded) {
  const Matrix4x4 rz = Matrix4x4::rotate(M_PI_2f, make_float3(0.0f, 0.0f, 5.0f));
  const float4 x = rz * make_float4(1.0f, 0.0f, 0.0f, 0.0f);
  EXPECT_NEAR(x.x, 0.0f, 1e-6f);
  EXPECT_NEAR(x.y, 1.0f, 1e-6f);
  EXPECT_NEAR(x.z, 0.0f, 1e-6f);
  const Matrix4x4 rx = Matrix4x4::rotate(M_PI_2f, make_float3(1.0f, 0.0f, 0.0f));
  const float4 y = rx * make_float4(0.0f, 1.0f, 0.0f, 0.0f);
  EXPECT_NEAR(y.z, 1.0f, 1e-6f);
  const Matrix4x4 ry = Matrix4x4::rotate(M_PI_2f, make_float3(0.0f, 1.0f, 0.0f));
  const float4 z = ry * make_float4(0.0f, 0.0f, 1.0f, 0.0f);
  EXPECT_NEAR(z.x, 1.0f, 1e-6f);

  // Rotations are orthonormal and keep the axis fixed.
  const float3 axis = normalize(make_float3(1.0f, 2.0f, -0.5f));
  const Matrix4x4 r = Matrix4x4::rotate(1.234f, axis);
  ExpectNearIdentity(r * r.transpose(), 1e-6f);
  EXPECT_NEAR(r.det(), 1.0f, 1e-5f);
  const float4 fixed = r * make_float4(axis, 0.0f);
  EXPECT_NEAR(fixed.x, axis.x, 1e-6f);
  EXPECT_NEAR(fixed.y, axis.y, 1e-6f);
  EXPECT_NEAR(fixed.z, axis.z, 1e-6f);
}

TEST(MatrixTest, TranslateScaleFromBasis) {
  const Matrix4x4 t = Matrix4x4::translate(make_float3(1.0f, 2.0f, 3.0f));
  const float4 p = t * make_float4(1.0f, 1.0f, 1.0f, 1.0f);
  EXPECT_EQ(p.x, 2.0f);
  EXPECT_EQ(p.y, 3.0f);
  EXPECT_EQ(p.z, 4.0f);
  EXPECT_EQ(p.w, 1.0f);
  const float4 v = t * make_float4(1.0f, 1.0f, 1.0f, 0.0f);  // Directions do not move.
  EXPECT_EQ(v.x, 1.0f);
  EXPECT_EQ(v.w, 0.0f);

  const float4 s = Matrix4x4::scale(make_float3(2.0f, 3.0f, 4.0f)) * make_float4(1.0f);
  EXPECT_EQ(s.x, 2.0f);
  EXPECT_EQ(s.y, 3.0f);
  EXPECT_EQ(s.z, 4.0f);
  EXPECT_EQ(s.w, 1.0f);

  const float3 u = make_float3(0.0f, 1.0f, 0.0f);
  const float3 w = make_float3(1.0f, 0.0f, 0.0f);
  const float3 vv = make_float3(0.0f, 0.0f, -1.0f);
  const float3 c = make_float3(5.0f, 6.0f, 7.0f);
  const Matrix4x4 basis = Matrix4x4::fromBasis(u, vv, w, c);
  const float4 local = basis * make_float4(2.0f, 3.0f, 4.0f, 1.0f);
  // 2u + 3v + 4w + c.
  EXPECT_EQ(local.x, 4.0f + 5.0f);
  EXPECT_EQ(local.y, 2.0f + 6.0f);
  EXPECT_EQ(local.z, -3.0f + 7.0f);
  EXPECT_EQ(local.w, 1.0f);
  const float4 col = basis.getCol(0);
  EXPECT_EQ(col.y, 1.0f);
  EXPECT_EQ(col.w, 0.0f);
}

// The linear part of a 4x4 transform.
TEST(MatrixTest, MakeMatrix3x3) {
  const optix::Matrix4x4 m = optix::Matrix4x4::translate(make_float3(7.0f, 8.0f, 9.0f)) *
                             optix::Matrix4x4::scale(make_float3(2.0f, 3.0f, 4.0f));
  const optix::Matrix3x3 l = optix::make_matrix3x3(m);
  for (unsigned int r = 0; r < 3; ++r) {
    for (unsigned int c = 0; c < 3; ++c) EXPECT_EQ(l(r, c), m(r, c)) << r << "," << c;
  }
  EXPECT_FLOAT_EQ(l.det(), 24.0f);
}

}  // namespace

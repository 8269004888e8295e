// Matrices: dual quaternion ↔ 3x4/4x4, and repairing drifted rotation blocks.
#include <gtest/gtest.h>

#include <cmath>

#include "support.hpp"

namespace {

using namespace dq;
using dq::test::max_abs_diff;
using dq::test::Random;
using dq::test::tol;

template <class T>
class MatrixTyped : public ::testing::Test {};
TYPED_TEST_SUITE(MatrixTyped, dq::test::FloatTypes);

TYPED_TEST(MatrixTyped, DualQuaternionMatrixRoundTrip) {
  using T = TypeParam;
  Random rng(61);
  for (int n = 0; n < 2000; ++n) {
    const DualQuaternion<T> q = rng.rigid<T>(100);
    const Mat4<T> m4 = to_mat4(q);
    EXPECT_EQ(m4(3, 0), T(0));
    EXPECT_EQ(m4(3, 3), T(1));
    EXPECT_LE(orthonormality_error(rotation_block(m4)), tol<T>(16));
    const DualQuaternion<T> back4 = from_matrix(m4), back34 = from_matrix(to_mat34(q));
    EXPECT_TRUE(approx_equal(back4, q, tol<T>(64) * T(100), SignPolicy::same_rotation));
    EXPECT_TRUE(approx_equal(back34, q, tol<T>(64) * T(100), SignPolicy::same_rotation));
  }
}

TYPED_TEST(MatrixTyped, AffineComposeEqualsFullProduct) {
  using T = TypeParam;
  Random rng(62);
  for (int n = 0; n < 500; ++n) {
    const DualQuaternion<T> a = rng.rigid<T>(), b = rng.rigid<T>();
    const Mat4<T> full = to_mat4(a) * to_mat4(b);
    const Mat34<T> c = compose(to_mat34(a), to_mat34(b));
    for (int r = 0; r < 3; ++r)
      for (int col = 0; col < 4; ++col) DQ_EXPECT_NEAR(c(r, col), full(r, col), tol<T>(16) * T(10));
  }
}

TEST(Matrix, OrthonormalizationRepairsDrift) {
  Random rng(63);
  for (int n = 0; n < 500; ++n) {
    const Quaternion<double> q = rng.rotation<double>();
    Mat3<double> m = q.to_matrix();
    for (double& v : m.m) v += rng.uniform(-1e-3, 1e-3);  // drift: scale and skew
    const Mat3<double> polar = orthonormalize_polar(m), gs = orthonormalize_gram_schmidt(m);
    EXPECT_LE(orthonormality_error(polar), 1e-14);
    EXPECT_LE(orthonormality_error(gs), 1e-14);
    // Both stay close to the original rotation; the polar factor is the nearest rotation, so it is
    // at least as close (Frobenius) as Gram–Schmidt.
    auto frob = [&](const Mat3<double>& r) {
      double s = 0;
      for (std::size_t i = 0; i < 9; ++i) s += (r.m[i] - m.m[i]) * (r.m[i] - m.m[i]);
      return s;
    };
    EXPECT_LE(frob(polar), frob(gs) + 1e-18);
    EXPECT_LE(dq::test::rotation_diff(Quaternion<double>::from_matrix(polar), q), 5e-3);
  }
  // A rotation is its own polar factor.
  const Mat3<double> r = Quaternion<double>::from_axis_angle(Vec3<double>{1, 2, 3}, 2.0).to_matrix();
  EXPECT_LE(max_abs_diff(orthonormalize_polar(r), r), 1e-15);
}

TEST(Matrix, FromMatrixOfARotationIsItsQuaternion) {
  // A quarter turn about z as a 3x3 matrix, written out: (cos π/4, 0, 0, sin π/4), up to sign.
  const Mat3<double> m = Mat3<double>::from_rows(0, -1, 0, 1, 0, 0, 0, 0, 1);
  const Quaternion<double> q = from_matrix(m);
  EXPECT_NEAR(std::abs(q.w), std::sqrt(0.5), 1e-15);
  EXPECT_NEAR(q.z * (q.w < 0 ? -1 : 1), std::sqrt(0.5), 1e-15);
  EXPECT_NEAR(std::abs(q.x) + std::abs(q.y), 0.0, 1e-15);
}

TEST(Matrix, RowsAndColumnMajorStorage) {
  const Mat<double, 2, 3> m = Mat<double, 2, 3>::from_rows(1, 2, 3, 4, 5, 6);
  EXPECT_EQ(m(0, 2), 3);
  EXPECT_EQ(m(1, 0), 4);
  EXPECT_EQ(m.m[1], 4);  // column-major: (1, 0) is the second stored value
  EXPECT_EQ(transpose(m)(2, 1), 6);
}

}  // namespace

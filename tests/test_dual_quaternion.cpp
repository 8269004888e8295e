// Dual quaternions: the algebra of the seeds, the unit condition, and the rigid-transform actions,
// each checked against an independent computation.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "support.hpp"

namespace {

using namespace dq;
using dq::test::max_abs_diff;
using dq::test::Random;
using dq::test::tol;

template <class T>
class DualQuaternionTyped : public ::testing::Test {};
TYPED_TEST_SUITE(DualQuaternionTyped, dq::test::FloatTypes);

/// A second implementation: the dual quaternion as a quaternion whose coefficients are dual
/// numbers, multiplied by the plain Hamilton formula over Dual<T>.
template <class T>
Quaternion<Dual<T>> as_dual_coefficients(const DualQuaternion<T>& q) {
  return {Dual<T>(q.real.w, q.dual.w), Dual<T>(q.real.x, q.dual.x), Dual<T>(q.real.y, q.dual.y),
          Dual<T>(q.real.z, q.dual.z)};
}
template <class T>
DualQuaternion<T> from_dual_coefficients(const Quaternion<Dual<T>>& q) {
  return {Quaternion<T>(q.w.real, q.x.real, q.y.real, q.z.real), Quaternion<T>(q.w.dual, q.x.dual, q.y.dual, q.z.dual)};
}

TYPED_TEST(DualQuaternionTyped, ProductEqualsQuaternionOverDualNumbers) {
  using T = TypeParam;
  Random rng(41);
  for (int n = 0; n < 2000; ++n) {
    const DualQuaternion<T> a{Quaternion<T>(rng.uniform<T>(-2, 2), rng.uniform<T>(-2, 2), rng.uniform<T>(-2, 2), rng.uniform<T>(-2, 2)),
                              Quaternion<T>(rng.uniform<T>(-2, 2), rng.uniform<T>(-2, 2), rng.uniform<T>(-2, 2), rng.uniform<T>(-2, 2))};
    const DualQuaternion<T> b = rng.rigid<T>();
    const DualQuaternion<T> expected = from_dual_coefficients(as_dual_coefficients(a) * as_dual_coefficients(b));
    EXPECT_LE(max_abs_diff(a * b, expected), tol<T>(4) * T(20));
  }
}

TYPED_TEST(DualQuaternionTyped, UnitPropertiesOfRigidTransforms) {
  using T = TypeParam;
  Random rng(42);
  const T t = tol<T>(64) * T(10);  // translations up to 10 scale the absolute error
  for (int n = 0; n < 2000; ++n) {
    const DualQuaternion<T> a = rng.rigid<T>(), b = rng.rigid<T>(), c = rng.rigid<T>();
    EXPECT_TRUE(a.is_unit(tol<T>(8)));
    EXPECT_TRUE((a * b).is_unit(tol<T>(64)));                                      // products stay unit
    EXPECT_LE(max_abs_diff(a * a.conjugate(), DualQuaternion<T>::identity()), t);  // Q Q* = 1
    EXPECT_LE(max_abs_diff(a * a.inverse(), DualQuaternion<T>::identity()), t);
    EXPECT_LE(max_abs_diff(a.inverse(), a.inverse_unit()), t);
    EXPECT_LE(max_abs_diff((a * b) * c, a * (b * c)), t * T(10));  // associativity
    const Dual<T> n2 = a.squared_norm();
    DQ_EXPECT_NEAR(n2.real, 1.0, tol<T>(8));
    DQ_EXPECT_NEAR(n2.dual, 0.0, t);
  }
}

TYPED_TEST(DualQuaternionTyped, GeneralInverse) {
  using T = TypeParam;
  Random rng(43);
  for (int n = 0; n < 1000; ++n) {
    const DualQuaternion<T> a = rng.rigid<T>() * rng.uniform<T>(T(0.5), T(3));  // not unit
    const DualQuaternion<T> a2{a.real, a.dual + Quaternion<T>(T(0.3), T(0), T(-0.2), T(0.1))};  // q_r·q_d ≠ 0
    for (const auto& q : {a, a2}) {
      EXPECT_LE(max_abs_diff(q * q.inverse(), DualQuaternion<T>::identity()), tol<T>(64) * T(30));
      EXPECT_LE(max_abs_diff(q.inverse() * q, DualQuaternion<T>::identity()), tol<T>(64) * T(30));
    }
  }
}

TYPED_TEST(DualQuaternionTyped, ConstructionAndExtraction) {
  using T = TypeParam;
  Random rng(44);
  for (int n = 0; n < 1000; ++n) {
    const Quaternion<T> r = rng.rotation<T>();
    const Vec3<T> t = rng.vec3<T>(100);
    const DualQuaternion<T> q = DualQuaternion<T>::from_rotation_translation(r, t);
    EXPECT_EQ(q.rotation(), r);
    EXPECT_LE(max_abs_diff(q.translation(), t), tol<T>(16) * T(100));
    // rotation then translation = T · R as a product of the pure parts.
    const DualQuaternion<T> product = DualQuaternion<T>::from_translation(t) * DualQuaternion<T>::from_rotation(r);
    EXPECT_LE(max_abs_diff(product, q), tol<T>(16) * T(100));
    EXPECT_LE(max_abs_diff(DualQuaternion<T>::from_translation(t).translation(), t), tol<T>(2) * T(100));
  }
}

TYPED_TEST(DualQuaternionTyped, PointTransformEqualsMatrixAndSandwich) {
  using T = TypeParam;
  Random rng(45);
  for (int n = 0; n < 2000; ++n) {
    const DualQuaternion<T> q = rng.rigid<T>();
    const Vec3<T> p = rng.vec3<T>(10);
    // Independent reference: rotate by the matrix of the rotation part, then add the translation
    // recovered from the definition t = 2 q_d q_r*.
    const Vec3<T> t = (q.dual * T(2) * q.real.conjugate()).vec();
    const Vec3<T> expected = q.real.to_matrix() * p + t;
    const T bound = tol<T>(64) * T(20);
    EXPECT_LE(max_abs_diff(q.transform_point(p), expected), bound);
    EXPECT_LE(max_abs_diff(q.transform_point_sandwich(p), expected), bound);
    EXPECT_LE(max_abs_diff(transform_point(to_mat4(q), p), expected), bound);
    EXPECT_LE(max_abs_diff(transform_point(to_mat34(q), p), expected), bound);
    // Composition order matches matrices: (A B) p = A (B p).
    const DualQuaternion<T> b = rng.rigid<T>();
    EXPECT_LE(max_abs_diff((q * b).transform_point(p), q.transform_point(b.transform_point(p))), bound * T(4));
    EXPECT_LE(max_abs_diff(to_mat4(q * b), to_mat4(q) * to_mat4(b)), bound * T(4));
    // Directions are only rotated; −Q is the same transform.
    EXPECT_LE(max_abs_diff(q.transform_direction(p), q.real.rotate(p)), T(0));
    EXPECT_LE(max_abs_diff((-q).transform_point(p), q.transform_point(p)), bound);
  }
}

TYPED_TEST(DualQuaternionTyped, LinesAndPlanesFollowTheirPoints) {
  using T = TypeParam;
  Random rng(46);
  for (int n = 0; n < 1000; ++n) {
    const DualQuaternion<T> q = rng.rigid<T>();
    const Vec3<T> p = rng.vec3<T>(5), d = normalized(rng.vec3<T>(1));
    // The moved line must be the line through the moved point with the rotated direction.
    const PluckerLine<T> moved = q.transform_line(PluckerLine<T>::through(p, d));
    const PluckerLine<T> expected = PluckerLine<T>::through(q.transform_point(p), q.transform_direction(d));
    EXPECT_LE(max_abs_diff(moved.direction, expected.direction), tol<T>(64));
    EXPECT_LE(max_abs_diff(moved.moment, expected.moment), tol<T>(64) * T(100));
    // As the dual vector sandwich Q (l + ε m) Q*, literally.
    const PluckerLine<T> line = PluckerLine<T>::through(p, d);
    const DualQuaternion<T> lv{Quaternion<T>::pure(line.direction), Quaternion<T>::pure(line.moment)};
    const DualQuaternion<T> s = q * lv * q.conjugate();
    EXPECT_LE(max_abs_diff(s.real.vec(), moved.direction), tol<T>(64));
    EXPECT_LE(max_abs_diff(s.dual.vec(), moved.moment), tol<T>(64) * T(100));
    // Planes: a point on the plane stays on the moved plane.
    const Plane<T> plane{d, dot(d, p)};
    const Plane<T> mp = q.transform_plane(plane);
    DQ_EXPECT_NEAR(dot(mp.normal, q.transform_point(p)), mp.distance, tol<T>(64) * T(100));
  }
}

TYPED_TEST(DualQuaternionTyped, NormalizationEnforcesTheWholeUnitCondition) {
  using T = TypeParam;
  Random rng(47);
  for (int n = 0; n < 1000; ++n) {
    const DualQuaternion<T> q = rng.rigid<T>();
    // Drift: scale, and push the dual part off orthogonality.
    DualQuaternion<T> drifted = q * rng.uniform<T>(T(0.5), T(2));
    drifted.dual = drifted.dual + drifted.real * rng.uniform<T>(T(-0.1), T(0.1));
    const DualQuaternion<T> u = drifted.normalized();
    DQ_EXPECT_NEAR(u.real.norm(), 1.0, tol<T>(8));
    DQ_EXPECT_NEAR(dot(u.real, u.dual), 0.0, tol<T>(64));
    // The projection keeps rotation and translation of the original transform.
    EXPECT_LE(max_abs_diff(u, q), tol<T>(128) * T(10));
    // Normalizing a unit dual quaternion changes (almost) nothing.
    EXPECT_LE(max_abs_diff(q.normalized(), q), tol<T>(64) * T(10));
    // The dual-number norm: Q / ‖Q‖ as a dual scalar division equals normalized().
    const Dual<T> nrm = drifted.norm();
    const Dual<T> inv = Dual<T>(T(1)) / nrm;
    EXPECT_LE(max_abs_diff(inv * drifted, u), tol<T>(128) * T(10));
  }
  EXPECT_EQ(DualQuaternion<T>(Quaternion<T>(0, 0, 0, 0), Quaternion<T>(1, 2, 3, 4)).normalized(), DualQuaternion<T>::identity());
  const T nan = std::numeric_limits<T>::quiet_NaN();
  EXPECT_TRUE(std::isnan(DualQuaternion<T>(Quaternion<T>(nan, 0, 0, 0), Quaternion<T>(0, 0, 0, 0)).normalized().real.w));
}

TEST(DualQuaternion, ThreeConjugates) {
  const DualQuaternion<double> q(1, 2, 3, 4, 5, 6, 7, 8);
  EXPECT_EQ(q.conjugate(), DualQuaternion<double>(1, -2, -3, -4, 5, -6, -7, -8));
  EXPECT_EQ(q.dual_conjugate(), DualQuaternion<double>(1, 2, 3, 4, -5, -6, -7, -8));
  EXPECT_EQ(q.combined_conjugate(), DualQuaternion<double>(1, -2, -3, -4, -5, 6, 7, 8));
}

TEST(DualQuaternion, ApproxEqualKnowsThatMinusQIsTheSameTransform) {
  Random rng(48);
  const DualQuaternion<double> q = rng.rigid<double>();
  EXPECT_FALSE(approx_equal(q, -q, 1e-12));
  EXPECT_TRUE(approx_equal(q, -q, 1e-12, SignPolicy::same_rotation));
  EXPECT_FALSE(q == -q);
}

TEST(DualQuaternion, CastBetweenScalarTypes) {
  const DualQuaternion<float> f(0.5f, -0.5f, 0.25f, 1e-30f, 3.0f, -7.5f, 1e20f, 0.1f);
  const DualQuaternion<double> d = f.cast<double>();
  EXPECT_EQ(d.real.x, -0.5);
  EXPECT_EQ(d.real.z, double(1e-30f));
  EXPECT_EQ(d.dual.y, double(1e20f));
  EXPECT_EQ(d.dual.z, double(0.1f));
  EXPECT_EQ(d.cast<float>(), f);  // float → double → float is exact
  EXPECT_EQ(Quaternion<double>(0.1, 0.2, 0.3, 0.4).cast<float>(), Quaternion<float>(0.1f, 0.2f, 0.3f, 0.4f));
  EXPECT_EQ(Vec3<double>(0.1, -1e30, 7.0).cast<float>(), Vec3<float>(0.1f, -1e30f, 7.0f));
  EXPECT_EQ(Vec3<float>(0.1f, 1e-40f, -2.5f).cast<double>(), Vec3<double>(double(0.1f), double(1e-40f), -2.5));
}

TEST(DualQuaternion, DualScalarMultiplication) {
  const DualQuaternion<double> q(1, 2, 3, 4, 5, 6, 7, 8);
  const DualQuaternion<double> s = Dual<double>(2, 3) * q;
  // (2 + 3ε)(q_r + ε q_d) = 2 q_r + ε (2 q_d + 3 q_r)
  EXPECT_EQ(s, DualQuaternion<double>(2, 4, 6, 8, 13, 18, 23, 28));
}

}  // namespace

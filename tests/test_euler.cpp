// Euler angles: all twelve sequences, intrinsic and extrinsic, against the product of elementary
// matrices; gimbal lock gives a valid triple and a flag, never NaN.
#include <gtest/gtest.h>

#include <cmath>

#include "support.hpp"

namespace {

using namespace dq;
using dq::test::max_abs_diff;
using dq::test::Random;

template <class T>
class EulerTyped : public ::testing::Test {};
TYPED_TEST_SUITE(EulerTyped, dq::test::FloatTypes);

TYPED_TEST(EulerTyped, QuaternionMatchesElementaryMatrixProduct) {
  using T = TypeParam;
  Random rng(71);
  for (EulerOrder order : all_euler_orders)
    for (EulerFrame frame : {EulerFrame::intrinsic, EulerFrame::extrinsic})
      for (int n = 0; n < 200; ++n) {
        const T a = rng.uniform<T>(-3, 3), b = rng.uniform<T>(-3, 3), c = rng.uniform<T>(-3, 3);
        const Mat3<T> expected = euler_to_matrix(order, frame, a, b, c);
        EXPECT_LE(max_abs_diff(from_euler(order, frame, a, b, c).to_matrix(), expected), dq::test::tol<T>(32))
            << to_string(order);
      }
}

TEST(Euler, ConventionsExamples) {
  // Intrinsic XYZ(a, b, c) = Rx(a) Ry(b) Rz(c); extrinsic XYZ(a, b, c) = Rz(c) Ry(b) Rx(a).
  const double a = 0.3, b = -0.7, c = 1.1;
  auto rx = [](double v) { return Quaternion<double>::from_axis_angle(Vec3<double>{1, 0, 0}, v); };
  auto ry = [](double v) { return Quaternion<double>::from_axis_angle(Vec3<double>{0, 1, 0}, v); };
  auto rz = [](double v) { return Quaternion<double>::from_axis_angle(Vec3<double>{0, 0, 1}, v); };
  EXPECT_LE(max_abs_diff(from_euler(EulerOrder::XYZ, EulerFrame::intrinsic, a, b, c), rx(a) * ry(b) * rz(c)), 0.0);
  EXPECT_LE(max_abs_diff(from_euler(EulerOrder::XYZ, EulerFrame::extrinsic, a, b, c), rz(c) * ry(b) * rx(a)), 0.0);
  // Extrinsic XYZ equals intrinsic ZYX with the angles reversed.
  EXPECT_LE(max_abs_diff(from_euler(EulerOrder::XYZ, EulerFrame::extrinsic, a, b, c),
                         from_euler(EulerOrder::ZYX, EulerFrame::intrinsic, c, b, a)), 0.0);
}

TYPED_TEST(EulerTyped, RoundTripInAllSequences) {
  using T = TypeParam;
  Random rng(72);
  for (EulerOrder order : all_euler_orders)
    for (EulerFrame frame : {EulerFrame::intrinsic, EulerFrame::extrinsic})
      for (int n = 0; n < 500; ++n) {
        const Quaternion<T> q = rng.rotation<T>();
        const EulerExtraction<T> e = to_euler(q, order, frame);
        EXPECT_FALSE(e.singular);
        const Quaternion<T> back = from_euler(order, frame, e.angles);
        EXPECT_LE(dq::test::rotation_diff(back, q), dq::test::tol<T>(64)) << to_string(order);
        // Ranges: (−π, π] outside, the middle one in its half range.
        EXPECT_LE(std::abs(e.angles.a), pi_v<T>);
        EXPECT_LE(std::abs(e.angles.c), pi_v<T>);
        if (is_proper_euler(order)) {
          EXPECT_GE(e.angles.b, T(0));
          EXPECT_LE(e.angles.b, pi_v<T>);
        } else {
          EXPECT_LE(std::abs(e.angles.b), pi_v<T> / 2);
        }
      }
}

TYPED_TEST(EulerTyped, AnglesInsideTheirRangesComeBackUnchanged) {
  using T = TypeParam;
  Random rng(73);
  for (EulerOrder order : all_euler_orders)
    for (EulerFrame frame : {EulerFrame::intrinsic, EulerFrame::extrinsic})
      for (int n = 0; n < 200; ++n) {
        const T a = rng.uniform<T>(T(-3.1), T(3.1)), c = rng.uniform<T>(T(-3.1), T(3.1));
        const T b = is_proper_euler(order) ? rng.uniform<T>(T(0.05), T(3.09)) : rng.uniform<T>(T(-1.52), T(1.52));
        const EulerExtraction<T> e = to_euler(from_euler(order, frame, a, b, c), order, frame);
        const T bound = dq::test::tol<T>(2048);
        DQ_EXPECT_NEAR(e.angles.a, a, bound) << to_string(order);
        DQ_EXPECT_NEAR(e.angles.b, b, bound) << to_string(order);
        DQ_EXPECT_NEAR(e.angles.c, c, bound) << to_string(order);
      }
}

TYPED_TEST(EulerTyped, GimbalLockGivesAValidTripleWithThirdAngleZero) {
  using T = TypeParam;
  Random rng(74);
  for (EulerOrder order : all_euler_orders)
    for (EulerFrame frame : {EulerFrame::intrinsic, EulerFrame::extrinsic})
      for (T b : is_proper_euler(order) ? std::array<T, 2>{T(0), pi_v<T>} : std::array<T, 2>{pi_v<T> / 2, -pi_v<T> / 2})
        for (int n = 0; n < 50; ++n) {
          const T a = rng.uniform<T>(-3, 3), c = rng.uniform<T>(-3, 3);
          const Quaternion<T> q = from_euler(order, frame, a, b, c);
          const EulerExtraction<T> e = to_euler(q, order, frame);
          EXPECT_TRUE(e.singular) << to_string(order);
          EXPECT_EQ(e.angles.c, T(0));
          EXPECT_FALSE(std::isnan(e.angles.a) || std::isnan(e.angles.b));
          EXPECT_LE(dq::test::rotation_diff(from_euler(order, frame, e.angles), q), dq::test::tol<T>(64)) << to_string(order);
          EXPECT_LE(euler_singularity_distance(q, order, frame), dq::test::tol<T>(64));
        }
}

TEST(Euler, ARigidTransformsAnglesAreItsRotations) {
  // to_euler of a dual quaternion reads its rotation: angles built into a transform with a
  // translation come back (away from gimbal lock), and the translation does not enter.
  const double a = 0.4, b = -0.7, c = 1.9;
  for (const EulerOrder order : {EulerOrder::XYZ, EulerOrder::ZYX, EulerOrder::ZXZ})
    for (const EulerFrame frame : {EulerFrame::intrinsic, EulerFrame::extrinsic}) {
      const double mid = order == EulerOrder::ZXZ ? -b : b;  // proper Euler: the middle angle in [0, π]
      const auto q = DualQuaternion<double>::from_rotation_translation(from_euler(order, frame, a, mid, c), {5, -3, 2});
      const EulerExtraction<double> e = to_euler(q, order, frame);
      EXPECT_FALSE(e.singular);
      EXPECT_NEAR(e.angles.a, a, 1e-14);
      EXPECT_NEAR(e.angles.b, mid, 1e-14);
      EXPECT_NEAR(e.angles.c, c, 1e-14);
    }
}

TEST(Euler, ThesisGimbalLockDerivation) {
  // Arends §2: Rx(φ) Ry(π/2) Rz(ψ) depends only on φ + ψ, a lost degree of freedom.
  const double half_pi = pi_v<double> / 2;
  for (double s : {-1.0, 0.4, 2.0}) {
    const Mat3<double> m1 = euler_to_matrix(EulerOrder::XYZ, EulerFrame::intrinsic, 0.3, half_pi, s - 0.3);
    const Mat3<double> m2 = euler_to_matrix(EulerOrder::XYZ, EulerFrame::intrinsic, s - 1.2, half_pi, 1.2);
    EXPECT_LE(max_abs_diff(m1, m2), 1e-15);
  }
}

TEST(Euler, SingularityDistance) {
  for (double b : {0.0, 0.1, 0.5, 1.0, 1.5}) {
    const Quaternion<double> q = from_euler(EulerOrder::ZYX, EulerFrame::intrinsic, 0.2, b, -0.4);
    EXPECT_NEAR(euler_singularity_distance(q, EulerOrder::ZYX, EulerFrame::intrinsic), pi_v<double> / 2 - b, 1e-14);
    const Quaternion<double> p = from_euler(EulerOrder::ZXZ, EulerFrame::intrinsic, 0.2, b, -0.4);
    EXPECT_NEAR(euler_singularity_distance(p, EulerOrder::ZXZ, EulerFrame::intrinsic), b, 1e-14);
  }
}

}  // namespace

// The seed listings' mistakes, reproduced faithfully here, each beside dqkit's behaviour on the
// same input (docs/seed-errata.md lists them).
#include <gtest/gtest.h>

#include <array>
#include <cmath>

#include "support.hpp"

namespace {

using namespace dq;
using dq::test::max_abs_diff;

// ---- Kenwright, appendix 13.1 (C#, XNA) -------------------------------------------------------

/// `Normalize`: divides both parts by mag = Dot(real, real), the *squared* norm, and leaves
/// q_r · q_d as it was.
DualQuaternion<double> kenwright_normalize(const DualQuaternion<double>& q) {
  const double mag = dot(q.real, q.real);
  return {q.real * (1.0 / mag), q.dual * (1.0 / mag)};
}

TEST(SeedErrata, KenwrightNormalizeUsesTheSquaredNorm) {
  const DualQuaternion<double> q = DualQuaternion<double>::from_rotation_translation(
      Quaternion<double>::from_axis_angle(Vec3<double>{1, 2, 3}, 0.8), Vec3<double>{4, 5, 6});
  const DualQuaternion<double> scaled = q * 2.0;
  EXPECT_NEAR(kenwright_normalize(scaled).real.norm(), 0.5, 1e-15);  // not unit
  EXPECT_NEAR(scaled.normalized().real.norm(), 1.0, 1e-15);
  EXPECT_LE(max_abs_diff(scaled.normalized(), q), 1e-14);
  // And the orthogonality condition is not restored.
  DualQuaternion<double> drifted = q;
  drifted.dual = drifted.dual + q.real * 0.01;
  EXPECT_GT(std::abs(dot(kenwright_normalize(drifted).real, kenwright_normalize(drifted).dual)), 1e-3);
  EXPECT_LT(std::abs(dot(drifted.normalized().real, drifted.normalized().dual)), 1e-15);
}

TEST(SeedErrata, KenwrightConstructorNormalizesOnlyTheRealPart) {
  // DualQuaternion_c(Quaternion r, Quaternion d) { m_real = Normalize(r); m_dual = d; }
  const DualQuaternion<double> q = DualQuaternion<double>::from_rotation_translation(
      Quaternion<double>::from_axis_angle(Vec3<double>{0, 1, 0}, 0.5), Vec3<double>{1, 0, 0});
  const DualQuaternion<double> scaled = q * 3.0;
  const DualQuaternion<double> listing{scaled.real.normalized(), scaled.dual};
  EXPECT_LE(max_abs_diff(listing.translation(), Vec3<double>{3, 0, 0}), 1e-14);  // translation tripled
  EXPECT_LE(max_abs_diff(scaled.normalized().translation(), Vec3<double>{1, 0, 0}), 1e-14);
}

TEST(SeedErrata, KenwrightMultiplicationOrderIsLeftToRight) {
  // operator*(lhs, rhs) returns (rhs.real * lhs.real, rhs.dual * lhs.real + rhs.real * lhs.dual):
  // lhs is applied first. In dqkit (and in matrix order) A * B applies B first.
  dq::test::Random rng(111);
  const DualQuaternion<double> a = rng.rigid<double>(), b = rng.rigid<double>();
  const DualQuaternion<double> listing{b.real * a.real, b.dual * a.real + b.real * a.dual};
  EXPECT_LE(max_abs_diff(listing, b * a), 1e-14);
  const Vec3<double> p{1, 2, 3};
  EXPECT_LE(max_abs_diff(listing.transform_point(p), b.transform_point(a.transform_point(p))), 1e-12);
}

TEST(SeedErrata, KenwrightMatrixIsTheRowVectorTranspose) {
  // M.M12 = 2xy + 2wz: XNA's row-vector matrix, the transpose of ours (CONVENTIONS.md).
  const Quaternion<double> q = Quaternion<double>::from_axis_angle(Vec3<double>{1, -1, 2}, 1.1);
  const double m12 = 2 * q.x * q.y + 2 * q.w * q.z;
  EXPECT_NEAR(q.to_matrix()(1, 0), m12, 1e-16);  // our (row 2, column 1), 0-based (1, 0)
}

// ---- VRML tutorial §2.5 (ECMAScript), storage x, y, z, w ----------------------------------------

using Mf = std::array<double, 8>;

Mf vrml_multiply(const Mf& a, const Mf& b) {
  return {a[3] * b[0] + a[0] * b[3] + a[1] * b[2] - a[2] * b[1], a[3] * b[1] + a[1] * b[3] + a[2] * b[0] - a[0] * b[2],
          a[3] * b[2] + a[2] * b[3] + a[0] * b[1] - a[1] * b[0], a[3] * b[3] - a[0] * b[0] - a[1] * b[1] - a[2] * b[2],
          a[7] * b[0] + a[4] * b[3] + a[5] * b[2] - a[6] * b[1] + a[3] * b[4] + a[0] * b[7] + a[1] * b[6] - a[2] * b[5],
          a[7] * b[1] + a[5] * b[3] + a[6] * b[0] - a[4] * b[2] + a[3] * b[5] + a[1] * b[7] + a[2] * b[4] - a[0] * b[6],
          a[7] * b[2] + a[6] * b[3] + a[4] * b[1] - a[5] * b[0] + a[3] * b[6] + a[2] * b[7] + a[0] * b[5] - a[1] * b[4],
          a[7] * b[3] - a[4] * b[0] - a[5] * b[1] - a[6] * b[2] + a[3] * b[7] - a[0] * b[4] - a[1] * b[5] - a[2] * b[6]};
}
Mf vrml_to_dual_quaternion(const Mf& a) {
  const double len = std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
  double ax = 0, ay = 0, az = 0, s = 0, c = 1;
  if (len >= 0.01) {
    ax = a[0] / len, ay = a[1] / len, az = a[2] / len;
    s = std::sin(a[3] / 2), c = std::cos(a[3] / 2);
  }
  const double vx = a[4] / 2, vy = a[5] / 2, vz = a[6] / 2;
  return {ax * s, ay * s, az * s, c, vx * c + (vy * az - vz * ay) * s, vy * c + (vz * ax - vx * az) * s,
          vz * c + (vx * ay - vy * ax) * s, -(ax * vx + ay * vy + az * vz) * s};
}
Mf vrml_from_dual_quaternion(const Mf& q) {
  const double s = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  if (s < 0.01) return {0, 0, 1, 0, 0, 0, 0, 0};
  Mf qu;
  for (int i = 0; i < 8; ++i) qu[static_cast<std::size_t>(i)] = q[static_cast<std::size_t>(i)] / s;
  const Mf rot_part{-qu[0], -qu[1], -qu[2], qu[3], 0, 0, 0, 0};
  const Mf trans = vrml_multiply(qu, rot_part);
  const double len = std::sqrt(qu[0] * qu[0] + qu[1] * qu[1] + qu[2] * qu[2]);
  if (len < 0.01) return {0, 0, 1, 0, 2 * trans[4], 2 * trans[5], 2 * trans[6], 0};
  return {qu[0] / len, qu[1] / len, qu[2] / len, 2 * std::acos(qu[3]), 2 * trans[4], 2 * trans[5], 2 * trans[6], 0};
}

TEST(SeedErrata, VrmlToDualQuaternionDropsShortAxes) {
  // An axis of length 0.005 is a valid direction; the listing treats it as no rotation.
  const Mf node{0.005, 0, 0, 1.0, 0, 0, 0, 0};
  EXPECT_EQ(vrml_to_dual_quaternion(node)[3], 1.0);  // identity real part
  const DualQuaternion<double> ours = from_vrml(VrmlTransform<double>{{0.005, 0, 0}, 1.0, {}, {}});
  EXPECT_NEAR(ours.real.w, std::cos(0.5), 1e-16);
}

TEST(SeedErrata, VrmlFromDualQuaternionDropsSmallRotations) {
  // A 1° rotation: |sin(θ/2)| ≈ 0.0087 < 0.01, so the listing returns no rotation at all.
  const double one_degree = std::acos(-1.0) / 180;
  const Mf q = vrml_to_dual_quaternion({0, 1, 0, one_degree, 1, 2, 3, 0});
  const Mf back = vrml_from_dual_quaternion(q);
  EXPECT_EQ(back[3], 0.0);
  const VrmlTransform<double> ours =
      to_vrml(from_vrml(VrmlTransform<double>{{0, 1, 0}, one_degree, {1, 2, 3}, {}}));
  EXPECT_NEAR(ours.angle, one_degree, 1e-16);
}

TEST(SeedErrata, VrmlFromDualQuaternionLosesTheTranslationOfSmallRealParts) {
  // A valid but scaled dual quaternion whose real part has norm < 0.01 returns all zeros.
  Mf q = vrml_to_dual_quaternion({0, 0, 1, 0, 5, 0, 0, 0});
  for (double& v : q) v *= 0.001;
  EXPECT_EQ(vrml_from_dual_quaternion(q)[4], 0.0);
  const DualQuaternion<double> ours = DualQuaternion<double>::from_translation(Vec3<double>{5, 0, 0}) * 0.001;
  EXPECT_NEAR(to_vrml(ours).translation.x, 5.0, 1e-12);
}

TEST(SeedErrata, VrmlAcosLosesDigitsNearZero) {
  // 2 acos(w) for a tiny angle: acos has an infinite slope at 1, so the angle of a 1e-9 rotation
  // is returned with only about half the digits (or as 0). dqkit uses 2 atan2(|v|, w).
  const double angle = 0.02;  // above the listing's threshold, so the acos branch is taken
  const Mf q = vrml_to_dual_quaternion({1, 0, 0, angle, 0, 0, 0, 0});
  const double listing = vrml_from_dual_quaternion(q)[3];
  const double ours = Quaternion<double>(q[3], q[0], q[1], q[2]).to_axis_angle().angle;
  EXPECT_LE(std::abs(ours - angle), std::abs(listing - angle));
  EXPECT_NEAR(ours, angle, 1e-17);
  // At 1e-7 the acos form has lost about half the digits: 2 acos(cos(5e-8)) is off by ~1e-9.
  const double tiny = 1e-7;
  const double w = std::cos(tiny / 2);
  EXPECT_GT(std::abs(2 * std::acos(w) - tiny), 1e-10);
  EXPECT_NEAR(Quaternion<double>(w, std::sin(tiny / 2), 0, 0).to_axis_angle().angle, tiny, 1e-22);
}

TEST(SeedErrata, VrmlDualSineFormula) {
  // The tutorial prints sin(â) = sin(a) + ε cos(a_ε); the correct rule is sin(a) + ε a_ε cos(a).
  const Dual<double> x(0.4, 3.0);
  EXPECT_NEAR(sin(x).dual, 3.0 * std::cos(0.4), 1e-16);
  EXPECT_GT(std::abs(sin(x).dual - std::cos(3.0)), 1.0);
}

}  // namespace

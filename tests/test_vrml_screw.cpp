// VRML Transform and screw parameters ↔ dual quaternions, including every degenerate input.
#include <gtest/gtest.h>

#include <cmath>

#include "support.hpp"

namespace {

using namespace dq;
using dq::test::max_abs_diff;
using dq::test::Random;

/// Independent reference for a VRML Transform: apply T·C·R·C⁻¹ to a point step by step.
Vec3<double> vrml_apply(const VrmlTransform<double>& v, const Vec3<double>& p) {
  const double n = norm(v.axis);
  if (n == 0) return p + v.translation;
  // Rodrigues' formula, written out.
  const Vec3<double> k = v.axis / n;
  const Vec3<double> x = p - v.center;
  const Vec3<double> rot = x * std::cos(v.angle) + cross(k, x) * std::sin(v.angle) + k * (dot(k, x) * (1 - std::cos(v.angle)));
  return rot + v.center + v.translation;
}

TEST(Vrml, FromVrmlMatchesTheNodeSemantics) {
  Random rng(81);
  for (int n = 0; n < 2000; ++n) {
    VrmlTransform<double> v{rng.vec3<double>(1), rng.uniform(-7.0, 7.0), rng.vec3<double>(10), rng.vec3<double>(3)};
    if (n % 5 == 0) v.axis = v.axis * 1e-4;  // short axes are still directions
    const Vec3<double> p = rng.vec3<double>(5);
    EXPECT_LE(max_abs_diff(from_vrml(v).transform_point(p), vrml_apply(v, p)), 1e-12);
  }
}

TEST(Vrml, RoundTripAndDegenerateInputs) {
  Random rng(82);
  for (int n = 0; n < 2000; ++n) {
    const DualQuaternion<double> q = rng.rigid<double>();
    const Vec3<double> center = n % 2 ? rng.vec3<double>(3) : Vec3<double>{};
    const VrmlTransform<double> v = to_vrml(q, center);
    EXPECT_GE(v.angle, 0.0);
    EXPECT_LE(v.angle, pi_v<double>);
    EXPECT_TRUE(approx_equal(from_vrml(v), q, 1e-12, SignPolicy::same_rotation));
  }
  // Identity: VRML's default rotation 0 0 1 0.
  const VrmlTransform<double> id = to_vrml(DualQuaternion<double>::identity());
  EXPECT_EQ(id.axis, (Vec3<double>{0, 0, 1}));
  EXPECT_EQ(id.angle, 0.0);
  // A 1° rotation is kept (the tutorial's 0.01 threshold dropped rotations under about 1.15°).
  const double one_degree = pi_v<double> / 180;
  const auto small = DualQuaternion<double>::from_rotation_translation(
      Quaternion<double>::from_axis_angle(Vec3<double>{0, 1, 0}, one_degree), Vec3<double>{1, 2, 3});
  const VrmlTransform<double> sv = to_vrml(small);
  EXPECT_NEAR(sv.angle, one_degree, 1e-15);
  EXPECT_LE(max_abs_diff(sv.axis, Vec3<double>{0, 1, 0}), 1e-15);
  EXPECT_LE(max_abs_diff(sv.translation, Vec3<double>{1, 2, 3}), 1e-15);
  // Half turn: exact angle π (acos would lose half the digits near it).
  const auto half = DualQuaternion<double>::from_rotation(Quaternion<double>(0, 0, 1, 0));
  EXPECT_EQ(to_vrml(half).angle, pi_v<double>);
  // Zero axis: identity rotation whatever the angle; translation kept.
  const VrmlTransform<double> zero_axis{{0, 0, 0}, 2.0, {1, 2, 3}, {}};
  EXPECT_LE(max_abs_diff(from_vrml(zero_axis).transform_point(Vec3<double>{1, 1, 1}), Vec3<double>{2, 3, 4}), 0.0);
  // A scaled (non-unit) dual quaternion: the translation survives (the tutorial dropped it when
  // the real part was small).
  const auto scaled = DualQuaternion<double>::from_translation(Vec3<double>{5, 0, 0}) * 0.001;
  EXPECT_LE(max_abs_diff(to_vrml(scaled).translation, Vec3<double>{5, 0, 0}), 1e-12);
}

TEST(Screw, RoundTripAndAgainstTheAxisConstruction) {
  Random rng(83);
  for (int n = 0; n < 2000; ++n) {
    const DualQuaternion<double> q = rng.rigid<double>();
    const Screw<double> s = to_screw(q);
    EXPECT_GE(s.angle, 0.0);
    EXPECT_LE(s.angle, pi_v<double>);
    EXPECT_NEAR(norm(s.axis.direction), 1.0, 1e-15);
    EXPECT_NEAR(dot(s.axis.direction, s.axis.moment), 0.0, 1e-11);  // Plücker identity
    EXPECT_TRUE(approx_equal(from_screw(s), q, 1e-11, SignPolicy::same_rotation));
    // Independent check: rotate about the axis through c = l × m, then slide d along it.
    const Vec3<double> c = s.axis.closest_point_to_origin(), p = rng.vec3<double>(5);
    const Quaternion<double> r = Quaternion<double>::from_axis_angle(s.axis.direction, s.angle);
    const Vec3<double> expected = r.rotate(p - c) + c + s.axis.direction * s.translation;
    EXPECT_LE(max_abs_diff(q.transform_point(p), expected), 1e-10);
  }
}

TEST(Screw, PureTranslationsAndIdentityAreExact) {
  const Vec3<double> t{3, -4, 12};
  const Screw<double> s = to_screw(DualQuaternion<double>::from_translation(t));
  EXPECT_EQ(s.angle, 0.0);
  EXPECT_EQ(s.translation, 13.0);
  EXPECT_LE(max_abs_diff(s.axis.direction, Vec3<double>{3.0 / 13, -4.0 / 13, 12.0 / 13}), 1e-16);
  EXPECT_EQ(s.axis.moment, (Vec3<double>{0, 0, 0}));
  EXPECT_EQ(from_screw(s).real, Quaternion<double>::identity());
  EXPECT_LE(max_abs_diff(from_screw(s).translation(), t), 1e-15);
  const Screw<double> id = to_screw(DualQuaternion<double>::identity());
  EXPECT_EQ(id.angle, 0.0);
  EXPECT_EQ(id.translation, 0.0);
  EXPECT_EQ(from_screw(id), DualQuaternion<double>::identity());
  // −Q (w < 0) gives the same screw as Q.
  const Screw<double> neg = to_screw(-DualQuaternion<double>::from_translation(t));
  EXPECT_EQ(neg.translation, 13.0);
}

TEST(Screw, RotationsBelowRoundoffAreTranslations) {
  // θ = 2e-20 with a huge translation: the axis would lie 1e300 away; it is a translation.
  const auto q = DualQuaternion<double>::from_rotation_translation(Quaternion<double>(1, 1e-20, 0, 0).normalized(), {0, 1e280, 0});
  const Screw<double> s = to_screw(q);
  EXPECT_EQ(s.angle, 0.0);
  EXPECT_EQ(s.translation, 1e280);
  EXPECT_TRUE(std::isfinite(s.axis.moment.x));
  EXPECT_TRUE(approx_equal(from_screw(s).real, q.real, 1e-16));
}

TEST(Screw, DualAngleThroughDualNumbers) {
  // Q = cos(θ̂/2) + ŝ sin(θ̂/2) evaluated with Dual<double> functions equals from_screw.
  const Screw<double> s{PluckerLine<double>::through({1, 2, 0}, {0, 0, 1}), 1.2, 0.7};
  const Dual<double> half = s.dual_angle() * 0.5;
  const Dual<double> c = cos(half), sn = sin(half);
  const Vec3<double> l = s.axis.direction, m = s.axis.moment;
  const DualQuaternion<double> expected{Quaternion<double>(c.real, l * sn.real), Quaternion<double>(c.dual, m * sn.real + l * sn.dual)};
  EXPECT_LE(max_abs_diff(from_screw(s), expected), 1e-16);
}

}  // namespace

// Numerical robustness at the edges of float and double: denormals, huge translations, angles
// within ulps of 0 and π, nearly antipodal blends, quaternions far from unit norm, long
// accumulation, and the NaN policy. Each assertion is a documented bound (docs/reliability.md).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>

#include "support.hpp"

namespace {

using namespace dq;
using dq::test::max_abs_diff;

template <class T>
bool finite(const Quaternion<T>& q) {
  return std::isfinite(q.w) && std::isfinite(q.x) && std::isfinite(q.y) && std::isfinite(q.z);
}
template <class T>
bool finite(const DualQuaternion<T>& q) {
  return finite(q.real) && finite(q.dual);
}

template <class T>
class Robustness : public ::testing::Test {};
using Types = ::testing::Types<float, double>;
TYPED_TEST_SUITE(Robustness, Types);

TYPED_TEST(Robustness, DenormalInputs) {
  using T = TypeParam;
  const T den = std::numeric_limits<T>::denorm_min();
  const Quaternion<T> q(den, 3 * den, 0, -den);
  const Quaternion<T> u = q.normalized();
  EXPECT_TRUE(finite(u));
  EXPECT_NEAR(static_cast<double>(u.norm()), 1.0, 1e-6);
  const DualQuaternion<T> d(q, Quaternion<T>(0, den, den, den));
  EXPECT_TRUE(finite(d.normalized()));
  // Products of denormal-sized parts underflow to zero, not to NaN.
  EXPECT_TRUE(finite(q * q));
  EXPECT_TRUE(finite(slerp(Quaternion<T>::identity(), Quaternion<T>(1, den, 0, 0), T(0.5))));
}

TYPED_TEST(Robustness, HugeTranslations) {
  using T = TypeParam;
  const T big = std::is_same_v<T, float> ? T(1e30) : T(1e300);
  const Quaternion<T> r = Quaternion<T>::from_axis_angle({1, 2, 3}, T(0.7));
  const DualQuaternion<T> q = DualQuaternion<T>::from_rotation_translation(r, {big, -big, big / 2});
  const Vec3<T> t = q.translation();
  EXPECT_LE(std::abs(t.x - big) / big, dq::test::tol<T>(8));
  const DualQuaternion<T> n = (q * T(3)).normalized();
  EXPECT_TRUE(finite(n));
  EXPECT_LE(std::abs(n.translation().y + big) / big, dq::test::tol<T>(16));
  const Vec3<T> p = q.transform_point({1, 1, 1});
  EXPECT_TRUE(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z));
  // sclerp between two far-apart huge transforms stays finite and unit.
  const DualQuaternion<T> b = DualQuaternion<T>::from_rotation_translation(r.conjugate(), {-big, big, 0});
  const DualQuaternion<T> m = sclerp(q, b, T(0.5));
  EXPECT_TRUE(finite(m));
  EXPECT_TRUE(m.is_unit(dq::test::tol<T>(64)));
  const Screw<T> s = to_screw(q);
  EXPECT_TRUE(std::isfinite(s.angle) && std::isfinite(s.translation));
  EXPECT_TRUE(std::isfinite(to_vrml(q).translation.x));
}

TYPED_TEST(Robustness, AnglesWithinUlpsOfZeroAndPi) {
  using T = TypeParam;
  const Vec3<T> axis = normalized(Vec3<T>{1, -2, 2});
  for (int k = 0; k < 64; ++k) {
    const T below_pi = std::nextafter(pi_v<T>, T(0)) - T(k) * std::numeric_limits<T>::epsilon();
    const T tiny = std::ldexp(T(1), -20 - k);
    for (T angle : {below_pi, tiny}) {
      const Quaternion<T> q = Quaternion<T>::from_axis_angle(axis, angle);
      const AxisAngle<T> aa = q.to_axis_angle();
      EXPECT_LE(std::abs(aa.angle - angle), dq::test::tol<T>(4) * (T(1) + angle)) << angle;
      EXPECT_LE(max_abs_diff(aa.axis, axis), dq::test::tol<T>(64)) << angle;  // axis kept even at tiny angles
      const DualQuaternion<T> d = DualQuaternion<T>::from_rotation_translation(q, {1, 2, 3});
      EXPECT_TRUE(approx_equal(exp(log(d)), d, dq::test::tol<T>(1024)));
      EXPECT_TRUE(finite(sclerp(DualQuaternion<T>::identity(), d, T(0.3))));
    }
  }
}

TYPED_TEST(Robustness, NearlyAntipodalBlends) {
  using T = TypeParam;
  const T e = std::numeric_limits<T>::epsilon();
  const Quaternion<T> a = Quaternion<T>::from_axis_angle({0, 1, 0}, T(0.3));
  const Quaternion<T> b = (-a + Quaternion<T>(0, e, 0, -e)).normalized();  // the same rotation, other sign
  const DualQuaternion<T> qa = DualQuaternion<T>::from_rotation_translation(a, {1, 0, 0});
  const DualQuaternion<T> qb = DualQuaternion<T>::from_rotation_translation(b, {1, 0, 0});
  const std::array<DualQuaternion<T>, 2> qs{qa, qb};
  for (T w : {T(0), T(0.25), T(0.5), T(0.75), T(1)}) {
    const std::array<T, 2> weights{T(1) - w, w};
    const DualQuaternion<T> m = dlb<T>(qs, weights);
    EXPECT_TRUE(m.is_unit(dq::test::tol<T>(16)));
    EXPECT_TRUE(approx_equal(m, qa, dq::test::tol<T>(64), SignPolicy::same_rotation));  // no collapse to zero
    EXPECT_TRUE(approx_equal(slerp(a, b, w), a, dq::test::tol<T>(16), SignPolicy::same_rotation));
  }
  // Exactly antipodal real parts with equal weights and no pivot alignment would sum to zero; the
  // pivot policy aligns them, so the blend is the shared rotation.
  const std::array<DualQuaternion<T>, 2> opposite{qa, -qa};
  const std::array<T, 2> half{T(0.5), T(0.5)};
  EXPECT_TRUE(approx_equal(dlb<T>(opposite, half), qa, dq::test::tol<T>(8), SignPolicy::same_rotation));
}

TYPED_TEST(Robustness, NormsFarFromOne) {
  using T = TypeParam;
  for (T scale : {T(1e-20), T(1e-5), T(1e5), T(1e20)}) {
    const Quaternion<T> r = Quaternion<T>::from_axis_angle({3, 1, -1}, T(1.2));
    const Quaternion<T> s = r * scale;
    EXPECT_LE(max_abs_diff(s.normalized(), r), dq::test::tol<T>(4));
    EXPECT_LE(dq::test::rotation_diff(slerp(s, Quaternion<T>::identity() * scale, T(0)), r), dq::test::tol<T>(4));
    const DualQuaternion<T> d = DualQuaternion<T>::from_rotation_translation(r, {1, 2, 3}) * scale;
    EXPECT_TRUE(approx_equal(d.normalized(), DualQuaternion<T>::from_rotation_translation(r, {1, 2, 3}), dq::test::tol<T>(32)));
    EXPECT_TRUE(approx_equal(to_vrml(d).translation == Vec3<T>{} ? DualQuaternion<T>{} : from_vrml(to_vrml(d)),
                             DualQuaternion<T>::from_rotation_translation(r, {1, 2, 3}), dq::test::tol<T>(64), SignPolicy::same_rotation));
  }
}

TEST(Robustness, MillionCompositions) {
  // One million products of a unit dual quaternion with itself: documented bounds of the drift of
  // the unit condition without renormalization, and with renormalization every step.
  const auto step_d = DualQuaternion<double>::from_rotation_translation(Quaternion<double>::from_axis_angle({1, 2, 3}, 0.001), {1e-3, 0, 2e-3});
  const DualQuaternion<float> step_f{float(step_d.real.w), float(step_d.real.x), float(step_d.real.y), float(step_d.real.z),
                                     float(step_d.dual.w),  float(step_d.dual.x), float(step_d.dual.y), float(step_d.dual.z)};
  DualQuaternion<double> free_d, kept_d;
  DualQuaternion<float> free_f, kept_f;
  for (int i = 0; i < 1000000; ++i) {
    free_d = free_d * step_d;
    kept_d = (kept_d * step_d).normalized();
    free_f = free_f * step_f;
    kept_f = (kept_f * step_f).normalized();
  }
  // Without renormalization the norm error grows (a random walk of roundoff); with it, it stays at
  // the roundoff of one step.
  EXPECT_LE(std::abs(free_d.real.norm() - 1), 1e-10);
  EXPECT_LE(std::abs(free_f.real.norm() - 1.0f), 5e-2f);
  EXPECT_LE(std::abs(kept_d.real.norm() - 1), 4e-16);
  EXPECT_LE(std::abs(kept_f.real.norm() - 1.0f), 2.4e-7f);
  EXPECT_LE(std::abs(dot(kept_f.real, kept_f.dual)), 1e-3f);  // relative to a translation of ~2000
  EXPECT_TRUE(kept_d.is_unit(1e-14));
  // The renormalized double result stays on the exact screw: step^1e6 by the screw power.
  const DualQuaternion<double> exact = pow(step_d, 1e6);
  EXPECT_TRUE(approx_equal(kept_d, exact, 1e-8, SignPolicy::same_rotation));
}

TEST(Robustness, NaNPolicy) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const Quaternion<double> q(nan, 0, 0, 1);
  EXPECT_TRUE(std::isnan(q.normalized().w));
  EXPECT_TRUE(std::isnan((q * Quaternion<double>::identity()).w));
  const DualQuaternion<double> d(q, Quaternion<double>(0, 0, 0, 0));
  EXPECT_TRUE(std::isnan(d.normalized().real.w));
  EXPECT_TRUE(std::isnan(slerp(q, Quaternion<double>::identity(), 0.5).w + slerp(q, Quaternion<double>::identity(), 0.5).z));
  // Documented fallbacks for degenerate but finite input: identity, never NaN.
  EXPECT_EQ(Quaternion<double>(0, 0, 0, 0).normalized(), Quaternion<double>::identity());
  EXPECT_EQ(DualQuaternion<double>(0, 0, 0, 0, 1, 2, 3, 4).normalized(), DualQuaternion<double>::identity());
  EXPECT_EQ(Quaternion<double>::from_axis_angle({0, 0, 0}, 1.0), Quaternion<double>::identity());
  const std::array<DualQuaternion<double>, 1> none{DualQuaternion<double>::identity()};
  const std::array<double, 1> zero{0.0};
  EXPECT_EQ(dlb<double>(none, zero), DualQuaternion<double>::identity());
}

// ---- the NaN policy, class by class (docs/reliability.md) ------------------------------------------

TEST(NaNPolicy, DenormalInputsGiveUnitResults) {
  const double den = std::numeric_limits<double>::denorm_min();
  for (const double a : {den, 3 * den, 1e-310}) {
    const Quaternion<double> q = Quaternion<double>::from_axis_angle({a, 0, 0}, 1.0);
    EXPECT_TRUE(std::isfinite(q.x)) << a;
    EXPECT_NEAR(q.squared_norm(), 1.0, 4 * test::tol<double>(1)) << a;
    const DualQuaternion<double> d = DualQuaternion<double>(a, a, 0, 0, 0, 0, a, 0).normalized();
    EXPECT_NEAR(dot(d.real, d.real), 1.0, 4 * test::tol<double>(1)) << a;
    EXPECT_NEAR(dot(d.real, d.dual), 0.0, 4 * test::tol<double>(1)) << a;
  }
  const Quaternion<float> f = Quaternion<float>::from_axis_angle({1e-45f, 0, 0}, 1.0f);
  EXPECT_NEAR(f.squared_norm(), 1.0f, 4 * test::tol<float>(1));
}

TEST(NaNPolicy, NaNInputsNeverBecomeFinite) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  auto has_nan = [](const auto& q) {
    const auto* c = &q.real.w;
    for (int i = 0; i < 8; ++i)
      if (std::isnan(c[i])) return true;
    return false;
  };
  EXPECT_TRUE(std::isnan(Quaternion<double>::from_axis_angle({0, 0, 0}, nan).w));
  VrmlTransform<double> v;
  v.axis = {0, 0, 0};
  v.angle = nan;
  EXPECT_TRUE(has_nan(from_vrml(v)));
  v.angle = 1;
  v.center = {nan, 0, 0};
  EXPECT_TRUE(has_nan(from_vrml(v)));
  for (const Quaternion<double>& q : {Quaternion<double>(nan, 0, 0, 0), Quaternion<double>(1, nan, 0, 0)}) {
    const AxisAngle<double> aa = q.to_axis_angle();
    EXPECT_TRUE(std::isnan(aa.angle) && std::isnan(aa.axis.x) && std::isnan(aa.axis.y)) << q;
  }
  // dlb whose weights cancel the real parts while a dual part is NaN.
  const std::array<DualQuaternion<double>, 2> qs{DualQuaternion<double>(1, 0, 0, 0, 0, nan, 0, 0),
                                                 DualQuaternion<double>::identity()};
  const std::array<double, 2> cancelling{1.0, -1.0};
  EXPECT_TRUE(has_nan(dlb(qs, cancelling)));
  EXPECT_TRUE(has_nan(DualQuaternion<double>(0, 0, 0, 0, nan, 0, 0, 0).normalized()));
  Mat4<double> m = to_mat4(DualQuaternion<double>::identity());
  m(3, 1) = nan;
  EXPECT_TRUE(has_nan(from_matrix(m)));
  m(3, 1) = 0;
  EXPECT_FALSE(has_nan(from_matrix(m)));
  // slerp at its endpoints: t = 1 once returned b whatever a was.
  for (const double t : {0.0, 1.0}) {
    const Quaternion<double> q = Quaternion<double>::from_axis_angle({0, 1, 0}, 0.4);
    const Quaternion<double> from_nan = slerp(Quaternion<double>(nan, 0, 0, 0), q, t), to_nan = slerp(q, Quaternion<double>(nan, 0, 0, 0), t);
    EXPECT_TRUE(std::isnan(from_nan.w) || std::isnan(from_nan.x)) << t;
    EXPECT_TRUE(std::isnan(to_nan.w) || std::isnan(to_nan.x)) << t;
    const Quaternion<float> f = slerp(Quaternion<float>(std::nanf(""), 0, 0, 0), q.cast<float>(), static_cast<float>(t));
    EXPECT_TRUE(std::isnan(f.w) || std::isnan(f.x)) << t;
  }
}

TEST(NaNPolicy, InfiniteInputsEndAndStayNonFinite) {
  // Found by fuzz_math: an infinite real part made normalized() rescale forever.
  const double inf = std::numeric_limits<double>::infinity();
  const DualQuaternion<double> q = DualQuaternion<double>(inf, 1, 0, 0, 0, 0, 0, 0).normalized();
  EXPECT_FALSE(std::isfinite(q.real.w) && std::isfinite(q.real.x) && std::isfinite(q.dual.w));
}

TEST(NaNPolicy, DivisionByZeroIsInfiniteLikeForReals) {
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_EQ(Quaternion<double>(0, 0, 0, 0).inverse(), Quaternion<double>(inf, 0, 0, 0));
  EXPECT_EQ(DualQuaternion<double>(0, 0, 0, 0, 1, 2, 3, 4).inverse().real, Quaternion<double>(inf, 0, 0, 0));
  // Tiny but representable: the inverse is exact, not inf/NaN from an underflowed |q|².
  EXPECT_EQ(Quaternion<double>(1e-200, 0, 0, 0).inverse(), Quaternion<double>(1e200, 0, 0, 0));
}

TEST(NaNPolicy, HugeExtrapolationStaysFinite) {
  // sclerp(a, b, 1e160): the screw scaled by 1e160 has a representable translation (~1e160).
  const auto a = DualQuaternion<double>::from_rotation_translation(Quaternion<double>::from_axis_angle({0, 0, 1}, 0.3), {1, 2, 3});
  const auto b = DualQuaternion<double>::from_rotation_translation(Quaternion<double>::from_axis_angle({0, 1, 1}, 0.7), {-1, 2, 5});
  const DualQuaternion<double> far = sclerp(a, b, 1e160);
  for (const double c : {far.real.w, far.real.x, far.real.y, far.real.z, far.dual.w, far.dual.x, far.dual.y, far.dual.z})
    EXPECT_TRUE(std::isfinite(c));
  EXPECT_NEAR(dot(far.real, far.real), 1.0, 1e-15);
  // The translation along the screw axis grows linearly: compare with the screw's own d × t.
  const Screw<double> s = to_screw(a.conjugate() * b);
  EXPECT_NEAR(dot((a.conjugate() * far).translation(), s.axis.direction) / (s.translation * 1e160), 1.0, 1e-6);
}

}  // namespace

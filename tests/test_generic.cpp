// The generic property harness: every operation, for every scalar (float, double, long double,
// Dual<double>, HyperDual<double>), at generic inputs, at the identity, near θ = π and for q
// versus −q.
//
// An operation is checked along a path x ↦ inputs(x) through its input space, written once as a
// generic lambda. Values are compared with the same lambda evaluated in long double; first and
// second derivatives (the ε parts of Dual and HyperDual) with fourth-order central finite
// differences of the long-double evaluation, and, where the answer is known in closed form, with
// that. Every constant of a path is a multiple of 1/64, so each scalar type sees the same input.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <string>

#include "dq/dq.hpp"

namespace {

using namespace dq;
using LD = long double;

// ---- the harness --------------------------------------------------------------------------------

template <class S>
S seed(LD x) {  // the path parameter, as a variable of S
  if constexpr (std::is_same_v<S, Dual<double>>) return Dual<double>::variable(static_cast<double>(x));
  else if constexpr (std::is_same_v<S, HyperDual<double>>) return HyperDual<double>::variable(static_cast<double>(x));
  else return static_cast<S>(x);
}

template <class F>
auto at(const F& f, LD x) {
  return f(x);
}
/// f'(x) and f''(x) of the long-double evaluation, fourth-order central differences. Truncation
/// h⁴ f⁽⁵⁾/30 and h⁴ f⁽⁶⁾/90 (about 1e-12 for h = 1e-3 and derivatives of order one), rounding
/// 1e-19/h and 6e-19/h² (1e-16 and 6e-13): far below the tolerances used, far above a wrong answer.
template <class F>
auto finite_differences(const F& f, LD x) {
  const LD h = 1e-3L;
  const auto m2 = f(x - 2 * h), m1 = f(x - h), p0 = f(x), p1 = f(x + h), p2 = f(x + 2 * h);
  auto d1 = p0, d2 = p0;
  for (std::size_t i = 0; i < p0.size(); ++i) {
    d1[i] = (8 * (p1[i] - m1[i]) - (p2[i] - m2[i])) / (12 * h);
    d2[i] = (-p2[i] + 16 * p1[i] - 30 * p0[i] + 16 * m1[i] - m2[i]) / (12 * h * h);
  }
  return std::pair{d1, d2};
}

template <class S>
constexpr double value_tolerance() {  // relative to (1 + |value|), times the case's conditioning
  return 64 * static_cast<double>(std::numeric_limits<real_t<S>>::epsilon());
}
constexpr double first_derivative_tolerance = 1e-9;   // relative to (1 + max |f'|): see above
constexpr double second_derivative_tolerance = 1e-7;  // relative to (1 + max |f''|)

template <class A>
LD largest(const A& a) {
  LD m = 0;
  for (LD v : a) m = std::max(m, std::abs(v));
  return m;
}

/// Checks one operation along one path at x0, for scalar S. `conditioning` widens the value
/// tolerance where the operation itself amplifies rounding (named at the call).
template <class S, class F>
void check(const std::string& name, LD x0, const F& f, double conditioning = 1) {
  SCOPED_TRACE(name + " at x = " + std::to_string(static_cast<double>(x0)));
  const auto ref = f(x0);
  const auto got = f(seed<S>(x0));
  static_assert(std::tuple_size_v<decltype(ref)> == std::tuple_size_v<decltype(got)>);
  const double vt = value_tolerance<S>() * conditioning;
  for (std::size_t i = 0; i < ref.size(); ++i)
    EXPECT_NEAR(static_cast<double>(value_of(got[i])), static_cast<double>(ref[i]), vt * (1 + static_cast<double>(std::abs(ref[i]))))
        << "value " << i;
  if constexpr (std::is_same_v<S, Dual<double>> || std::is_same_v<S, HyperDual<double>>) {
    const auto [d1, d2] = finite_differences(f, x0);
    const double t1 = first_derivative_tolerance * (1 + static_cast<double>(largest(d1)));
    const double t2 = second_derivative_tolerance * (1 + static_cast<double>(largest(d2)));
    for (std::size_t i = 0; i < ref.size(); ++i) {
      if constexpr (std::is_same_v<S, Dual<double>>) {
        EXPECT_NEAR(got[i].dual, static_cast<double>(d1[i]), t1) << "first derivative " << i;
      } else {
        EXPECT_NEAR(got[i].e1, static_cast<double>(d1[i]), t1) << "first derivative (ε1) " << i;
        EXPECT_NEAR(got[i].e2, static_cast<double>(d1[i]), t1) << "first derivative (ε2) " << i;
        EXPECT_NEAR(got[i].e12, static_cast<double>(d2[i]), t2) << "second derivative " << i;
      }
    }
  }
}

template <class S>
S c(double v) {  // a path constant (multiples of 1/64 only: exact in every S)
  return S(static_cast<real_t<S>>(v));
}
template <class S>
Quaternion<S> quat(double w, double x, double y, double z) {
  return {c<S>(w), c<S>(x), c<S>(y), c<S>(z)};
}
template <class S>
Vec3<S> vec(double x, double y, double z) {
  return {c<S>(x), c<S>(y), c<S>(z)};
}
template <class S>
std::array<S, 4> parts(const Quaternion<S>& q) {
  return {q.w, q.x, q.y, q.z};
}
template <class S>
std::array<S, 8> parts(const DualQuaternion<S>& q) {
  return {q.real.w, q.real.x, q.real.y, q.real.z, q.dual.w, q.dual.x, q.dual.y, q.dual.z};
}
template <class S>
std::array<S, 3> parts(const Vec3<S>& v) {
  return {v.x, v.y, v.z};
}

// Base rotations: generic, the identity, and one 1/64 rad short of a half turn.
template <class S>
Quaternion<S> rotation(int which) {
  switch (which) {
    case 0: return Quaternion<S>::from_rotation_vector(vec<S>(0.375, -0.5, 0.625));
    case 1: return Quaternion<S>::identity();
    default: return Quaternion<S>::from_axis_angle(vec<S>(0.25, 0.75, -0.5), S(pi_v<S>) - c<S>(1.0 / 64));
  }
}
template <class S>
DualQuaternion<S> transform(int which) {
  return DualQuaternion<S>::from_rotation_translation(rotation<S>(which), which == 1 ? vec<S>(0, 0, 0) : vec<S>(1.5, -0.75, 2.25));
}
const char* const kWhere[] = {"generic", "identity", "near pi"};

/// The paths of the checks: q(x) = base · exp(x η) through the rotations around a base, and
/// Q(x) = base · exp(x ξ) through the rigid transforms around one, ξ a generic screw.
template <class X>
Quaternion<X> rotation_path(int which, X x) {
  return rotation<X>(which) * exp(Quaternion<X>::pure(vec<X>(0.5, 0.25, -0.75) * x));
}
template <class X>
DualQuaternion<X> transform_path(int which, X x) {
  const DualQuaternion<X> xi{Quaternion<X>::pure(vec<X>(0.5, 0.25, -0.75)), Quaternion<X>::pure(vec<X>(1.25, -0.5, 0.75))};
  return transform<X>(which) * exp(xi * x);
}
// The path parameter: a generic value, or 0 at the identity (the limit itself) and near π (so
// that the path stays on one side of the half turn).
LD start(int which) { return which == 0 ? 0.3125L : 0.0L; }

template <class S>
class Generic : public ::testing::Test {};
using Scalars = ::testing::Types<float, double, long double, Dual<double>, HyperDual<double>>;
TYPED_TEST_SUITE(Generic, Scalars);

// ---- scalar functions ----------------------------------------------------------------------------

TYPED_TEST(Generic, ElementaryFunctions) {
  using S = TypeParam;
  using std::abs, std::atan2, std::cbrt, std::exp, std::expm1, std::hypot, std::log1p, std::max, std::min, std::pow,
      std::sqrt;
  check<S>("expm1", 0.3125L, [](auto x) { return std::array{expm1(x), expm1(x * x)}; });
  check<S>("expm1 at 0", 0.0L, [](auto x) { return std::array{expm1(x)}; });
  check<S>("pow(scalar, x)", 0.3125L, [](auto x) {
    using X = decltype(x);
    return std::array{pow(c<X>(2.5), x)};
  });
  check<S>("pow(x, integer)", 0.625L, [](auto x) { return std::array{pow(x, 2), pow(x, 3)}; });
  check<S>("abs below 0", -0.75L, [](auto x) { return std::array{abs(x)}; });
  check<S>("abs above 0", 0.75L, [](auto x) { return std::array{abs(x)}; });
  check<S>("min and max", 0.375L, [](auto x) {
    using X = decltype(x);
    return std::array{min(x, c<X>(0.5)), max(x, c<X>(0.5)), min(x * x, x), max(x * x, x)};
  });
  check<S>("sqrt cbrt log1p hypot atan2", 0.6875L, [](auto x) {
    using X = decltype(x);
    return std::array{sqrt(x), cbrt(x), log1p(x), hypot(x, c<X>(0.75)), atan2(x, c<X>(-0.5)), exp(-x)};
  });
}

// ---- quaternions ---------------------------------------------------------------------------------

TYPED_TEST(Generic, QuaternionExpLogAndRotationVectors) {
  using S = TypeParam;
  for (int which = 0; which < 3; ++which) {
    const std::string where = kWhere[which];
    const LD x0 = start(which);
    auto q_of = [which](auto x) { return rotation_path(which, x); };
    check<S>("log " + where, x0, [&](auto x) { return parts(log(q_of(x))); }, which == 2 ? 4 : 1);
    check<S>("to_rotation_vector " + where, x0, [&](auto x) { return parts(q_of(x).to_rotation_vector()); }, which == 2 ? 4 : 1);
    check<S>("from_rotation_vector " + where, x0, [&](auto x) {
      using X = decltype(x);
      return parts(Quaternion<X>::from_rotation_vector(rotation<X>(which).to_rotation_vector() + vec<X>(0.25, -0.5, 0.125) * x));
    });
    check<S>("exp " + where, x0, [&](auto x) {
      using X = decltype(x);
      return parts(exp(log(rotation<X>(which)) + Quaternion<X>(c<X>(0.125), vec<X>(0.25, -0.5, 0.125)) * x));
    });
    if (which != 1)  // the axis is undefined at the identity; the angle is |x|-like there
      check<S>("to_axis_angle " + where, x0, [&](auto x) {
        const auto aa = q_of(x).to_axis_angle();
        return std::array{aa.angle, aa.axis.x, aa.axis.y, aa.axis.z};
      }, which == 2 ? 8 : 1);
    check<S>("slerp (b moves) " + where, x0, [&](auto x) {
      using X = decltype(x);
      return parts(slerp(rotation<X>(0), q_of(x), c<X>(0.375)));
    }, 4);
    check<S>("slerp (t moves) " + where, x0, [&](auto x) {
      using X = decltype(x);
      return parts(slerp(rotation<X>(which), rotation<X>(0), x));
    }, 4);
    check<S>("normalized " + where, x0, [&](auto x) {
      using X = decltype(x);
      return parts((q_of(x) * (c<X>(1.5) + x)).normalized());
    });
    check<S>("rotate " + where, x0, [&](auto x) {
      using X = decltype(x);
      return parts(q_of(x).rotate(vec<X>(1, -2, 0.5)));
    });
    // q and −q: every rotation-valued result is the same rotation.
    check<S>("q vs -q " + where, x0, [&](auto x) {
      using X = decltype(x);
      const Quaternion<X> q = q_of(x);
      const Vec3<X> d = q.to_rotation_vector() - (-q).to_rotation_vector();
      const Vec3<X> r = slerp(rotation<X>(0), q, c<X>(0.375)).rotate(vec<X>(1, 2, 3)) -
                        slerp(rotation<X>(0), -q, c<X>(0.375)).rotate(vec<X>(1, 2, 3));
      return std::array{d.x, d.y, d.z, r.x, r.y, r.z};
    });
  }
}

// ---- dual quaternions -----------------------------------------------------------------------------

TYPED_TEST(Generic, DualQuaternionScrewCalculus) {
  using S = TypeParam;
  for (int which = 0; which < 3; ++which) {
    const std::string where = kWhere[which];
    const LD x0 = start(which);
    auto q_of = [which](auto x) { return transform_path(which, x); };
    const double cond = which == 2 ? 64 : 4;  // near a half turn the dual part of log grows like 1/sinc
    check<S>("log " + where, x0, [&](auto x) { return parts(log(q_of(x))); }, cond);
    check<S>("exp " + where, x0, [&](auto x) {
      using X = decltype(x);
      const DualQuaternion<X> xi{Quaternion<X>::pure(vec<X>(0.125, -0.25, 0.5)), Quaternion<X>::pure(vec<X>(0.75, 0.5, -0.25))};
      return parts(exp(log(transform<X>(which)) + xi * x));
    }, cond);
    check<S>("sclerp (b moves) " + where, x0, [&](auto x) {
      using X = decltype(x);
      return parts(sclerp(transform<X>(0), q_of(x), c<X>(0.375)));
    }, cond);
    check<S>("sclerp (t moves) " + where, x0, [&](auto x) {
      using X = decltype(x);
      return parts(sclerp(transform<X>(which), transform<X>(0), x));
    }, cond);
    check<S>("pow " + where, x0, [&](auto x) {
      using X = decltype(x);
      return parts(pow(q_of(x), c<X>(0.625)));
    }, cond);
    check<S>("dlb two keys " + where, x0, [&](auto x) {
      using X = decltype(x);
      return parts(dlb(transform<X>(0), q_of(x), c<X>(0.375)));
    }, 4);
    check<S>("normalized " + where, x0, [&](auto x) {
      using X = decltype(x);
      const DualQuaternion<X> q = q_of(x);
      return parts(DualQuaternion<X>(q.real * (c<X>(1.25) + x), q.dual * c<X>(1.25) + q.real * (x * c<X>(0.5))).normalized());
    });
    check<S>("transform_point " + where, x0, [&](auto x) {
      using X = decltype(x);
      return parts(q_of(x).transform_point(vec<X>(1, -2, 0.5)));
    });
    if (which == 0)  // the screw axis is undefined at the identity and flips at π
      check<S>("to_screw " + where, x0, [&](auto x) {
        const auto s = to_screw(q_of(x));
        return std::array{s.angle, s.translation, s.axis.direction.x, s.axis.moment.y};
      }, 8);
    check<S>("Q vs -Q " + where, x0, [&](auto x) {
      using X = decltype(x);
      const DualQuaternion<X> q = q_of(x);
      const Vec3<X> p = vec<X>(1, 2, 3);
      const Vec3<X> a = sclerp(transform<X>(0), q, c<X>(0.375)).transform_point(p) -
                        sclerp(transform<X>(0), -q, c<X>(0.375)).transform_point(p);
      const Vec3<X> b = dlb(transform<X>(0), q, c<X>(0.375)).transform_point(p) -
                        dlb(transform<X>(0), -q, c<X>(0.375)).transform_point(p);
      return std::array{a.x, a.y, a.z, b.x, b.y, b.z};
    }, 4);
  }
}

// ---- conversions and the remaining blends ------------------------------------------------------------

TYPED_TEST(Generic, ConversionsAndBlends) {
  using S = TypeParam;
  for (int which = 0; which < 3; ++which) {
    const std::string where = kWhere[which];
    const LD x0 = start(which);
    auto q_of = [which](auto x) { return rotation_path(which, x); };
    auto dq_of = [which](auto x) { return transform_path(which, x); };
    check<S>("matrix round trip " + where, x0, [&](auto x) {
      const auto m = q_of(x).to_matrix();
      const auto q = std::remove_cvref_t<decltype(q_of(x))>::from_matrix(m);
      const auto r = q_of(x).canonical();
      return std::array{m(0, 1), m(2, 0), q.w - r.w, q.x - r.x, q.y - r.y, q.z - r.z};
    });
    if (which == 0)  // Euler angles are smooth away from gimbal lock (and wrap at ±π)
      for (const EulerOrder order : {EulerOrder::ZYX, EulerOrder::XYZ, EulerOrder::ZXZ})
        check<S>("to_euler " + std::string(to_string(order)), x0, [&](auto x) {
          const auto e = to_euler(q_of(x), order, EulerFrame::intrinsic).angles;
          return std::array{e.a, e.b, e.c};
        }, 4);
    if (which != 1)  // like the axis-angle, VRML's axis is undefined at the identity
    check<S>("vrml round trip " + where, x0, [&](auto x) {
      using X = decltype(x);
      const auto v = to_vrml(dq_of(x), vec<X>(0.5, 0.25, 0));
      const auto back = from_vrml(v);
      const auto p = back.transform_point(vec<X>(1, 2, 3)) - dq_of(x).transform_point(vec<X>(1, 2, 3));
      return std::array{p.x, p.y, p.z, v.translation.x};
    }, 4);
    check<S>("sqrt " + where, x0, [&](auto x) { return parts(sqrt(dq_of(x))); }, which == 2 ? 64 : 4);
    check<S>("nlerp " + where, x0, [&](auto x) {
      using X = decltype(x);
      return parts(nlerp(rotation<X>(0), q_of(x), c<X>(0.375)));
    });
    check<S>("dib " + where, x0, [&](auto x) {
      using X = decltype(x);
      const std::array<DualQuaternion<X>, 3> qs{transform<X>(0), dq_of(x), transform<X>(1)};
      const std::array<X, 3> w{c<X>(0.25), c<X>(0.5), c<X>(0.25)};
      return parts(dib(qs, w, 60).value);
    }, 16);
    check<S>("average " + where, x0, [&](auto x) {
      using X = decltype(x);
      const std::array<Quaternion<X>, 3> qs{rotation<X>(0), q_of(x), rotation<X>(0) * q_of(x)};
      return parts(average(qs));
    }, 16);
  }
}

// ---- analytic values at the limits ------------------------------------------------------------------

TEST(GenericAnalytic, LogOfExpHasDerivativeXiAtTheIdentity) {
  // d/dε log(exp(εξ)) = ξ at ε = 0, and the second derivative is 0 (the landed code gave 0 and NaN).
  const Vec3<double> xi{0.3, -0.2, 0.7};
  const auto q = log(exp(Quaternion<HyperDual<double>>::pure(Vec3<HyperDual<double>>{xi.x, xi.y, xi.z} * HyperDual<double>::variable(0))));
  for (const auto& [got, want] : {std::pair{q.x, xi.x}, {q.y, xi.y}, {q.z, xi.z}}) {
    EXPECT_EQ(got.e1, want);
    EXPECT_EQ(got.e12, 0.0);
  }
  const DualQuaternion<Dual<double>> screw{Quaternion<Dual<double>>::pure({0.3, -0.2, 0.7}), Quaternion<Dual<double>>::pure({1.0, 2.0, -0.5})};
  const auto l = log(exp(screw * Dual<double>::variable(0)));
  const std::array<double, 8> want{0, 0.3, -0.2, 0.7, 0, 1.0, 2.0, -0.5};
  const auto got = parts(l);
  for (std::size_t i = 0; i < 8; ++i) EXPECT_NEAR(got[i].dual, want[i], 4e-16) << i;
}

TEST(GenericAnalytic, SclerpFromTheIdentityHasTheHalfScrewDerivative) {
  // sclerp(I, exp(εξ), ½) = exp(εξ/2): derivative ξ/2 in the vector parts at ε = 0 (0 before).
  using D = Dual<double>;
  const DualQuaternion<D> xi{Quaternion<D>::pure({0.4, 0.1, -0.3}), Quaternion<D>::pure({-1.0, 0.5, 2.0})};
  const auto s = sclerp(DualQuaternion<D>::identity(), exp(xi * D::variable(0)), D(0.5));
  const std::array<double, 8> want{0, 0.2, 0.05, -0.15, 0, -0.5, 0.25, 1.0};
  const auto got = parts(s);
  for (std::size_t i = 0; i < 8; ++i) EXPECT_NEAR(got[i].dual, want[i], 4e-16) << i;
}

TEST(GenericAnalytic, SecondDerivativeOfExpAtZeroIsTheSquare) {
  // exp(εξ) = 1 + εξ + ε²ξ²/2 + …, and ξ² = −|ξ|² for a pure ξ: the real part's second derivative.
  const Vec3<double> xi{0.3, -0.2, 0.7};
  const HyperDual<double> e = HyperDual<double>::variable(0);
  const auto q = exp(Quaternion<HyperDual<double>>::pure(Vec3<HyperDual<double>>{xi.x, xi.y, xi.z} * e));
  EXPECT_DOUBLE_EQ(q.w.e12, -dot(xi, xi));
  const auto r = Quaternion<HyperDual<double>>::from_rotation_vector(Vec3<HyperDual<double>>{xi.x, xi.y, xi.z} * e);
  EXPECT_DOUBLE_EQ(r.w.e12, -dot(xi, xi) / 4);
}

TEST(GenericAnalytic, RotationsWhoseSquareUnderflows) {
  // 1e-170 rad: θ² = 1e-340 underflows in double. exp/log and the rotation vectors stay exact.
  const Vec3<double> v{1e-170, -2e-170, 3e-170};
  const Quaternion<double> q = Quaternion<double>::from_rotation_vector(v);
  EXPECT_EQ(q.w, 1.0);
  EXPECT_EQ(q.x, 0.5e-170);
  EXPECT_EQ(q.y, -1e-170);
  EXPECT_EQ(q.z, 1.5e-170);
  const Vec3<double> back = q.to_rotation_vector();
  EXPECT_EQ(back.x, v.x);
  EXPECT_EQ(back.y, v.y);
  EXPECT_EQ(back.z, v.z);
  const auto aa = q.to_axis_angle();
  EXPECT_NEAR(aa.angle, std::sqrt(14.0) * 1e-170, 1e-185);
  const DualQuaternion<double> d = DualQuaternion<double>::from_rotation_translation(q, {1, 2, 3});
  const DualQuaternion<double> l = log(d);
  EXPECT_TRUE(std::isfinite(l.dual.x) && std::isfinite(l.real.x));
  EXPECT_EQ(l.real.x, 0.5e-170);
  const DualQuaternion<double> half = sclerp(DualQuaternion<double>::identity(), d, 0.5);
  EXPECT_NEAR(half.translation().y, 1.0, 1e-15);
  EXPECT_EQ(half.real.x, 0.25e-170);
}

TEST(GenericAnalytic, IntegerArgumentsWork) {
  const DualQuaternion<double> a = DualQuaternion<double>::identity();
  const DualQuaternion<double> b = DualQuaternion<double>::from_translation({2, 0, 0});
  EXPECT_EQ(sclerp(a, b, 1).translation().x, 2.0);
  EXPECT_EQ(dlb(a, b, 0), a);
  EXPECT_EQ(slerp(a.real, b.real, 1), b.real);
  EXPECT_EQ(pow(Dual<double>::variable(3), 2).dual, 6.0);
  EXPECT_EQ(pow(HyperDual<double>::variable(3), 2).e12, 2.0);
  EXPECT_EQ(pow(2, Dual<double>::variable(3)).real, 8.0);
  EXPECT_TRUE(approx_equal(pow(b, 2), DualQuaternion<double>::from_translation({4, 0, 0}), 1e-15));
  EXPECT_TRUE(approx_equal(slerp(Quaternion<float>{}, Quaternion<float>(0, 1, 0, 0), 1), Quaternion<float>(0, 1, 0, 0), 1e-7f));
}

}  // namespace

// Interpolation and blending: slerp edge cases, squad, averages, the screw calculus of dual
// quaternions, sclerp against an independent se(3) matrix exponential, dlb and dib.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <limits>
#include <cmath>
#include <vector>

#include "support.hpp"

namespace {

using namespace dq;
using dq::test::max_abs_diff;
using dq::test::Random;
using dq::test::rotation_diff;

constexpr double kPi = pi_v<double>;

// ---- slerp ----------------------------------------------------------------------------------------

/// The textbook formula, valid away from Ω = 0 and Ω = π: an independent reference.
template <class T>
Quaternion<T> textbook_slerp(Quaternion<T> a, Quaternion<T> b, T t) {
  if (dot(a, b) < 0) b = -b;
  const T omega = std::acos(dot(a, b));
  return a * (std::sin((1 - t) * omega) / std::sin(omega)) + b * (std::sin(t * omega) / std::sin(omega));
}

TEST(Slerp, MatchesTheTextbookFormulaAwayFromItsFailureCases) {
  Random rng(201);
  for (int n = 0; n < 2000; ++n) {
    const Quaternion<double> a = rng.rotation<double>(), b = rng.rotation<double>();
    if (std::abs(dot(a, b)) > 0.99) continue;
    const double t = rng.uniform(-0.5, 1.5);
    EXPECT_LE(max_abs_diff(slerp(a, b, t), textbook_slerp(a, b, t)), 1e-13);
  }
}

TEST(Slerp, PlainValuesAgreeWithTheExpLogFormAtEveryAngle) {
  // Plain values on the shortest arc take the weights form (asin, sincos); dual numbers take
  // a · exp(t log(a* b)) with series: two formulas, compared from 1 rad down to 1e-12 rad, where
  // the weights switch to their series. Each is a few roundings from the truth, so they agree to
  // a few ulps (8 ε here). In float, against the textbook weights evaluated in long double (no
  // failure case at these angles in that precision): 8 float ε.
  Random rng(207);
  double worst = 0, worst_float = 0;
  for (int k = 0; k <= 12; ++k) {
    for (int n = 0; n < 200; ++n) {
      const Quaternion<double> a = rng.rotation<double>();
      const Quaternion<double> b = (a * Quaternion<double>::from_axis_angle(normalized(rng.vec3<double>(1)), std::pow(10.0, -k))).normalized();
      const double t = rng.uniform(-0.5, 1.5);
      const Quaternion<double> plain = slerp(a, b, t);
      const Quaternion<Dual<double>> series = slerp(a.cast<Dual<double>>(), b.cast<Dual<double>>(), Dual<double>(t));
      worst = std::max(worst, max_abs_diff(plain, Quaternion<double>(series.w.real, series.x.real, series.y.real, series.z.real)));
      if (k <= 6) {
        const Quaternion<float> af = a.cast<float>(), bf = b.cast<float>();
        const auto reference = textbook_slerp(af.cast<long double>().normalized(), bf.cast<long double>().normalized(), static_cast<long double>(float(t)));
        worst_float = std::max(worst_float, static_cast<double>(max_abs_diff(slerp(af, bf, float(t)).cast<long double>(), reference)));
      }
    }
  }
  EXPECT_LE(worst, 8 * std::numeric_limits<double>::epsilon());
  EXPECT_LE(worst_float, 8 * std::numeric_limits<float>::epsilon());
}

TEST(Slerp, TheThesisFailureCasesGiveUnitResults) {
  const double ulp = std::numeric_limits<double>::epsilon();
  // Equal endpoints: the thesis' example slerp((0,1,0,0), (0,1,0,0), ½) gave a longer vector.
  const Quaternion<double> x(0, 1, 0, 0);
  EXPECT_EQ(slerp(x, x, 0.5), x);
  Random rng(202);
  for (int n = 0; n < 2000; ++n) {
    const Quaternion<double> a = rng.rotation<double>();
    const double t = rng.uniform(-1.0, 2.0);
    // sin Ω ≈ 0: endpoints a few ulps apart; Ω ≈ π: nearly antipodal (the same rotation);
    // drift: endpoints 1e-3 off the unit sphere.
    const Quaternion<double> near = (a + Quaternion<double>(ulp, -ulp, 2 * ulp, 0)).normalized();
    const Quaternion<double> anti = (-a + Quaternion<double>(0, ulp, 0, -ulp)).normalized();
    const Quaternion<double> drifted = rng.rotation<double>() * 1.001;
    for (const auto& b : {a, near, anti, -a, drifted}) {
      for (Path path : {Path::shortest, Path::longest}) {
        const Quaternion<double> s = slerp(a, b, t, path);
        EXPECT_NEAR(s.norm(), 1.0, 4 * ulp);
        EXPECT_FALSE(std::isnan(s.w));
      }
    }
    // Nearly equal: the result stays between (and near) the endpoints.
    EXPECT_LE(rotation_diff(slerp(a, near, 0.5), a), 8 * ulp);
  }
}

TEST(Slerp, ConstantAngularSpeedAndExactEndpoints) {
  Random rng(203);
  for (int n = 0; n < 500; ++n) {
    const Quaternion<double> a = rng.rotation<double>(), b = rng.rotation<double>();
    const double total = angular_distance(a, b);
    EXPECT_LE(max_abs_diff(slerp(a, b, 0.0), a), 2.3e-16);  // 1 ulp
    EXPECT_LE(rotation_diff(slerp(a, b, 1.0), b), 4.5e-16);  // 2 ulps
    for (double t : {0.1, 0.25, 0.5, 0.9}) {
      EXPECT_NEAR(angular_distance(a, slerp(a, b, t)), t * total, 1e-14);
      // The long way: the angles add to 2π.
      EXPECT_NEAR(angular_distance(a, slerp(a, b, t, Path::longest)), std::min(t * (2 * kPi - total), 2 * kPi - t * (2 * kPi - total)), 1e-13);
    }
  }
}

TEST(Slerp, UnitToRoundingKeepsInputsWithin4EpsilonAndNormalizesTheOthers) {
  const float eps = std::numeric_limits<float>::epsilon();
  for (float w : {1.0f, 1.0f + eps, 1.0f - eps / 2}) {  // |q|² − 1 ≈ 0, 2ε, −ε: kept as they are
    const Quaternion<float> q(w, 0, 0, 0);
    EXPECT_EQ(detail::unit_to_rounding(q), q) << w - 1;
  }
  for (float w : {1.0f + 3 * eps, 1.0f - 5 * eps / 2}) {  // |q|² − 1 ≈ 6ε, −5ε: normalized
    const Quaternion<float> q(w, 0, 0, 0), want(1, 0, 0, 0);
    EXPECT_EQ(detail::unit_to_rounding(q), q.normalized()) << w - 1;
    EXPECT_EQ(detail::unit_to_rounding(q), want) << w - 1;
  }
}

// Float slerp runs its quaternion arithmetic in vector lanes (detail::slerp_shortest_lanes) with
// the general path's operations in its order: bit for bit that path's result, on random pairs,
// pairs on opposite hemispheres, nearly equal and exactly equal pairs, drifted inputs (which take
// the general path), for t inside and outside [0, 1]; and the same ambiguity report.
TEST(Slerp, FloatLanesAreTheGeneralPathBitForBit) {
  Random rng(211);
  const Quaternion<float> tiny = Quaternion<float>::from_axis_angle({0.3f, -0.2f, 0.9f}, 1e-5f);
  for (int n = 0; n < 20000; ++n) {
    const Quaternion<float> a = rng.rotation<float>();
    Quaternion<float> b = rng.rotation<float>();
    if (n % 5 == 1) b = a * tiny;
    if (n % 5 == 2) b = -a;
    if (n % 5 == 3) b = a * 1.001f;
    const float t = n % 7 == 0 ? 1.0f : n % 7 == 1 ? 0.0f : static_cast<float>(rng.uniform(-0.5, 1.5));
    const Quaternion<float> ua = detail::unit_to_rounding(a), ub = detail::unit_to_rounding(b);
    InterpolationReport want_report, got_report;
    const Quaternion<float> want = detail::slerp_shortest_values(ua, detail::align_sign(ub, dot(ua, ub), Path::shortest, &want_report), t);
    const Quaternion<float> got = slerp(a, b, t, Path::shortest, &got_report);
    const auto bits = [](const Quaternion<float>& q) {
      return std::array{std::bit_cast<std::uint32_t>(q.w), std::bit_cast<std::uint32_t>(q.x), std::bit_cast<std::uint32_t>(q.y),
                        std::bit_cast<std::uint32_t>(q.z)};
    };
    ASSERT_EQ(bits(got), bits(want)) << n << ": " << got << " against " << want;
    ASSERT_EQ(got_report.ambiguous, want_report.ambiguous) << n;
  }
}

#if DQKIT_VECTOR_EXTENSIONS
// Float slerp's angles come from polynomials evaluated in double (detail::chord_angle,
// detail::sin_to_quarter_turn; coefficients from scripts/fit_slerp_polynomials.py). Against long
// double asin and sin on dense grids over their ranges (and a little past the ends, where rounding
// may put an argument): within 1/64 of a float ulp, so they add nothing visible to float results.
TEST(Slerp, FloatAnglePolynomialsAreFarBelowAFloatUlp) {
  const long double bound = static_cast<long double>(std::numeric_limits<float>::epsilon()) / 64;
  const double chord_top = 2 * std::sin(kPi / 8) * 1.0001, angle_top = kPi / 2 * 1.0001;
  for (int i = 1; i <= 100000; ++i) {
    const double z = chord_top * i / 100000;
    const long double want = 2 * std::asin(static_cast<long double>(z) / 2);
    ASSERT_LE(std::abs((static_cast<long double>(detail::chord_angle(z)) - want) / want), bound) << z;
    const double y = angle_top * i / 100000;
    const detail::double2 got = detail::sin_to_quarter_turn(detail::double2{y, -y});
    const long double sine = std::sin(static_cast<long double>(y));
    ASSERT_LE(std::abs((static_cast<long double>(got[0]) - sine) / sine), bound) << y;
    ASSERT_EQ(got[1], -got[0]) << y;  // odd
  }
}

// The float weights against their formula evaluated in long double with libm, from the same float
// chords z = |a − b| and o = |a + b|: Ω/2 = asin(z/2) or π/4 − asin(r/2) for r = (o − z)/√2,
// whichever argument is smaller, and weights sin((1 − t)Ω), sin(tΩ) times 2/(z o). Each weight is
// the reference faithfully rounded (one of the two floats around it: the double arithmetic and
// the polynomials add under 1/64 ulp), over Ω from 1e-7 to π/2 and t in [−1, 2] (farther out, a
// weight near a zero of its sine is only as accurate as Ω absolutely); also at Ω = π/2 with the
// chords rounded across each other (o < z: a · b ≈ 0), where Ω comes out just above π/2; at t = 0
// exactly (1, 0), and at z = 0, (1 − t, t). (The formula itself is checked against the textbook
// slerp in long double above.)
TEST(Slerp, FloatWeightsAreTheirLongDoubleFormulaRounded) {
  Random rng(212);
  const long double pi = 3.141592653589793238462643383279502884L;
  int nearest = 0;
  const int count = 200000;
  for (int n = 0; n < count; ++n) {
    const long double omega = n % 100 <= 2 ? pi / 2 : std::pow(10.0L, rng.uniform<long double>(-7, std::log10(pi / 2)));
    float z = static_cast<float>(2 * std::sin(omega / 2)), o = static_cast<float>(2 * std::cos(omega / 2));
    if (n % 100 == 1) z = std::nextafter(o, 2.0f);
    if (n % 100 == 2) o = std::nextafter(z, 0.0f);
    const float t = static_cast<float>(n % 10 == 0 ? rng.uniform(-1.0, 2.0) : rng.uniform(0.0, 1.0));
    const long double zl = static_cast<long double>(z), ol = static_cast<long double>(o), r = (ol - zl) / std::sqrt(2.0L);
    const long double angle = zl <= r ? 2 * std::asin(zl / 2) : pi / 2 - 2 * std::asin(r / 2);
    const std::array<long double, 2> want = {std::sin((1 - static_cast<long double>(t)) * angle) * 2 / (zl * ol),
                                             std::sin(static_cast<long double>(t) * angle) * 2 / (zl * ol)};
    const auto [wa, wb] = detail::slerp_weights(z, o, t);
    for (const auto& [got, exact] : {std::pair{wa, want[0]}, std::pair{wb, want[1]}}) {
      const float rounded = static_cast<float>(exact);
      const float other = std::nextafter(rounded, static_cast<long double>(rounded) < exact ? INFINITY : -INFINITY);
      ASSERT_TRUE(got == rounded || got == other) << "Ω " << static_cast<double>(omega) << " t " << t << ": " << got << " against "
                                                  << static_cast<double>(exact);
      nearest += got == rounded;
    }
  }
  RecordProperty("rounded_to_nearest_percent", std::to_string(100.0 * nearest / (2 * count)));
  EXPECT_EQ(detail::slerp_weights(0.7f, 1.8f, 0.0f), (std::pair{1.0f, 0.0f}));
  EXPECT_EQ(detail::slerp_weights(0.0f, 2.0f, 0.25f), (std::pair{0.75f, 0.25f}));
}
#endif

// slerp takes inputs that are unit to rounding (|q|² within 4 ε of 1) as they are and normalizes
// the others: either way the result is the slerp of the normalized inputs, here against long
// double, for inputs exactly unit in long double, rounded to float, and scaled off unit.
TEST(Slerp, InputsUnitToRoundingOrDriftedGiveTheSameRotation) {
  Random rng(204);
  for (int n = 0; n < 2000; ++n) {
    const Quaternion<long double> a = rng.rotation<long double>(), b = rng.rotation<long double>();
    const long double t = rng.uniform<long double>(0, 1);
    const Quaternion<long double> want = slerp(a, b, t);
    for (float scale : {1.0f, 1.0f + 3e-7f, 1.0f - 3e-7f, 1.001f, 0.5f}) {
      const Quaternion<float> fa = (a * static_cast<long double>(scale)).cast<float>(), fb = b.cast<float>();
      const Quaternion<float> got = slerp(fa, fb, static_cast<float>(t));
      // Float inputs are the long-double ones to 1/2 ulp: 8 ulps covers that and the arithmetic.
      ASSERT_LE(max_abs_diff(got.cast<long double>(), want), 8 * std::numeric_limits<float>::epsilon()) << n << " scale " << scale;
      ASSERT_LE(std::abs(static_cast<double>(got.squared_norm()) - 1), 8 * std::numeric_limits<float>::epsilon()) << n;
    }
  }
}

TEST(Slerp, AmbiguousHalfTurnIsReported) {
  const Quaternion<double> a = Quaternion<double>::identity(), b(0, 0, 0, 1);  // π apart
  InterpolationReport report;
  const Quaternion<double> m = slerp(a, b, 0.5, Path::shortest, &report);
  EXPECT_TRUE(report.ambiguous);
  EXPECT_NEAR(angular_distance(a, m), kPi / 2, 1e-15);
  slerp(a, Quaternion<double>(0.6, 0.8, 0, 0), 0.5, Path::shortest, &report);
  EXPECT_FALSE(report.ambiguous);
}

TEST(Nlerp, FollowsTheSameArc) {
  Random rng(204);
  for (int n = 0; n < 500; ++n) {
    const Quaternion<double> a = rng.rotation<double>(), b = rng.rotation<double>();
    const Quaternion<double> m = nlerp(a, b, 0.3);
    EXPECT_NEAR(m.norm(), 1.0, 4e-16);
    EXPECT_NEAR(angular_distance(a, m) + angular_distance(m, b), angular_distance(a, b), 1e-13);
  }
}

TEST(Squad, InterpolatesKeysAndIsSmoothAcrossThem) {
  Random rng(205);
  std::vector<Quaternion<double>> keys;
  for (int i = 0; i < 5; ++i) keys.push_back(rng.rotation<double>());
  for (std::size_t i = 1; i < keys.size(); ++i)
    if (dot(keys[i - 1], keys[i]) < 0) keys[i] = -keys[i];
  auto ctrl = [&](std::size_t i) { return squad_control_point(keys[i - 1], keys[i], keys[i + 1]); };
  // Segments 1→2 and 2→3; velocity on both sides of key 2 must agree (C¹).
  auto seg = [&](std::size_t i, double t) { return squad(keys[i], ctrl(i), ctrl(i + 1), keys[i + 1], t); };
  EXPECT_LE(rotation_diff(seg(1, 0.0), keys[1]), 1e-15);
  EXPECT_LE(rotation_diff(seg(1, 1.0), keys[2]), 1e-15);
  const double h = 1e-6;
  auto velocity = [&](const Quaternion<double>& p, const Quaternion<double>& q) {  // rotation vector per unit t
    Quaternion<double> d = p.conjugate() * q;
    return d.to_rotation_vector() / h;
  };
  const Vec3<double> left = velocity(seg(1, 1.0 - h), seg(1, 1.0));
  const Vec3<double> right = velocity(seg(2, 0.0), seg(2, h));
  EXPECT_LE(max_abs_diff(left, right), 1e-4 * (1 + norm(left)));
}

TEST(Average, EigenvectorMeanProperties) {
  Random rng(206);
  for (int n = 0; n < 200; ++n) {
    const Quaternion<double> center = rng.rotation<double>();
    // Symmetric pairs around the center average to the center, whatever the signs.
    std::vector<Quaternion<double>> qs;
    for (int k = 0; k < 3; ++k) {
      const Quaternion<double> d = Quaternion<double>::from_rotation_vector(rng.vec3<double>(0.5));
      qs.push_back(center * d);
      qs.push_back(-(center * d.conjugate()));
    }
    EXPECT_LE(rotation_diff(average<double>(qs), center), 1e-3);  // chordal mean: close, not exact
    // Two inputs with equal weights: the slerp midpoint, exactly (chordal = geodesic here).
    const Quaternion<double> a = rng.rotation<double>(), b = rng.rotation<double>();
    const std::array<Quaternion<double>, 2> two{a, -b};
    EXPECT_LE(rotation_diff(average<double>(two), slerp(a, b, 0.5)), 1e-12);
    // Weights: all weight on one input returns it.
    const std::array<double, 2> w{0.0, 1.0};
    EXPECT_LE(rotation_diff(average<double>(two, w), b), 1e-12);
  }
}

// ---- the screw calculus -----------------------------------------------------------------------------

DualQuaternion<double> random_screw_edge(Random& rng, int n) {
  switch (n % 5) {
    case 0: return rng.rigid<double>();
    case 1: return DualQuaternion<double>::from_translation(rng.vec3<double>(5));  // pure translation
    case 2:  // near identity
      return DualQuaternion<double>::from_rotation_translation(Quaternion<double>::from_rotation_vector(rng.vec3<double>(1e-9)),
                                                               rng.vec3<double>(5));
    case 3:  // θ = π
      return DualQuaternion<double>::from_rotation_translation(Quaternion<double>::pure(normalized(rng.vec3<double>(1))),
                                                               rng.vec3<double>(5));
    default:  // θ just below π
      return DualQuaternion<double>::from_rotation_translation(
          Quaternion<double>::from_axis_angle(rng.vec3<double>(1), kPi - 1e-9), rng.vec3<double>(5));
  }
}

TEST(ScrewCalculus, ExpOfLogAndLogOfExp) {
  Random rng(211);
  for (int n = 0; n < 5000; ++n) {
    const DualQuaternion<double> q = random_screw_edge(rng, n);
    // Near a 2π turn (w < 0) log is ill-conditioned: its dual part grows like 1/sinc(θ/2), and
    // the round trip's error with it (a few ulps of the largest component of log q).
    const DualQuaternion<double> l = log(q);
    const double scale = std::max({1.0, norm(l.real.vec()), norm(l.dual.vec())});
    EXPECT_TRUE(approx_equal(exp(l), q, 64 * std::numeric_limits<double>::epsilon() * scale)) << n;
    const DualQuaternion<double> c = q.real.w < 0 ? -q : q;
    EXPECT_TRUE(approx_equal(exp(log(c)), c, 1e-13)) << n;
    // log of exp on the principal domain |u| < π.
    const DualQuaternion<double> xi{Quaternion<double>::pure(rng.vec3<double>(1.5)), Quaternion<double>::pure(rng.vec3<double>(3))};
    EXPECT_TRUE(approx_equal(log(exp(xi)), xi, 1e-12)) << n;
  }
  // Pure translation: exactly 1 + ε t/2 ↔ (0, 0) + ε (0, t/2).
  const DualQuaternion<double> tr = DualQuaternion<double>::from_translation({2, 4, 6});
  EXPECT_EQ(log(tr), (DualQuaternion<double>(0, 0, 0, 0, 0, 1, 2, 3)));
  EXPECT_EQ(exp(log(tr)), tr);
}

TEST(ScrewCalculus, SincDerivativeOverXIsAccurateEverywhere) {
  // Reference: the Taylor series in long double with 16 terms (exact to long-double rounding for
  // |a| ≤ 1), against dqkit's double evaluation (series in a² below a = 1, closed form above).
  double worst = 0;
  for (int i = 0; i <= 2000; ++i) {
    const double a = std::pow(10.0, -8.0 + 8.0 * i / 2000.0);  // 1e-8 … 1
    long double ref = 0, term_sign = -1, factorial = 6;  // (2n+1)! for n = 1
    const long double a2 = static_cast<long double>(a) * static_cast<long double>(a);
    long double power = 1;
    for (int n = 1; n <= 16; ++n) {
      ref += term_sign * 2 * n * power / factorial;
      term_sign = -term_sign;
      power *= a2;
      factorial *= (2.0L * n + 2) * (2.0L * n + 3);
    }
    const double got = detail::sinc_derivative_over_angle_of_squared(a * a, [] { return 0.0; });
    worst = std::max(worst, static_cast<double>(std::abs((static_cast<long double>(got) - ref) / ref)));
  }
  EXPECT_LE(worst / std::numeric_limits<double>::epsilon(), 8.0);
  RecordProperty("max_ulps", std::to_string(worst / std::numeric_limits<double>::epsilon()));
}

TEST(ScrewCalculus, LogIsTheHalfScrew) {
  Random rng(212);
  for (int n = 0; n < 2000; ++n) {
    const DualQuaternion<double> q = rng.rigid<double>();
    const Screw<double> s = to_screw(q);
    const DualQuaternion<double> l = log(q.real.w < 0 ? -q : q);
    EXPECT_LE(max_abs_diff(l.real.vec(), s.axis.direction * (s.angle / 2)), 1e-14);
    EXPECT_LE(max_abs_diff(l.dual.vec(), s.axis.moment * (s.angle / 2) + s.axis.direction * (s.translation / 2)), 1e-12);
  }
}

TEST(ScrewCalculus, PowAndSqrt) {
  Random rng(213);
  for (int n = 0; n < 2000; ++n) {
    const DualQuaternion<double> q = random_screw_edge(rng, n);
    const DualQuaternion<double> r = sqrt(q);
    EXPECT_TRUE(approx_equal(r * r, q, 1e-12, SignPolicy::same_rotation)) << n;
    EXPECT_TRUE(r.is_unit(1e-14));
    const DualQuaternion<double> c = q.real.w < 0 ? -q : q;
    EXPECT_TRUE(approx_equal(pow(c, 3.0), c * c * c, 1e-11));
    EXPECT_TRUE(approx_equal(pow(c, -1.0), c.conjugate(), 1e-12));
  }
}

// ---- sclerp -------------------------------------------------------------------------------------------

/// The se(3) twist matrix route, written independently: a · expm(t · logm(a⁻¹ b)) with general
/// 4x4 matrix exp/log (inverse scaling and squaring), as Sophus-style code would do it.
Mat4<double> sclerp_by_matrices(const DualQuaternion<double>& a, const DualQuaternion<double>& b, double t) {
  const Mat4<double> ma = to_mat4(a), rel = to_mat4(a.conjugate() * b);
  const auto l = matrix_log(rel);
  EXPECT_TRUE(l.has_value());
  return ma * matrix_exp(*l * t);
}

TEST(Sclerp, MatchesTheSe3MatrixExponential) {
  Random rng(221);
  for (int n = 0; n < 500; ++n) {
    const DualQuaternion<double> a = rng.rigid<double>(), b = rng.rigid<double>();
    if (angular_distance(a.real, b.real) > 3.0) continue;  // matrix log needs θ < π
    for (double t : {0.0, 0.3, 0.5, 1.0, 1.4}) {
      EXPECT_LE(max_abs_diff(to_mat4(sclerp(a, b, t)), sclerp_by_matrices(a, b, t)), 1e-11) << n << " t=" << t;
    }
  }
}

TEST(Sclerp, IsAScrewMotionAtConstantSpeed) {
  Random rng(222);
  for (int n = 0; n < 1000; ++n) {
    const DualQuaternion<double> a = random_screw_edge(rng, n), b = random_screw_edge(rng, n + 1);
    DualQuaternion<double> rel = a.conjugate() * b;
    if (rel.real.w < 0) rel = -rel;
    const Screw<double> s = to_screw(rel);
    EXPECT_TRUE(approx_equal(sclerp(a, b, 0.0), a, 1e-14));
    EXPECT_TRUE(approx_equal(sclerp(a, b, 1.0), b, 1e-11, SignPolicy::same_rotation));
    for (double t : {0.2, 0.5, 0.8}) {
      const DualQuaternion<double> m = sclerp(a, b, t);
      EXPECT_TRUE(m.is_unit(1e-13));
      // Equal to the screw-parameter construction with θ and d scaled by t.
      const DualQuaternion<double> expected = a * from_screw(Screw<double>{s.axis, s.angle * t, s.translation * t});
      EXPECT_TRUE(approx_equal(m, expected, 1e-10, SignPolicy::same_rotation)) << n;
      // Constant angular and linear speed: the relative screw at t has θ t and d t.
      const Screw<double> st = to_screw(a.conjugate() * m);
      EXPECT_NEAR(st.angle, s.angle * t, 1e-10);
      if (s.angle > 1e-6) {
        EXPECT_NEAR(st.translation, s.translation * t, 1e-9);
      }
    }
  }
}

TEST(Sclerp, EdgeCasesNeverNaN) {
  const DualQuaternion<double> a = DualQuaternion<double>::from_translation({1, 2, 3});
  const DualQuaternion<double> b = DualQuaternion<double>::from_translation({4, 6, 3});
  // Identical rotations: a straight line, exactly.
  const DualQuaternion<double> m = sclerp(a, b, 0.5);
  EXPECT_EQ(m.real, Quaternion<double>::identity());
  EXPECT_LE(max_abs_diff(m.translation(), Vec3<double>{2.5, 4, 3}), 1e-15);
  // Rotations exactly π apart: ambiguous, reported, unit.
  const DualQuaternion<double> c = DualQuaternion<double>::from_rotation_translation(Quaternion<double>(0, 0, 1, 0), {1, 0, 0});
  InterpolationReport report;
  const DualQuaternion<double> h = sclerp(a, c, 0.5, Path::shortest, &report);
  EXPECT_TRUE(report.ambiguous);
  EXPECT_TRUE(h.is_unit(1e-14));
  EXPECT_NEAR(angular_distance(h.real, a.real), kPi / 2, 1e-14);
  // The same input twice, and −b.
  EXPECT_TRUE(approx_equal(sclerp(c, c, 0.7), c, 1e-15));
  EXPECT_TRUE(approx_equal(sclerp(c, -c, 0.7), c, 1e-15, SignPolicy::same_rotation));
  // The long way round turns by 2π − θ.
  const DualQuaternion<double> q = DualQuaternion<double>::from_rotation(Quaternion<double>::from_axis_angle({0, 0, 1}, 1.0));
  EXPECT_NEAR(angular_distance(sclerp(DualQuaternion<double>::identity(), q, 0.5, Path::longest).real, Quaternion<double>::identity()),
              kPi - 0.5, 1e-14);
}

TEST(Sclerp, InputsOffUnitAreTheTransformsTheyStandFor) {
  // Scaled inputs (their real parts' norms off 1) and a dual part with a component along the real
  // part: interpolated as the rigid transforms they normalize to. Reference: sclerp of the unit
  // inputs themselves (for the scaled ones) and the endpoints (for the skewed one). These gave
  // NaN (scale 2, 1.5) or a wrong rotation (0.5, 1.01) before sclerp normalized its inputs.
  Random rng(431);
  for (int n = 0; n < 200; ++n) {
    const DualQuaternion<double> a = rng.rigid<double>(3), b = rng.rigid<double>(3);
    const double t = rng.uniform<double>(-0.5, 1.5);
    const DualQuaternion<double> want = sclerp(a, b, t);
    for (const double scale : {2.0, 1.5, 1.01, 0.5, 1 + 1e-9}) {
      const DualQuaternion<double> got = sclerp(a * scale, b * (1 / scale), t);
      ASSERT_TRUE(got.is_unit(1e-14)) << n << " scale " << scale;
      ASSERT_TRUE(approx_equal(got, want, 1e-12, SignPolicy::same_rotation)) << n << " scale " << scale << " t " << t;
    }
    DualQuaternion<double> skewed = a;
    skewed.dual = skewed.dual + skewed.real * 0.01;  // q_r · q_d = 0.01: not a rigid transform as given
    EXPECT_TRUE(approx_equal(sclerp(skewed, b, 0.0), skewed.normalized(), 1e-14, SignPolicy::same_rotation)) << n;
    EXPECT_TRUE(approx_equal(sclerp(skewed, b, 1.0), b, 1e-13, SignPolicy::same_rotation)) << n;
  }
}

template <class T>
DualQuaternion<Dual<T>> lift(const DualQuaternion<T>& q) {
  auto l = [](const Quaternion<T>& p) { return Quaternion<Dual<T>>(p.w, p.x, p.y, p.z); };
  return {l(q.real), l(q.dual)};
}

TEST(Sclerp, DerivativesOffTheUnitSurfaceAreThoseOfTheNormalizedInput) {
  // a(s) = (1 + s) A with A unit: every a(s) is the transform A, so d/ds sclerp(a(s), B, t) = 0.
  // At s = 0 the value is unit; the derivative points off the unit surface and must still be
  // normalized away (a check of the value alone would keep it and give a non-zero derivative).
  Random rng(229);
  for (int n = 0; n < 100; ++n) {
    const DualQuaternion<double> a = rng.rigid<double>(), b = rng.rigid<double>();
    const auto scaled = [](const Quaternion<double>& q) {
      return Quaternion<Dual<double>>(Dual<double>(q.w, q.w), Dual<double>(q.x, q.x), Dual<double>(q.y, q.y), Dual<double>(q.z, q.z));
    };
    const DualQuaternion<Dual<double>> as{scaled(a.real), scaled(a.dual)};
    const DualQuaternion<Dual<double>> m = sclerp(as, lift(b), Dual<double>(rng.uniform(0.0, 1.0)));
    for (const Dual<double>& c : {m.real.w, m.real.x, m.real.y, m.real.z, m.dual.w, m.dual.x, m.dual.y, m.dual.z})
      EXPECT_NEAR(c.dual, 0.0, 1e-12) << n;
  }
}

TEST(Sclerp, DerivativeInTIsTheScrewVelocity) {
  // d/dt a·exp(tξ) = a·exp(tξ)·ξ with ξ = log(a⁻¹ b), computed by running sclerp over Dual<double>.
  Random rng(223);
  for (int n = 0; n < 500; ++n) {
    const DualQuaternion<double> a = rng.rigid<double>(), b = rng.rigid<double>();
    const double t = rng.uniform(0.0, 1.0);
    const DualQuaternion<Dual<double>> m = sclerp(lift(a), lift(b), Dual<double>::variable(t));
    DualQuaternion<double> rel = a.conjugate() * b;
    if (rel.real.w < 0) rel = -rel;
    const DualQuaternion<double> velocity = sclerp(a, b, t) * log(rel);
    const std::array<Dual<double>, 8> got{m.real.w, m.real.x, m.real.y, m.real.z, m.dual.w, m.dual.x, m.dual.y, m.dual.z};
    const std::array<double, 8> want{velocity.real.w, velocity.real.x, velocity.real.y, velocity.real.z,
                                     velocity.dual.w, velocity.dual.x, velocity.dual.y, velocity.dual.z};
    for (std::size_t i = 0; i < 8; ++i) EXPECT_NEAR(got[i].dual, want[i], 1e-11) << n << " component " << i;
  }
}

// ---- blending ---------------------------------------------------------------------------------------

TEST(Dlb, CloseToSclerpForTwoInputs) {
  // Documented bound (docs/interpolation.md): for rotations up to 90° apart and translations up
  // to 2, |dlb − sclerp| ≤ 0.02 in the 8 components (max-norm). Measured: see the docs.
  Random rng(231);
  double worst = 0;
  for (int n = 0; n < 2000; ++n) {
    const DualQuaternion<double> a = rng.rigid<double>(1);
    DualQuaternion<double> b = a * DualQuaternion<double>::from_rotation_translation(
                                       Quaternion<double>::from_axis_angle(rng.vec3<double>(1), rng.uniform(0.0, kPi / 2)),
                                       rng.vec3<double>(1));
    const double t = rng.uniform(0.0, 1.0);
    const std::array<DualQuaternion<double>, 2> qs{a, b};
    const std::array<double, 2> w{1 - t, t};
    const DualQuaternion<double> blend = dlb<double>(qs, w);
    EXPECT_TRUE(blend.is_unit(1e-14));
    worst = std::max(worst, max_abs_diff(blend, sclerp(a, b, t)));
  }
  EXPECT_LE(worst, 0.02);
  RecordProperty("dlb_vs_sclerp_max", std::to_string(worst));
}

TEST(Blending, InvariantUnderACommonRigidChangeOfCoordinates) {
  Random rng(232);
  for (int n = 0; n < 300; ++n) {
    // Clustered inputs, as the bones influencing one vertex are: within about ±60° of a centre.
    const DualQuaternion<double> centre = rng.rigid<double>(2);
    std::vector<DualQuaternion<double>> qs;
    std::vector<double> w;
    for (int k = 0; k < 4; ++k) {
      qs.push_back(centre * DualQuaternion<double>::from_rotation_translation(
                                Quaternion<double>::from_rotation_vector(rng.vec3<double>(0.6)), rng.vec3<double>(1)));
      w.push_back(rng.uniform(0.0, 1.0));
    }
    const DualQuaternion<double> c = rng.rigid<double>(3);
    std::vector<DualQuaternion<double>> left, right;
    for (const auto& q : qs) {
      left.push_back(c * q);
      right.push_back(q * c);
    }
    const DualQuaternion<double> base = dlb<double>(qs, w);
    EXPECT_TRUE(approx_equal(dlb<double>(left, w), c * base, 1e-12, SignPolicy::same_rotation));
    EXPECT_TRUE(approx_equal(dlb<double>(right, w), base * c, 1e-12, SignPolicy::same_rotation));
    const IterativeBlend<double> d = dib<double>(qs, w);
    EXPECT_TRUE(d.converged) << d.residual << " after " << d.iterations;
    EXPECT_TRUE(d.value.is_unit(1e-13));
    EXPECT_TRUE(approx_equal(dib<double>(left, w).value, c * d.value, 1e-10, SignPolicy::same_rotation));
    EXPECT_TRUE(approx_equal(dib<double>(right, w).value, d.value * c, 1e-10, SignPolicy::same_rotation));
  }
}

TEST(Blending, SignPolicyIsRelativeToThePivotNotTheOrder) {
  Random rng(233);
  std::vector<DualQuaternion<double>> qs{rng.rigid<double>(), rng.rigid<double>(), rng.rigid<double>()};
  const std::vector<double> w{0.5, 0.3, 0.2};
  qs[1] = -qs[1];  // the same transform with the other sign
  const DualQuaternion<double> a = dlb<double>(qs, w);
  const std::vector<DualQuaternion<double>> rev{qs[2], qs[1], qs[0]};
  const std::vector<double> wrev{0.2, 0.3, 0.5};
  EXPECT_TRUE(approx_equal(dlb<double>(rev, wrev), a, 1e-14, SignPolicy::same_rotation));
  EXPECT_EQ(dlb<double>({}, {}), DualQuaternion<double>::identity());
}

TEST(Dib, TwoInputsLandOnTheSclerp) {
  Random rng(234);
  for (int n = 0; n < 300; ++n) {
    const DualQuaternion<double> a = rng.rigid<double>(), b = rng.rigid<double>();
    const double t = rng.uniform(0.0, 1.0);
    const std::array<DualQuaternion<double>, 2> qs{a, b};
    const std::array<double, 2> w{1 - t, t};
    const IterativeBlend<double> r = dib<double>(qs, w, 50);
    if (angular_distance(a.real, b.real) > 2.5) continue;
    EXPECT_TRUE(r.converged) << r.residual;
    EXPECT_TRUE(approx_equal(r.value, sclerp(a, b, t), 1e-10, SignPolicy::same_rotation)) << n;
  }
}

TEST(Decoupled, RotationBySlerpTranslationByLine) {
  Random rng(235);
  const DualQuaternion<double> a = rng.rigid<double>(), b = rng.rigid<double>();
  const DualQuaternion<double> m = decoupled_interpolate(a, b, 0.25);
  EXPECT_LE(max_abs_diff(m.real, slerp(a.real, b.real, 0.25)), 1e-15);
  EXPECT_LE(max_abs_diff(m.translation(), a.translation() * 0.75 + b.translation() * 0.25), 1e-13);
}

TEST(Alexa, MatrixLogExpAndInterpolation) {
  Random rng(236);
  for (int n = 0; n < 200; ++n) {
    const DualQuaternion<double> a = rng.rigid<double>(), b = rng.rigid<double>();
    const Mat4<double> ma = to_mat4(a), mb = to_mat4(b);
    const auto la = matrix_log(ma);
    ASSERT_TRUE(la.has_value());
    EXPECT_LE(max_abs_diff(matrix_exp(*la), ma), 1e-11);
    EXPECT_LE(max_abs_diff(*alexa_interpolate(ma, mb, 0.0), ma), 1e-11);
    EXPECT_LE(max_abs_diff(*alexa_interpolate(ma, mb, 1.0), mb), 1e-11);
    // Commuting inputs (rotations about one axis through the origin, translations along it):
    // Alexa's operator equals the screw interpolation.
    const Vec3<double> axis = normalized(rng.vec3<double>(1));
    const auto s1 = from_screw(Screw<double>{{axis, {}}, 0.4, 1.0}), s2 = from_screw(Screw<double>{{axis, {}}, 1.9, -2.0});
    EXPECT_LE(max_abs_diff(*alexa_interpolate(to_mat4(s1), to_mat4(s2), 0.3), to_mat4(sclerp(s1, s2, 0.3))), 1e-11);
  }
  // A half turn has no principal real logarithm: reported, not garbage.
  EXPECT_FALSE(matrix_log(to_mat4(DualQuaternion<double>::from_rotation(Quaternion<double>(0, 1, 0, 0)))).has_value());
}

// ---- gimbal lock ----------------------------------------------------------------------------------

TEST(GimbalLock, EulerLosesADegreeOfFreedomQuaternionsDoNot) {
  // Jacobian of the rotation (as a rotation vector of R₀⁻¹R) with respect to the three
  // parameters, by forward-mode dual numbers: rank 2 at Euler's singularity, 3 for a rotation
  // vector parameterization at the same rotation.
  using D = Dual<double>;
  const double a = 0.3, b = kPi / 2, c = -0.2;
  const Quaternion<double> q0 = from_euler(EulerOrder::XYZ, EulerFrame::intrinsic, a, b, c);
  auto column = [&](int k) {
    std::array<D, 3> p{D(a), D(b), D(c)};
    p[static_cast<std::size_t>(k)].dual = 1;
    const Quaternion<D> q = from_euler(EulerOrder::XYZ, EulerFrame::intrinsic, p[0], p[1], p[2]);
    const Quaternion<D> rel = Quaternion<D>(q0.w, -q0.x, -q0.y, -q0.z) * q;
    return Vec3<double>{2 * rel.x.dual, 2 * rel.y.dual, 2 * rel.z.dual};  // d(rotation vector) at 0
  };
  const Vec3<double> ja = column(0), jb = column(1), jc = column(2);
  const double det_euler = dot(ja, cross(jb, jc));
  EXPECT_NEAR(det_euler, 0.0, 1e-15);                 // rank-deficient: a and c do the same thing
  EXPECT_NEAR(norm(cross(ja, jc)), 0.0, 1e-15);
  // Rotation vector perturbations r₀ ∘ exp(δ): the identity Jacobian, determinant 1.
  auto rv_column = [&](int k) {
    Vec3<D> d{D(0), D(0), D(0)};
    d[k].dual = 1;
    const Quaternion<D> rel = Quaternion<D>::from_rotation_vector(d);
    return Vec3<double>{2 * rel.x.dual, 2 * rel.y.dual, 2 * rel.z.dual};
  };
  EXPECT_NEAR(dot(rv_column(0), cross(rv_column(1), rv_column(2))), 1.0, 1e-15);
}

}  // namespace

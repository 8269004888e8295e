// Interpolating and averaging rotations: slerp, nlerp, squad and the weighted average of N.
//
// slerp is written as a · exp(t · log(a* b)) with sinc-type series, not with the textbook weights
// sin((1−t)Ω)/sin Ω, so it has none of the failure cases the Arends thesis found: equal endpoints
// (Ω = 0), sin Ω ≈ 0, and Ω ≈ π all give a unit result that is continuous in t.
#pragma once

#include <array>
#include <utility>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <ranges>
#include <span>
#include <type_traits>

#include "dq/core/quaternion.hpp"
#include "dq/core/series.hpp"
#include "dq/util/assert.hpp"

namespace dq {

/// Which of the two arcs between q and ±q' to follow.
enum class Path {
  shortest,  ///< the rotation by at most π (the usual choice)
  longest,   ///< the other way round (rotation angle 2π minus the shortest)
};

/// Optional report of a choice an interpolation had to make.
struct InterpolationReport {
  bool ambiguous = false;  ///< the endpoints are exactly π apart: both arcs are equally short
};

namespace detail {
/// b or −b, so that a and the result are on the requested arc; reports the tie at dot = 0.
template <class Q, class T>
Q align_sign(const Q& b, const T& d, Path path, InterpolationReport* report) {
  if (report) report->ambiguous = d == T(0);
  const bool flip = path == Path::shortest ? d < T(0) : d > T(0);
  return flip ? -b : b;
}

/// Whether a quaternion with this |q|² is unit to rounding: within 4 ε of 1, where normalizing
/// would move each component by at most 2 ε relative, a few ulps.
template <class T>
bool is_unit_to_rounding(const T& squared_norm) {
  using std::abs;
  return abs(squared_norm - T(1)) <= T(4) * std::numeric_limits<T>::epsilon();
}
/// q itself if it is unit to rounding, else q.normalized(). For plain values: it saves slerp a
/// square root and a division per input on its latency path (with normalized() inlining its common
/// path: 28 → 22 ns per float slerp), with no effect beyond rounding.
template <class T>
Quaternion<T> unit_to_rounding(const Quaternion<T>& q) {
  if (is_unit_to_rounding(q.squared_norm())) [[likely]]
    return q;
  return q.normalized();
}

/// The slerp weights (of a and of b) for unit a, b with a · b ≥ 0 from the chords |a − b| and
/// |a + b|: the angle Ω between them is at most π/2 and Ω = 2 asin(|a − b|/2), accurate at every
/// angle. The weights sin((1−t)Ω)/sin Ω and sin(tΩ)/sin Ω come from the sincos of tΩ and the two
/// chords; for Ω² below √ε from their series t (1 + (1 − t²) Ω²/6), so nothing divides by a
/// vanishing sine. Float has its own overload below.
template <class T>
std::pair<T, T> slerp_weights(const T& chord, const T& opposite, const T& t) {
  using std::asin;
  using std::cos;
  using std::min;
  using std::sin;
  const T omega = T(2) * asin(min(chord / T(2), T(1)));
  if (omega * omega < square_root_epsilon<real_t<T>>) {
    const T s = T(1) - t, w2 = omega * omega / T(6);
    return {s * (T(1) + (T(1) - s * s) * w2), t * (T(1) + (T(1) - t * t) * w2)};
  }
  // sin((1−t)Ω) = sin Ω cos tΩ − cos Ω sin tΩ, with sin Ω = 2 sin(Ω/2) cos(Ω/2) and cos Ω =
  // cos²(Ω/2) − sin²(Ω/2) from the chords (|a − b| = 2 sin(Ω/2), |a + b| = 2 cos(Ω/2)).
  const T sin_omega = chord * opposite / T(2), cos_omega = (opposite * opposite - chord * chord) / T(4);
  const T wb = sin(t * omega) / sin_omega;
  return {cos(t * omega) - cos_omega * wb, wb};
}

#if DQKIT_VECTOR_EXTENSIONS
using double2 = double __attribute__((vector_size(16)));

// Float slerp's angles in double by polynomials, instead of libm's asinf and sincosf (two calls that
// ran one after the other, with the values live across them spilled: about 12 ns of the 20 a float
// slerp took, docs/performance.md).
// The coefficients are least-squares fits at Chebyshev nodes (scripts/fit_slerp_polynomials.py);
// each function's relative error, below 6e-10, is under 1/200 of a float ulp, so the float weights
// round as if from the exact functions to within that (tests/test_interp.cpp checks 1/64).

/// sin y for |y| ≤ π/2, in each lane: y + y³ q(y²) with q of degree 4.
inline double2 sin_to_quarter_turn(double2 y) {
  const double2 y2 = y * y, y4 = y2 * y2;  // Estrin's scheme: a shorter dependency chain than Horner's
  const double2 q = (y2 * 0.008333332769589823 - 0.16666666663888038) +
                    y4 * ((y2 * 2.7536473361991798e-06 - 0.00019841086721745886) + y4 * -2.4080377023410074e-08);
  return y + y * y2 * q;
}
/// The angle 2 asin(z/2) subtended by a chord z of the unit circle, for 0 ≤ z ≤ 2 sin(π/8):
/// z + z³ p(z²), p the fit of (asin x − x)/x³ in x² = z²/4 with its coefficients scaled by powers of 4 (exact).
inline double chord_angle(double z) {
  const double z2 = z * z, z4 = z2 * z2;
  const double p = (z2 * (0.07499891627147982 / 16) + 0.16666666988439566 / 4) +
                   z4 * ((z2 * (0.029309131048651255 / 256) + 0.04470087269875102 / 64) + z4 * (0.03020548129463721 / 1024));
  return z + z * z2 * p;
}

/// slerp_weights for float (preferred to the template for float arguments), from both chords (|a − b| = 2 sin(Ω/2) and |a + b| = 2 cos(Ω/2)), in
/// double. Ω/2 ≤ π/4 is asin of the smaller of sin(Ω/2) and sin(π/4 − Ω/2) = (cos(Ω/2) − sin(Ω/2))/√2,
/// both at most sin(π/8), picked without a branch (random pairs would mispredict it); sin Ω =
/// |a − b| |a + b| / 2 from the chords (their product exact in double), so no division waits for
/// the angle. Where rounding puts |a + b| below |a − b| (a · b ≈ 0), sin(π/4 − Ω/2) is negative and
/// Ω just above π/2. At t = 0
/// the weights are (1, 0) exactly (as t = 1 returns b); at Ω = 0, (1 − t, t).
inline std::pair<float, float> slerp_weights(float chord, float opposite_chord, float t) {
  if (t == 0.0f) return {1.0f, 0.0f};
  if (chord == 0.0f) return {1.0f - t, t};
  const double z = static_cast<double>(chord), rest = (static_cast<double>(opposite_chord) - z) * 0.70710678118654752440;  // 2 sin(π/4 − Ω/2)
  const double angle = chord_angle(std::min(z, rest));
  const double far = static_cast<double>(z > rest);                    // 1: Ω = π/2 − 2 asin(rest/2)
  const double omega = angle * (1 - 2 * far) + std::numbers::pi / 2 * far;  // the sign flip is exact
  const double inverse_sine = 2 / (z * double(opposite_chord));
  const double2 angles = double2{1.0 - double(t), double(t)} * omega;
  double2 sines;
  if (t > 0.0f && t < 1.0f) [[likely]] {
    sines = sin_to_quarter_turn(angles);
  } else {  // extrapolating: angles beyond [0, π/2]
    sines = double2{std::sin(angles[0]), std::sin(angles[1])};
  }
  const double2 w = sines * inverse_sine;
  return {static_cast<float>(w[0]), static_cast<float>(w[1])};
}
#endif

/// slerp on the shortest arc for plain values (no derivative parts), faster than the exp/log
/// form (slerp_weights): a and b unit with a · b ≥ 0.
template <class T>
Quaternion<T> slerp_shortest_values(const Quaternion<T>& a, const Quaternion<T>& b, const T& t) {
  using std::sqrt;
  // The endpoint exactly, unless a is NaN: NaN in, NaN out (a needs no test at t = 0: its
  // weights are then 1 and 0, and b's NaN reaches the sum).
  if (t == T(1)) return dot(a, a) == dot(a, a) ? b : a;
  const Quaternion<T> difference = a - b;
  const auto [wa, wb] = slerp_weights(sqrt(dot(difference, difference)), sqrt(dot(a + b, a + b)), t);
  return a * wa + b * wb;
}

#if DQKIT_VECTOR_EXTENSIONS
/// slerp on the shortest arc for float inputs that are unit to rounding (nothing where one is not:
/// the general path normalizes it first), with the quaternion arithmetic
/// in the lanes of one vector: |a|², |b|², |a − b|², |a + b|² from one transpose, a · b, and the
/// weighted sum, with the same operations in the same order as the general path (sums of squares
/// left to right, as dot), so bit for bit its result; the weights are slerp_weights'.
inline std::optional<Quaternion<float>> slerp_shortest_lanes(const Quaternion<float>& a, const Quaternion<float>& b, float t,
                                                             InterpolationReport* report) {
  using std::sqrt;
  const float4 va = to_lanes(a), vb = to_lanes(b);
  const float4 d = va - vb, s = va + vb, p0 = va * va, p1 = vb * vb, p2 = d * d, p3 = s * s;
  // Transposed, lane k holds the four squares of p_k, summed w, x, y, z in order: (|a|², |b|², |a − b|², |a + b|²).
  const float4 t0 = __builtin_shufflevector(p0, p1, 0, 4, 1, 5), t1 = __builtin_shufflevector(p0, p1, 2, 6, 3, 7);
  const float4 t2 = __builtin_shufflevector(p2, p3, 0, 4, 1, 5), t3 = __builtin_shufflevector(p2, p3, 2, 6, 3, 7);
  const float4 squares = ((__builtin_shufflevector(t0, t2, 0, 1, 4, 5) + __builtin_shufflevector(t0, t2, 2, 3, 6, 7)) +
                          __builtin_shufflevector(t1, t3, 0, 1, 4, 5)) +
                         __builtin_shufflevector(t1, t3, 2, 3, 6, 7);
  if (!is_unit_to_rounding(squares[0]) || !is_unit_to_rounding(squares[1])) return std::nullopt;
  const float4 ab = va * vb;
  const float d_ab = ((ab[0] + ab[1]) + ab[2]) + ab[3];
  if (report) report->ambiguous = d_ab == 0.0f;
  const bool flip = d_ab < 0.0f;  // then b is −b: its chords swap
  if (t == 1.0f) return flip ? -b : b;
  const float minus = sqrt(squares[2]), plus = sqrt(squares[3]);
  const auto [wa, wb] = slerp_weights(flip ? plus : minus, flip ? minus : plus, t);
  return from_lanes(va * wa + vb * (flip ? -wb : wb));
}
#endif
}  // namespace detail

/// Spherical linear interpolation between rotations a (t = 0) and b (t = 1), at constant angular
/// speed. Inputs are normalized first (drift is tolerated; inputs unit to rounding are taken as
/// they are, detail::unit_to_rounding); t outside [0, 1] extrapolates along
/// the same great circle. When the endpoints are exactly π apart (ambiguous), the arc of b as
/// given is followed and `report->ambiguous` is set; the longest path between equal rotations
/// (a full turn) turns about x. The endpoints are reproduced to an ulp or two.
///
/// Written as a · exp(t · log(a* b)) with the series of core/series.hpp (derivatives right
/// everywhere), and for plain values on the shortest arc with the weights of
/// detail::slerp_shortest_values: neither divides by a vanishing sine, so none of the failure
/// cases the Arends thesis found (equal endpoints, sin Ω ≈ 0, Ω ≈ π) occurs.
template <class T>
Quaternion<T> slerp(const Quaternion<T>& a, const Quaternion<T>& b, const std::type_identity_t<T>& t,
                    Path path = Path::shortest, InterpolationReport* report = nullptr) {
  if constexpr (!has_derivatives_v<T>) {
    if (path == Path::shortest) {
#if DQKIT_VECTOR_EXTENSIONS
      if constexpr (std::is_same_v<T, float>) {
        if (const auto q = detail::slerp_shortest_lanes(a, b, t, report)) return *q;
      }
#endif
      const Quaternion<T> ua = detail::unit_to_rounding(a), ub = detail::unit_to_rounding(b);
      return detail::slerp_shortest_values(ua, detail::align_sign(ub, dot(ua, ub), path, report), t);
    }
  }
  const Quaternion<T> qa = a.normalized();
  const Quaternion<T> r = (qa.conjugate() * detail::align_sign(b, dot(qa, b), path, report)).normalized();
  return qa * detail::exp_pure(detail::log_unit_vector(r) * t);
}

/// Normalized linear interpolation: cheaper than slerp, same path, non-constant speed.
template <class T>
Quaternion<T> nlerp(const Quaternion<T>& a, const Quaternion<T>& b, const std::type_identity_t<T>& t,
                    Path path = Path::shortest) {
  const Quaternion<T> qb = detail::align_sign(b, dot(a, b), path, nullptr);
  return (a * (T(1) - t) + qb * t).normalized();
}

/// The inner control point s_i of squad at key q with neighbours prev and next (Shoemake):
/// s_i = q exp(−(log(q⁻¹ next) + log(q⁻¹ prev))/4), with neighbours sign-aligned to q.
template <class T>
Quaternion<T> squad_control_point(const Quaternion<T>& prev, const Quaternion<T>& q, const Quaternion<T>& next) {
  const Quaternion<T> p = dot(prev, q) < T(0) ? -prev : prev;
  const Quaternion<T> n = dot(next, q) < T(0) ? -next : next;
  const Quaternion<T> qi = q.conjugate();
  return (q * exp((log(qi * n) + log(qi * p)) * T(-0.25))).normalized();
}

/// Spherical cubic interpolation between keys q1 (t = 0) and q2 (t = 1) with control points
/// s1, s2 (from squad_control_point): slerp(slerp(q1, q2, t), slerp(s1, s2, t), 2t(1−t)).
/// C¹-continuous across keys when the control points come from the neighbours.
template <class T>
Quaternion<T> squad(const Quaternion<T>& q1, const Quaternion<T>& s1, const Quaternion<T>& s2, const Quaternion<T>& q2,
                    const std::type_identity_t<T>& t) {
  const Quaternion<T> q2a = dot(q1, q2) < T(0) ? -q2 : q2;
  const Quaternion<T> s2a = dot(s1, s2) < T(0) ? -s2 : s2;
  return slerp(slerp(q1, q2a, t), slerp(s1, s2a, t), T(2) * t * (T(1) - t), Path::shortest);
}

namespace detail {
/// Eigenvector of the largest eigenvalue of a symmetric 4x4 matrix, by cyclic Jacobi rotations
/// (no allocation, converges for every symmetric input).
template <class T>
std::array<T, 4> dominant_eigenvector(std::array<std::array<T, 4>, 4> m) {
  using std::abs;
  using std::sqrt;
  std::array<std::array<T, 4>, 4> v{};
  for (int i = 0; i < 4; ++i) v[static_cast<std::size_t>(i)][static_cast<std::size_t>(i)] = T(1);
  for (int sweep = 0; sweep < 64; ++sweep) {
    T off = T(0);
    for (std::size_t p = 0; p < 4; ++p)
      for (std::size_t q = p + 1; q < 4; ++q) off += m[p][q] * m[p][q];
    if (value_of(off) == 0) break;
    for (std::size_t p = 0; p < 4; ++p)
      for (std::size_t q = p + 1; q < 4; ++q) {
        if (value_of(m[p][q]) == 0) continue;
        const T theta = (m[q][q] - m[p][p]) / (T(2) * m[p][q]);
        const T sign = theta < T(0) ? T(-1) : T(1);
        const T tt = sign / (abs(theta) + sqrt(theta * theta + T(1)));
        const T c = T(1) / sqrt(tt * tt + T(1)), s = tt * c;
        for (std::size_t k = 0; k < 4; ++k) {  // rotate columns p, q
          const T mkp = m[k][p], mkq = m[k][q];
          m[k][p] = c * mkp - s * mkq;
          m[k][q] = s * mkp + c * mkq;
        }
        for (std::size_t k = 0; k < 4; ++k) {  // rotate rows p, q
          const T mpk = m[p][k], mqk = m[q][k];
          m[p][k] = c * mpk - s * mqk;
          m[q][k] = s * mpk + c * mqk;
        }
        for (std::size_t k = 0; k < 4; ++k) {
          const T vkp = v[k][p], vkq = v[k][q];
          v[k][p] = c * vkp - s * vkq;
          v[k][q] = s * vkp + c * vkq;
        }
      }
  }
  std::size_t best = 0;
  for (std::size_t i = 1; i < 4; ++i)
    if (m[i][i] > m[best][best]) best = i;
  return {v[0][best], v[1][best], v[2][best], v[3][best]};
}

/// Newton steps on the eigenpair equations ((M − λI) v = 0, v·v = 1) from an eigenvector v of
/// M's largest eigenvalue. Jacobi rotations do not carry derivative parts (Dual, HyperDual)
/// through (their angles divide by vanishing off-diagonals); from the converged value, each
/// Newton step makes one more order of derivatives exact (two steps: first and second). Skipped where the largest
/// eigenvalue is not simple (the Jacobian is singular: the average is not unique there).
template <class T>
std::array<T, 4> refine_eigenvector(const std::array<std::array<T, 4>, 4>& m, std::array<T, 4> v) {
  using std::abs;
  for (int step = 0; step < 2; ++step) {
    T lambda = T(0);
    for (std::size_t r = 0; r < 4; ++r)
      for (std::size_t k = 0; k < 4; ++k) lambda += v[r] * m[r][k] * v[k];
    // J δ = −F with J = [[M − λI, −v], [−vᵀ, 0]], F = ((M − λI) v, (1 − v·v)/2).
    std::array<std::array<T, 6>, 5> a{};
    for (std::size_t r = 0; r < 4; ++r) {
      T f = T(0);
      for (std::size_t k = 0; k < 4; ++k) {
        a[r][k] = m[r][k] - (r == k ? lambda : T(0));
        f += a[r][k] * v[k];
      }
      a[r][4] = -v[r];
      a[r][5] = -f;
      a[4][r] = -v[r];
    }
    a[4][5] = -(T(1) - (v[0] * v[0] + v[1] * v[1] + v[2] * v[2] + v[3] * v[3])) / T(2);
    for (std::size_t c = 0; c < 5; ++c) {  // Gaussian elimination, partial pivoting on values
      std::size_t piv = c;
      for (std::size_t r = c + 1; r < 5; ++r)
        if (abs(value_of(a[r][c])) > abs(value_of(a[piv][c]))) piv = r;
      if (!(abs(value_of(a[piv][c])) > real_t<T>(1e-6))) return v;  // not a simple eigenvalue
      std::swap(a[c], a[piv]);
      for (std::size_t r = c + 1; r < 5; ++r) {
        const T factor = a[r][c] / a[c][c];
        for (std::size_t k = c; k < 6; ++k) a[r][k] -= factor * a[c][k];
      }
    }
    std::array<T, 5> delta{};
    for (std::size_t r = 5; r-- > 0;) {
      T sum = a[r][5];
      for (std::size_t k = r + 1; k < 5; ++k) sum -= a[r][k] * delta[k];
      delta[r] = sum / a[r][r];
    }
    for (std::size_t r = 0; r < 4; ++r) v[r] += delta[r];
  }
  return v;
}
}  // namespace detail

/// The weighted average rotation (Markley et al.): the unit q maximizing Σ wᵢ (q · qᵢ)², i.e. the
/// dominant eigenvector of Σ wᵢ qᵢ qᵢᵀ. Insensitive to the signs of the inputs. Weights must be
/// non-negative; `weights` empty means equal weights. Returns the canonical sign (w ≥ 0). With
/// no input, the identity.
template <class T>
Quaternion<T> average(std::span<const Quaternion<T>> rotations, std::span<const T> weights = {}) {
  DQ_PRECONDITION(weights.empty() || weights.size() == rotations.size(),
                  "average needs no weights or one weight per rotation",
                  Quaternion<T>(T(std::numeric_limits<real_t<T>>::quiet_NaN()), T(0), T(0), T(0)));
  std::array<std::array<T, 4>, 4> m{};
  for (std::size_t i = 0; i < rotations.size(); ++i) {
    const T w = weights.empty() ? T(1) : weights[i];
    const Quaternion<T>& q = rotations[i];
    const std::array<T, 4> c{q.w, q.x, q.y, q.z};
    for (std::size_t r = 0; r < 4; ++r)
      for (std::size_t k = 0; k < 4; ++k) m[r][k] += w * c[r] * c[k];
  }
  if (rotations.empty()) return Quaternion<T>::identity();
  // Jacobi on the values, then Newton in T for the derivative parts (refine_eigenvector).
  std::array<std::array<real_t<T>, 4>, 4> values{};
  for (std::size_t r = 0; r < 4; ++r)
    for (std::size_t k = 0; k < 4; ++k) values[r][k] = value_of(m[r][k]);
  const auto ev = detail::dominant_eigenvector(values);
  const auto e = detail::refine_eigenvector(m, std::array<T, 4>{T(ev[0]), T(ev[1]), T(ev[2]), T(ev[3])});
  return Quaternion<T>(e[0], e[1], e[2], e[3]).normalized().canonical();
}

/// average over any contiguous containers, the scalar type taken from the elements.
template <std::ranges::contiguous_range Qs>
  requires detail::is_quaternion_v<std::ranges::range_value_t<Qs>>
auto average(const Qs& rotations) {
  using T = typename std::ranges::range_value_t<Qs>::scalar_type;
  return average(std::span<const Quaternion<T>>(rotations));
}
template <std::ranges::contiguous_range Qs, std::ranges::contiguous_range Ws>
  requires detail::is_quaternion_v<std::ranges::range_value_t<Qs>>
auto average(const Qs& rotations, const Ws& weights) {
  using T = typename std::ranges::range_value_t<Qs>::scalar_type;
  return average(std::span<const Quaternion<T>>(rotations), std::span<const T>(weights));
}

}  // namespace dq

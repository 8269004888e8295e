// The smooth functions behind exp, log, slerp and sclerp, written as functions of the squared
// angle so that values, first and second derivatives are right at, near and far from 0.
//
// cos(θ), sin(θ)/θ and (θ cos θ − sin θ)/θ³ are even: as functions of x = θ² they are entire, and
// a power series in x has the right value and the right derivatives at x = 0 for every scalar
// (Dual, HyperDual). Written through θ = √x instead, the derivative of √x at 0 is infinite (a
// HyperDual gives NaN) and a constant branch at θ = 0 gives derivative 0. Working in θ² also means
// that an angle whose square underflows (1e-170 rad in double) takes the series, whose value at
// x = 0 is exact, instead of dividing by zero.
//
// Each series is summed to the precision of its real type: the number of terms is chosen at
// compile time so that the first omitted term, and its second derivative, are below epsilon
// where the series is used. Beyond that, the closed forms take over where they no longer cancel.
//
// Plain values (float, double, long double) need no derivatives: for them cos and sinc take the
// closed forms (faster than the long series), with two-term series only where θ⁴ is below ε, and
// atan2(s, w)/s likewise; the result is as accurate either way.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <limits>

#include "dq/core/scalar.hpp"

namespace dq::detail {

/// Coefficients c_k of a series Σ c_k x^k, k < N, computed at compile time in the real type R.
template <class R, std::size_t N, class Coefficient>
constexpr std::array<R, N> series_coefficients(Coefficient c) {
  std::array<R, N> out{};
  for (std::size_t k = 0; k < N; ++k) out[k] = c(k);
  return out;
}

/// Σ c_k x^k by Horner's rule (x is a scalar of any kind; the coefficients are plain reals).
template <class T, class R, std::size_t N>
T horner(const T& x, const std::array<R, N>& c) {
  T acc = T(c[N - 1]);
  for (std::size_t k = N - 1; k-- > 0;) acc = acc * x + T(c[k]);
  return acc;
}

/// The number of terms for a series in x ≤ bound whose k-th coefficient is at most
/// `magnitude(k)`: the first omitted term, times (2k)² for the second derivative in θ, is
/// below ε/16.
template <class R, class Magnitude>
constexpr std::size_t series_terms(R bound, Magnitude magnitude) {
  const R eps = std::numeric_limits<R>::epsilon();
  for (std::size_t k = 1; k < 64; ++k) {
    R term = magnitude(k);
    for (std::size_t i = 0; i < k; ++i) term *= bound;
    if (term * R(4 * k * k) < eps / 16) return k;
  }
  return 64;
}

/// 1/n! in R, at compile time.
template <class R>
constexpr R inverse_factorial(std::size_t n) {
  R r = 1;
  for (std::size_t i = 2; i <= n; ++i) r /= R(i);
  return r;
}

/// The even functions of θ below are taken from their series for θ² < 1, and from their closed
/// forms above (where the closed forms of sinc and of (θ cos θ − sin θ)/θ³ lose at most a few
/// bits, and so do their derivatives).
template <class R>
inline constexpr R even_series_bound = R(1);

template <class R>
inline constexpr std::size_t cos_terms = series_terms<R>(even_series_bound<R>, [](std::size_t k) { return inverse_factorial<R>(2 * k); });
template <class R>
inline constexpr std::size_t sinc_terms =
    series_terms<R>(even_series_bound<R>, [](std::size_t k) { return inverse_factorial<R>(2 * k + 1); });
template <class R>
inline constexpr std::size_t sinc_derivative_terms =
    series_terms<R>(even_series_bound<R>, [](std::size_t k) { return R(2 * k + 2) * inverse_factorial<R>(2 * k + 3); });

/// √ε: below it, two terms of a series in θ² are exact to the last bit.
template <class R>
inline constexpr R square_root_epsilon = constexpr_sqrt(std::numeric_limits<R>::epsilon());

/// θ from θ²: √(θ²), or, where θ² overflowed, `fallback()` (a hypot-based norm).
template <class T, class Fallback>
T angle_from_squared(const T& x, Fallback fallback) {
  using std::sqrt;
  if (value_of(x) <= std::numeric_limits<real_t<T>>::max()) return sqrt(x);
  return fallback();
}

/// cos θ as a function of x = θ².
template <class T, class Fallback>
T cos_of_squared(const T& x, Fallback fallback) {
  using R = real_t<T>;
  using std::cos;
  static constexpr auto c = series_coefficients<R, cos_terms<R>>([](std::size_t k) {
    return (k % 2 ? R(-1) : R(1)) * inverse_factorial<R>(2 * k);
  });
  if constexpr (has_derivatives_v<T>)
    if (value_of(x) < even_series_bound<R>) return horner(x, c);
  return cos(angle_from_squared(x, fallback));  // √0 = 0 and cos 0 = 1: exact at the limit too
}

/// sin θ / θ as a function of x = θ².
template <class T, class Fallback>
T sinc_of_squared(const T& x, Fallback fallback) {
  using R = real_t<T>;
  using std::sin;
  static constexpr auto c = series_coefficients<R, sinc_terms<R>>([](std::size_t k) {
    return (k % 2 ? R(-1) : R(1)) * inverse_factorial<R>(2 * k + 1);
  });
  if constexpr (has_derivatives_v<T>) {
    if (value_of(x) < even_series_bound<R>) return horner(x, c);
  } else if (x < square_root_epsilon<R>) {
    return T(1) - x / T(6);  // omitted x²/120 < ε/120
  }
  const T theta = angle_from_squared(x, fallback);
  return sin(theta) / theta;
}

/// (θ cos θ − sin θ)/θ³ = sinc'(θ)/θ as a function of x = θ² (the dual-part coefficient of the
/// screw exp and log). Its closed form cancels badly near 0 (the numerator is ≈ −θ³/3).
template <class T, class Fallback>
T sinc_derivative_over_angle_of_squared(const T& x, Fallback fallback) {
  using R = real_t<T>;
  using std::cos;
  using std::sin;
  static constexpr auto c = series_coefficients<R, sinc_derivative_terms<R>>([](std::size_t k) {
    return (k % 2 ? R(1) : R(-1)) * R(2 * k + 2) * inverse_factorial<R>(2 * k + 3);
  });
  if (value_of(x) < even_series_bound<R>) return horner(x, c);
  const T theta = angle_from_squared(x, fallback);
  return (theta * cos(theta) - sin(theta)) / (theta * theta * theta);
}

/// (1 − sinc θ)/θ² = (θ − sin θ)/θ³ as a function of x = θ² (the second coefficient of the
/// left Jacobian of SO(3)); its closed form cancels near 0 (the numerator is ≈ θ³/6).
template <class T, class Fallback>
T one_minus_sinc_over_squared(const T& x, Fallback fallback) {
  using R = real_t<T>;
  using std::sin;
  static constexpr std::size_t n =
      series_terms<R>(even_series_bound<R>, [](std::size_t k) { return inverse_factorial<R>(2 * k + 3); });
  static constexpr auto c = series_coefficients<R, n>([](std::size_t k) {
    return (k % 2 ? R(-1) : R(1)) * inverse_factorial<R>(2 * k + 3);
  });
  if (value_of(x) < even_series_bound<R>) return horner(x, c);
  const T theta = angle_from_squared(x, fallback);
  return (theta - sin(theta)) / (theta * x);
}

/// atan(z)/z as a function of y = z² for y < 1/16 (slow-converging, so only used there).
template <class T>
T atan_over_argument_of_squared(const T& y) {
  using R = real_t<T>;
  static constexpr std::size_t n = series_terms<R>(R(1) / 16, [](std::size_t k) { return R(1) / R(2 * k + 1); });
  static constexpr auto c = series_coefficients<R, n>([](std::size_t k) { return (k % 2 ? R(-1) : R(1)) / R(2 * k + 1); });
  return horner(y, c);
}

/// Ω/s with Ω = atan2(s, w), for a unit quaternion (w, v) with s = |v|: the factor that turns
/// the vector part into its logarithm. Near the identity (w > 0, s ≤ w/4) a series in s²/w²,
/// smooth through s = 0 with the right derivatives, and 1/w exactly when s² underflowed;
/// elsewhere the closed form (for plain values, asin or acos, whichever is well conditioned: both
/// cheaper than atan2). s = 0 with w < 0 (a turn by 2π) has no finite value: callers handle it
/// first. `norm` gives s without squaring (for s² outside the normal range).
template <class T, class Norm>
T angle_over_sine(const T& s2, const T& w, Norm norm) {
  using R = real_t<T>;
  using std::sqrt;
  if (value_of(w) > R(0)) {
    const T y = s2 / (w * w);
    if constexpr (has_derivatives_v<T>) {
      if (value_of(y) < R(1) / 16) return atan_over_argument_of_squared(y) / w;
    } else if (y < square_root_epsilon<R>) {
      return (T(1) - y / T(3)) / w;  // omitted y²/5 < ε/5
    }
  }
  const R v = value_of(s2);
  const T s = v >= std::numeric_limits<R>::min() && v <= std::numeric_limits<R>::max() ? sqrt(s2) : norm();
  if constexpr (!has_derivatives_v<T>) {
    using std::abs;
    using std::acos;
    using std::asin;
    if (abs(w) >= s) return (w < T(0) ? pi_v<T> - asin(s) : asin(s)) / s;
    return acos(w) / s;
  } else {
    using std::atan2;
    return atan2(s, w) / s;
  }
}

}  // namespace dq::detail

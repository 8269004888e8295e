// Dual numbers a + εb with ε² = 0, ε ≠ 0.
//
// Besides being the coefficients of dual quaternions and dual angles, a dual number is a
// forward-mode derivative: for any analytic f, f(a + εb) = f(a) + ε b f'(a). Every function below
// implements that rule, so generic code run with Dual<T> returns exact first derivatives, and
// Dual<Dual<T>> returns second derivatives (Kenwright, §5.2).
//
// Comparisons (<, ==, ...) compare the real parts only, as autodiff scalars do, so that code
// branching on a value takes the same branch for the derivative.
#pragma once

#include <algorithm>
#include <cmath>
#include <ostream>
#include <type_traits>

#include "dq/core/scalar.hpp"

namespace dq {

template <class T>
struct Dual {
  T real{};  ///< the value a
  T dual{};  ///< the coefficient b of ε (the derivative when used for differentiation)

  constexpr Dual() noexcept = default;
  constexpr Dual(const T& a) noexcept : real(a) {}  // NOLINT: implicit from a scalar, like T
  constexpr Dual(const T& a, const T& b) noexcept : real(a), dual(b) {}

  /// A variable for differentiation: x + ε·1.
  static constexpr Dual variable(const T& x) noexcept { return {x, T(1)}; }

  constexpr Dual& operator+=(const Dual& o) noexcept { real += o.real; dual += o.dual; return *this; }
  constexpr Dual& operator-=(const Dual& o) noexcept { real -= o.real; dual -= o.dual; return *this; }
  constexpr Dual& operator*=(const Dual& o) noexcept { return *this = *this * o; }
  constexpr Dual& operator/=(const Dual& o) noexcept { return *this = *this / o; }

  friend constexpr Dual operator+(const Dual& x) noexcept { return x; }
  friend constexpr Dual operator-(const Dual& x) noexcept { return {-x.real, -x.dual}; }
  friend constexpr Dual operator+(const Dual& x, const Dual& y) noexcept { return {x.real + y.real, x.dual + y.dual}; }
  friend constexpr Dual operator-(const Dual& x, const Dual& y) noexcept { return {x.real - y.real, x.dual - y.dual}; }
  friend constexpr Dual operator*(const Dual& x, const Dual& y) noexcept {
    return {x.real * y.real, x.real * y.dual + x.dual * y.real};
  }
  /// (a + εb)/(c + εd) = a/c + ε (b c − a d)/c²; undefined (inf/NaN) for c = 0, as for reals.
  friend constexpr Dual operator/(const Dual& x, const Dual& y) noexcept {
    const T q = x.real / y.real;
    return {q, (x.dual - q * y.dual) / y.real};
  }
  friend constexpr Dual operator+(const Dual& x, const T& s) noexcept { return {x.real + s, x.dual}; }
  friend constexpr Dual operator+(const T& s, const Dual& x) noexcept { return {s + x.real, x.dual}; }
  friend constexpr Dual operator-(const Dual& x, const T& s) noexcept { return {x.real - s, x.dual}; }
  friend constexpr Dual operator-(const T& s, const Dual& x) noexcept { return {s - x.real, -x.dual}; }
  friend constexpr Dual operator*(const Dual& x, const T& s) noexcept { return {x.real * s, x.dual * s}; }
  friend constexpr Dual operator*(const T& s, const Dual& x) noexcept { return {s * x.real, s * x.dual}; }
  friend constexpr Dual operator/(const Dual& x, const T& s) noexcept { return {x.real / s, x.dual / s}; }
  friend constexpr Dual operator/(const T& s, const Dual& x) noexcept { return Dual(s) / x; }

  friend constexpr bool operator==(const Dual& x, const Dual& y) noexcept { return x.real == y.real; }
  friend constexpr bool operator<(const Dual& x, const Dual& y) noexcept { return x.real < y.real; }
  friend constexpr bool operator>(const Dual& x, const Dual& y) noexcept { return x.real > y.real; }
  friend constexpr bool operator<=(const Dual& x, const Dual& y) noexcept { return x.real <= y.real; }
  friend constexpr bool operator>=(const Dual& x, const Dual& y) noexcept { return x.real >= y.real; }

  /// The conjugate a − εb.
  constexpr Dual conjugate() const noexcept { return {real, -dual}; }

  friend std::ostream& operator<<(std::ostream& os, const Dual& x) {
    return os << '(' << x.real << " + ε" << x.dual << ')';
  }
};

template <class T>
struct scalar_traits<Dual<T>> {
  using real_type = real_t<T>;
  static constexpr real_type value(const Dual<T>& x) noexcept { return value_of(x.real); }
  static constexpr bool has_derivatives = true;
  static constexpr real_type largest_part(const Dual<T>& x) noexcept {
    const real_type a = dq::largest_part(x.real), b = dq::largest_part(x.dual);
    return a < b ? b : a;
  }
};

// ---- elementary functions: f(a + εb) = f(a) + ε b f'(a) ------------------------------------
// `using std::f` lets the same body serve T = float/double and nested dual scalars (ADL).

/// √x. The derivative part is 0 when b = 0 (so √0 of a constant is 0, not NaN); otherwise
/// b/(2√a), which is infinite at a = 0 as for reals.
template <class T>
Dual<T> sqrt(const Dual<T>& x) {
  using std::sqrt;
  const T s = sqrt(x.real);
  if (x.dual == T(0)) return {s, T(0)};
  return {s, x.dual / (T(2) * s)};
}
template <class T>
Dual<T> cbrt(const Dual<T>& x) {
  using std::cbrt;
  const T c = cbrt(x.real);
  if (x.dual == T(0)) return {c, T(0)};
  return {c, x.dual / (T(3) * c * c)};
}
template <class T>
Dual<T> exp(const Dual<T>& x) {
  using std::exp;
  const T e = exp(x.real);
  return {e, x.dual * e};
}
template <class T>
Dual<T> expm1(const Dual<T>& x) {
  using std::exp;
  using std::expm1;
  return {expm1(x.real), x.dual * exp(x.real)};
}
template <class T>
Dual<T> log(const Dual<T>& x) {
  using std::log;
  return {log(x.real), x.dual / x.real};
}
template <class T>
Dual<T> log1p(const Dual<T>& x) {
  using std::log1p;
  return {log1p(x.real), x.dual / (T(1) + x.real)};
}
/// x^p for a constant exponent p.
template <class T>
Dual<T> pow(const Dual<T>& x, const std::type_identity_t<T>& p) {
  using std::pow;
  if (p == T(0)) return {T(1), T(0)};
  return {pow(x.real, p), x.dual * p * pow(x.real, p - T(1))};
}
/// s^y for a constant base s > 0.
template <class T>
Dual<T> pow(const std::type_identity_t<T>& s, const Dual<T>& y) {
  using std::log;
  using std::pow;
  const T v = pow(s, y.real);
  return {v, y.dual * v * log(s)};
}
/// x^y with both varying: d(x^y) = x^y (y' ln x + y x'/x). Requires x > 0 where y varies.
template <class T>
Dual<T> pow(const Dual<T>& x, const Dual<T>& y) {
  using std::log;
  using std::pow;
  const T v = pow(x.real, y.real);
  T d = y.real * pow(x.real, y.real - T(1)) * x.dual;
  if (y.dual != T(0)) d += v * log(x.real) * y.dual;
  return {v, d};
}
template <class T>
Dual<T> sin(const Dual<T>& x) {
  using std::cos;
  using std::sin;
  return {sin(x.real), x.dual * cos(x.real)};
}
template <class T>
Dual<T> cos(const Dual<T>& x) {
  using std::cos;
  using std::sin;
  return {cos(x.real), -x.dual * sin(x.real)};
}
template <class T>
Dual<T> tan(const Dual<T>& x) {
  using std::tan;
  const T t = tan(x.real);
  return {t, x.dual * (T(1) + t * t)};
}
template <class T>
Dual<T> asin(const Dual<T>& x) {
  using std::asin;
  using std::sqrt;
  return {asin(x.real), x.dual / sqrt(T(1) - x.real * x.real)};
}
template <class T>
Dual<T> acos(const Dual<T>& x) {
  using std::acos;
  using std::sqrt;
  return {acos(x.real), -x.dual / sqrt(T(1) - x.real * x.real)};
}
template <class T>
Dual<T> atan(const Dual<T>& x) {
  using std::atan;
  return {atan(x.real), x.dual / (T(1) + x.real * x.real)};
}
/// atan2(y, x): derivative (x y' − y x')/(x² + y²).
template <class T>
Dual<T> atan2(const Dual<T>& y, const Dual<T>& x) {
  using std::atan2;
  const T r2 = x.real * x.real + y.real * y.real;
  if (y.dual == T(0) && x.dual == T(0)) return {atan2(y.real, x.real), T(0)};
  return {atan2(y.real, x.real), (x.real * y.dual - y.real * x.dual) / r2};
}
template <class T>
Dual<T> sinh(const Dual<T>& x) {
  using std::cosh;
  using std::sinh;
  return {sinh(x.real), x.dual * cosh(x.real)};
}
template <class T>
Dual<T> cosh(const Dual<T>& x) {
  using std::cosh;
  using std::sinh;
  return {cosh(x.real), x.dual * sinh(x.real)};
}
template <class T>
Dual<T> tanh(const Dual<T>& x) {
  using std::tanh;
  const T t = tanh(x.real);
  return {t, x.dual * (T(1) - t * t)};
}
template <class T>
Dual<T> asinh(const Dual<T>& x) {
  using std::asinh;
  using std::sqrt;
  return {asinh(x.real), x.dual / sqrt(x.real * x.real + T(1))};
}
template <class T>
Dual<T> acosh(const Dual<T>& x) {
  using std::acosh;
  using std::sqrt;
  return {acosh(x.real), x.dual / sqrt(x.real * x.real - T(1))};
}
template <class T>
Dual<T> atanh(const Dual<T>& x) {
  using std::atanh;
  return {atanh(x.real), x.dual / (T(1) - x.real * x.real)};
}
/// hypot(x, y) without overflow; derivative (x x' + y y')/h, 0 where both derivative parts are 0.
/// At the origin the derivative is the one-sided one, |(x', y')| (as for abs).
template <class T>
Dual<T> hypot(const Dual<T>& x, const Dual<T>& y) {
  using std::hypot;
  const T h = hypot(x.real, y.real);
  if (x.dual == T(0) && y.dual == T(0)) return {h, T(0)};
  if (h == T(0)) return {h, hypot(x.dual, y.dual)};
  return {h, (x.real * x.dual + y.real * y.dual) / h};
}
/// |x|; at a = 0 the one-sided derivative of the sign of b is taken (|0 + εb| = ε|b|).
template <class T>
Dual<T> abs(const Dual<T>& x) {
  if (x.real < T(0)) return -x;
  if (T(0) < x.real) return x;
  return {x.real, x.dual < T(0) ? -x.dual : x.dual};
}
template <class T>
Dual<T> fabs(const Dual<T>& x) {
  return abs(x);
}
template <class T>
Dual<T> min(const Dual<T>& x, const Dual<T>& y) {
  return y < x ? y : x;
}
template <class T>
Dual<T> max(const Dual<T>& x, const Dual<T>& y) {
  return x < y ? y : x;
}
// Step functions: piecewise constant, derivative 0 where defined.
template <class T>
Dual<T> floor(const Dual<T>& x) {
  using std::floor;
  return {floor(x.real), T(0)};
}
template <class T>
Dual<T> ceil(const Dual<T>& x) {
  using std::ceil;
  return {ceil(x.real), T(0)};
}
template <class T>
Dual<T> round(const Dual<T>& x) {
  using std::round;
  return {round(x.real), T(0)};
}
template <class T>
Dual<T> trunc(const Dual<T>& x) {
  using std::trunc;
  return {trunc(x.real), T(0)};
}
/// fmod(x, y) = x − n y with n = trunc(x/y) held constant.
template <class T>
Dual<T> fmod(const Dual<T>& x, const Dual<T>& y) {
  using std::fmod;
  using std::trunc;
  const T n = trunc(x.real / y.real);
  return {fmod(x.real, y.real), x.dual - n * y.dual};
}
template <class T>
bool isfinite(const Dual<T>& x) {
  using std::isfinite;
  return isfinite(x.real) && isfinite(x.dual);
}
template <class T>
bool isnan(const Dual<T>& x) {
  using std::isnan;
  return isnan(x.real) || isnan(x.dual);
}

/// d/dx f at x, computed by forward mode: f(x + ε).dual.
template <class T, class F>
T derivative(F&& f, const T& x) {
  return f(Dual<T>::variable(x)).dual;
}

}  // namespace dq

// Hyper-dual numbers (Fike and Alonso): a + b ε1 + c ε2 + d ε1ε2, with ε1² = ε2² = 0, ε1ε2 ≠ 0.
//
// For analytic f:  f(x) = f(a) + b f'(a) ε1 + c f'(a) ε2 + (d f'(a) + b c f''(a)) ε1ε2.
// Seeding x = a + ε1 + ε2 gives f'(a) in e1 and f''(a) in e12 exactly, with no step size; seeding
// two variables with ε1 and ε2 gives a mixed second derivative (a Hessian entry).
// Comparisons compare the real parts only (see dual.hpp).
#pragma once

#include <cmath>
#include <ostream>
#include <type_traits>

#include "dq/core/scalar.hpp"

namespace dq {

template <class T>
struct HyperDual {
  T real{};  ///< a
  T e1{};    ///< b, coefficient of ε1
  T e2{};    ///< c, coefficient of ε2
  T e12{};   ///< d, coefficient of ε1ε2

  constexpr HyperDual() noexcept = default;
  constexpr HyperDual(const T& a) noexcept : real(a) {}  // NOLINT: implicit from a scalar
  constexpr HyperDual(const T& a, const T& b, const T& c, const T& d) noexcept
      : real(a), e1(b), e2(c), e12(d) {}

  /// x + ε1 + ε2: f(variable(x)) holds f'(x) in e1 (and e2) and f''(x) in e12.
  static constexpr HyperDual variable(const T& x) noexcept { return {x, T(1), T(1), T(0)}; }

  /// Applies f with value f0 = f(a), first derivative f1 = f'(a), second f2 = f''(a).
  constexpr HyperDual chain(const T& f0, const T& f1, const T& f2) const noexcept {
    return {f0, e1 * f1, e2 * f1, e12 * f1 + e1 * e2 * f2};
  }

  constexpr HyperDual& operator+=(const HyperDual& o) noexcept { return *this = *this + o; }
  constexpr HyperDual& operator-=(const HyperDual& o) noexcept { return *this = *this - o; }
  constexpr HyperDual& operator*=(const HyperDual& o) noexcept { return *this = *this * o; }
  constexpr HyperDual& operator/=(const HyperDual& o) noexcept { return *this = *this / o; }

  friend constexpr HyperDual operator+(const HyperDual& x) noexcept { return x; }
  friend constexpr HyperDual operator-(const HyperDual& x) noexcept { return {-x.real, -x.e1, -x.e2, -x.e12}; }
  friend constexpr HyperDual operator+(const HyperDual& x, const HyperDual& y) noexcept {
    return {x.real + y.real, x.e1 + y.e1, x.e2 + y.e2, x.e12 + y.e12};
  }
  friend constexpr HyperDual operator-(const HyperDual& x, const HyperDual& y) noexcept {
    return {x.real - y.real, x.e1 - y.e1, x.e2 - y.e2, x.e12 - y.e12};
  }
  friend constexpr HyperDual operator*(const HyperDual& x, const HyperDual& y) noexcept {
    return {x.real * y.real, x.real * y.e1 + x.e1 * y.real, x.real * y.e2 + x.e2 * y.real,
            x.real * y.e12 + x.e1 * y.e2 + x.e2 * y.e1 + x.e12 * y.real};
  }
  /// The inverse of the Arends thesis (§5.1): 1/a − b/a² ε1 − c/a² ε2 + (2bc/a³ − d/a²) ε1ε2.
  constexpr HyperDual inverse() const noexcept {
    const T inv = T(1) / real;
    const T inv2 = inv * inv;
    return {inv, -e1 * inv2, -e2 * inv2, T(2) * e1 * e2 * inv2 * inv - e12 * inv2};
  }
  friend constexpr HyperDual operator/(const HyperDual& x, const HyperDual& y) noexcept { return x * y.inverse(); }
  friend constexpr HyperDual operator+(const HyperDual& x, const T& s) noexcept { return {x.real + s, x.e1, x.e2, x.e12}; }
  friend constexpr HyperDual operator+(const T& s, const HyperDual& x) noexcept { return x + s; }
  friend constexpr HyperDual operator-(const HyperDual& x, const T& s) noexcept { return {x.real - s, x.e1, x.e2, x.e12}; }
  friend constexpr HyperDual operator-(const T& s, const HyperDual& x) noexcept { return -(x - s); }
  friend constexpr HyperDual operator*(const HyperDual& x, const T& s) noexcept {
    return {x.real * s, x.e1 * s, x.e2 * s, x.e12 * s};
  }
  friend constexpr HyperDual operator*(const T& s, const HyperDual& x) noexcept { return x * s; }
  friend constexpr HyperDual operator/(const HyperDual& x, const T& s) noexcept {
    return {x.real / s, x.e1 / s, x.e2 / s, x.e12 / s};
  }
  friend constexpr HyperDual operator/(const T& s, const HyperDual& x) noexcept { return x.inverse() * s; }

  friend constexpr bool operator==(const HyperDual& x, const HyperDual& y) noexcept { return x.real == y.real; }
  friend constexpr bool operator<(const HyperDual& x, const HyperDual& y) noexcept { return x.real < y.real; }
  friend constexpr bool operator>(const HyperDual& x, const HyperDual& y) noexcept { return x.real > y.real; }
  friend constexpr bool operator<=(const HyperDual& x, const HyperDual& y) noexcept { return x.real <= y.real; }
  friend constexpr bool operator>=(const HyperDual& x, const HyperDual& y) noexcept { return x.real >= y.real; }

  friend std::ostream& operator<<(std::ostream& os, const HyperDual& x) {
    return os << '(' << x.real << " + ε1 " << x.e1 << " + ε2 " << x.e2 << " + ε1ε2 " << x.e12 << ')';
  }
};

template <class T>
struct scalar_traits<HyperDual<T>> {
  using real_type = real_t<T>;
  static constexpr real_type value(const HyperDual<T>& x) noexcept { return value_of(x.real); }
  static constexpr bool has_derivatives = true;
  static constexpr real_type largest_part(const HyperDual<T>& x) noexcept {
    real_type m = dq::largest_part(x.real);
    for (const T* p : {&x.e1, &x.e2, &x.e12}) m = m < dq::largest_part(*p) ? dq::largest_part(*p) : m;
    return m;
  }
};

// ---- elementary functions through chain(f, f', f'') ------------------------------------------
// Where a function's derivative is singular (√ at 0), derivative parts that are 0 stay 0.

template <class T>
HyperDual<T> sqrt(const HyperDual<T>& x) {
  using std::sqrt;
  const T s = sqrt(x.real);
  if (x.e1 == T(0) && x.e2 == T(0) && x.e12 == T(0)) return {s, T(0), T(0), T(0)};
  const T d1 = T(0.5) / s;
  return x.chain(s, d1, -d1 / (T(2) * x.real));
}
template <class T>
HyperDual<T> cbrt(const HyperDual<T>& x) {
  using std::cbrt;
  const T c = cbrt(x.real);
  if (x.e1 == T(0) && x.e2 == T(0) && x.e12 == T(0)) return {c, T(0), T(0), T(0)};
  const T d1 = T(1) / (T(3) * c * c);
  return x.chain(c, d1, T(-2) * d1 / (T(3) * x.real));
}
template <class T>
HyperDual<T> exp(const HyperDual<T>& x) {
  using std::exp;
  const T e = exp(x.real);
  return x.chain(e, e, e);
}
template <class T>
HyperDual<T> expm1(const HyperDual<T>& x) {
  using std::exp;
  using std::expm1;
  const T e = exp(x.real);
  return x.chain(expm1(x.real), e, e);
}
template <class T>
HyperDual<T> log(const HyperDual<T>& x) {
  using std::log;
  const T inv = T(1) / x.real;
  return x.chain(log(x.real), inv, -inv * inv);
}
template <class T>
HyperDual<T> log1p(const HyperDual<T>& x) {
  using std::log1p;
  const T inv = T(1) / (T(1) + x.real);
  return x.chain(log1p(x.real), inv, -inv * inv);
}
template <class T>
HyperDual<T> pow(const HyperDual<T>& x, const std::type_identity_t<T>& p) {
  using std::pow;
  if (p == T(0)) return HyperDual<T>(T(1));
  return x.chain(pow(x.real, p), p * pow(x.real, p - T(1)), p * (p - T(1)) * pow(x.real, p - T(2)));
}
/// x^y = exp(y log x) for x > 0; both may vary.
template <class T>
HyperDual<T> pow(const HyperDual<T>& x, const HyperDual<T>& y) {
  return exp(y * log(x));
}
template <class T>
HyperDual<T> pow(const std::type_identity_t<T>& s, const HyperDual<T>& y) {
  using std::log;
  return exp(y * log(s));
}
template <class T>
HyperDual<T> sin(const HyperDual<T>& x) {
  using std::cos;
  using std::sin;
  const T s = sin(x.real);
  return x.chain(s, cos(x.real), -s);
}
template <class T>
HyperDual<T> cos(const HyperDual<T>& x) {
  using std::cos;
  using std::sin;
  const T c = cos(x.real);
  return x.chain(c, -sin(x.real), -c);
}
template <class T>
HyperDual<T> tan(const HyperDual<T>& x) {
  using std::tan;
  const T t = tan(x.real);
  const T d1 = T(1) + t * t;
  return x.chain(t, d1, T(2) * t * d1);
}
template <class T>
HyperDual<T> asin(const HyperDual<T>& x) {
  using std::asin;
  using std::sqrt;
  const T r = T(1) / sqrt(T(1) - x.real * x.real);
  return x.chain(asin(x.real), r, x.real * r * r * r);
}
template <class T>
HyperDual<T> acos(const HyperDual<T>& x) {
  using std::acos;
  using std::sqrt;
  const T r = T(1) / sqrt(T(1) - x.real * x.real);
  return x.chain(acos(x.real), -r, -x.real * r * r * r);
}
template <class T>
HyperDual<T> atan(const HyperDual<T>& x) {
  using std::atan;
  const T r = T(1) / (T(1) + x.real * x.real);
  return x.chain(atan(x.real), r, T(-2) * x.real * r * r);
}
/// atan2(y, x) with both varying: built from the first- and second-order partials of atan2.
template <class T>
HyperDual<T> atan2(const HyperDual<T>& y, const HyperDual<T>& x) {
  using std::atan2;
  const T r2 = x.real * x.real + y.real * y.real;
  const T fy = x.real / r2, fx = -y.real / r2;                  // ∂/∂y, ∂/∂x
  const T fyy = T(-2) * x.real * y.real / (r2 * r2);            // ∂²/∂y²
  const T fxx = -fyy;                                           // ∂²/∂x²
  const T fxy = (y.real * y.real - x.real * x.real) / (r2 * r2);  // ∂²/∂x∂y
  const T v = atan2(y.real, x.real);
  if (r2 == T(0)) return HyperDual<T>(v);
  return {v, fy * y.e1 + fx * x.e1, fy * y.e2 + fx * x.e2,
          fy * y.e12 + fx * x.e12 + fyy * y.e1 * y.e2 + fxx * x.e1 * x.e2 +
              fxy * (x.e1 * y.e2 + y.e1 * x.e2)};
}
template <class T>
HyperDual<T> sinh(const HyperDual<T>& x) {
  using std::cosh;
  using std::sinh;
  const T s = sinh(x.real);
  return x.chain(s, cosh(x.real), s);
}
template <class T>
HyperDual<T> cosh(const HyperDual<T>& x) {
  using std::cosh;
  using std::sinh;
  const T c = cosh(x.real);
  return x.chain(c, sinh(x.real), c);
}
template <class T>
HyperDual<T> tanh(const HyperDual<T>& x) {
  using std::tanh;
  const T t = tanh(x.real);
  const T d1 = T(1) - t * t;
  return x.chain(t, d1, T(-2) * t * d1);
}
template <class T>
HyperDual<T> asinh(const HyperDual<T>& x) {
  using std::asinh;
  using std::sqrt;
  const T r = T(1) / sqrt(x.real * x.real + T(1));
  return x.chain(asinh(x.real), r, -x.real * r * r * r);
}
template <class T>
HyperDual<T> acosh(const HyperDual<T>& x) {
  using std::acosh;
  using std::sqrt;
  const T r = T(1) / sqrt(x.real * x.real - T(1));
  return x.chain(acosh(x.real), r, -x.real * r * r * r);
}
template <class T>
HyperDual<T> atanh(const HyperDual<T>& x) {
  using std::atanh;
  const T r = T(1) / (T(1) - x.real * x.real);
  return x.chain(atanh(x.real), r, T(2) * x.real * r * r);
}
/// hypot(x, y) = √(x² + y²) without overflow in the value.
template <class T>
HyperDual<T> hypot(const HyperDual<T>& x, const HyperDual<T>& y) {
  using std::hypot;
  const T h = hypot(x.real, y.real);
  if (h == T(0)) return HyperDual<T>(h);
  const T s = T(1) / h;
  const HyperDual<T> xs = x * s, ys = y * s;  // scaled so that the square cannot overflow
  return sqrt(xs * xs + ys * ys) * h;
}
template <class T>
HyperDual<T> abs(const HyperDual<T>& x) {
  return x.real < T(0) ? -x : x;
}
template <class T>
HyperDual<T> fabs(const HyperDual<T>& x) {
  return abs(x);
}
template <class T>
HyperDual<T> min(const HyperDual<T>& x, const HyperDual<T>& y) {
  return y < x ? y : x;
}
template <class T>
HyperDual<T> max(const HyperDual<T>& x, const HyperDual<T>& y) {
  return x < y ? y : x;
}
template <class T>
HyperDual<T> floor(const HyperDual<T>& x) {
  using std::floor;
  return HyperDual<T>(floor(x.real));
}
template <class T>
HyperDual<T> ceil(const HyperDual<T>& x) {
  using std::ceil;
  return HyperDual<T>(ceil(x.real));
}
template <class T>
HyperDual<T> round(const HyperDual<T>& x) {
  using std::round;
  return HyperDual<T>(round(x.real));
}
template <class T>
HyperDual<T> trunc(const HyperDual<T>& x) {
  using std::trunc;
  return HyperDual<T>(trunc(x.real));
}
template <class T>
bool isfinite(const HyperDual<T>& x) {
  using std::isfinite;
  return isfinite(x.real) && isfinite(x.e1) && isfinite(x.e2) && isfinite(x.e12);
}
template <class T>
bool isnan(const HyperDual<T>& x) {
  using std::isnan;
  return isnan(x.real) || isnan(x.e1) || isnan(x.e2) || isnan(x.e12);
}

/// f''(x), exactly, through one hyper-dual evaluation.
template <class T, class F>
T second_derivative(F&& f, const T& x) {
  return f(HyperDual<T>::variable(x)).e12;
}

/// ∂²f/∂x_i∂x_j of f(x, y) at a point, seeding x with ε1 and y with ε2.
template <class T, class F>
T mixed_derivative(F&& f, const T& x, const T& y) {
  return f(HyperDual<T>(x, T(1), T(0), T(0)), HyperDual<T>(y, T(0), T(1), T(0))).e12;
}

}  // namespace dq

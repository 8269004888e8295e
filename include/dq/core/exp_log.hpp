// exp, log, pow and sqrt of unit dual quaternions as true screw operations.
//
// For a unit dual quaternion Q = cos(θ̂/2) + ŝ sin(θ̂/2) (dual angle θ̂ = θ + ε d, dual axis
// ŝ = l + ε m), log Q = ŝ θ̂/2, a pure dual quaternion (0, u) + ε (0, v) with u = (θ/2) l and
// v = (θ/2) m + (d/2) l. So pow(Q, t) = exp(t log Q) is the screw motion with θ̂ scaled by t: the
// translation follows the screw, unlike the decoupled "log = θn/2 + ε t/2" some libraries use.
//
// Everything is written with sinc-type functions that have series near 0, so there is no
// division by a vanishing angle: exact for pure translations and accurate near the identity.
#pragma once

#include <cmath>

#include "dq/core/dual_quaternion.hpp"

namespace dq {

namespace detail {
/// g(a) = (a cos a − sin a)/a³ = sinc'(a)/a. The closed form cancels (its numerator is ≈ −a³/3),
/// losing about log2(1/a²) bits, so below |a| = 0.5 the Taylor series is used, through a¹²
/// (truncation below 3e-18 relative there): a few ulps everywhere (tested against long double).
template <class T>
T sinc_derivative_over_x(const T& a) {
  using std::abs;
  using std::cos;
  using std::sin;
  if (abs(value_of(a)) < real_t<T>(0.5)) {
    const T a2 = a * a;
    // −1/3 + a²/30 − a⁴/840 + a⁶/45360 − a⁸/3991680 + a¹⁰/518918400 − a¹²/93405312000, Horner in a².
    return T(-1) / T(3) +
           a2 * (T(1) / T(30) +
                 a2 * (T(-1) / T(840) +
                       a2 * (T(1) / T(45360) +
                             a2 * (T(-1) / T(3991680) + a2 * (T(1) / T(518918400) + a2 * (T(-1) / T(93405312000.0)))))));
  }
  return (a * cos(a) - sin(a)) / (a * a * a);
}
}  // namespace detail

/// exp of a pure dual quaternion ξ = (0, u) + ε (0, v) (the scalar parts are ignored): the unit
/// dual quaternion of the screw with half dual angle |u| + ε (u·v)/|u| about the dual axis û/|û|.
template <class T>
DualQuaternion<T> exp(const DualQuaternion<T>& xi) {
  using std::cos;
  using std::sqrt;
  const Vec3<T> u = xi.real.vec(), v = xi.dual.vec();
  const T a = sqrt(dot(u, u));
  const T uv = dot(u, v);
  const T s = detail::sinc(a);
  return {Quaternion<T>(cos(a), u * s), Quaternion<T>(-uv * s, v * s + u * (uv * detail::sinc_derivative_over_x(a)))};
}

/// The principal logarithm of a unit dual quaternion: a pure dual quaternion (0, u) + ε (0, v),
/// the half screw ŝ θ̂/2, with |u| = θ/2 ∈ [0, π). Q and −Q (the same transform) have different
/// logarithms; take the `canonical` sign first (w ≥ 0) for the shortest screw. The one input
/// with no principal logarithm, q_r = −1 exactly (a 2π turn, whose screw axis is undefined), is
/// answered with the logarithm of −Q, the same transform (a pure translation): documented choice.
template <class T>
DualQuaternion<T> log(const DualQuaternion<T>& q) {
  using std::atan2;
  using std::sqrt;
  const Vec3<T> vr = q.real.vec();
  const T s = sqrt(dot(vr, vr));
  if (s == T(0) && q.real.w < T(0)) return log(-q);
  const T a = atan2(s, q.real.w);  // half angle in [0, π)
  const Vec3<T> u = s > T(0) ? vr * (a / s) : Vec3<T>{};
  // Invert the dual part of exp: q_d = (−k sinc a, v sinc a + u k g(a)) with k = u·v.
  const T sa = detail::sinc(a);
  const T k = -q.dual.w / sa;
  const Vec3<T> v = (q.dual.vec() - u * (k * detail::sinc_derivative_over_x(a))) / sa;
  return {Quaternion<T>::pure(u), Quaternion<T>::pure(v)};
}

/// Q^t = exp(t log Q): the screw motion of Q scaled by t (θ and d both times t). Uses the
/// principal logarithm of Q as given (see log for the sign).
template <class T>
DualQuaternion<T> pow(const DualQuaternion<T>& q, const T& t) {
  return exp(log(q) * t);
}

/// The square root of a unit dual quaternion: half the screw motion (shortest, w ≥ 0 taken).
template <class T>
DualQuaternion<T> sqrt(const DualQuaternion<T>& q) {
  const DualQuaternion<T> c = q.real.w < T(0) ? -q : q;
  return pow(c, T(0.5));
}

}  // namespace dq

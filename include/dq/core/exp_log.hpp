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
#include <type_traits>

#include "dq/core/dual_quaternion.hpp"

namespace dq {

/// exp of a pure dual quaternion ξ = (0, u) + ε (0, v) (the scalar parts are ignored): the unit
/// dual quaternion of the screw with half dual angle |u| + ε (u·v)/|u| about the dual axis û/|û|.
template <class T>
DualQuaternion<T> exp(const DualQuaternion<T>& xi) {
  using std::cos;
  using std::sin;
  const Vec3<T> u = xi.real.vec(), v = xi.dual.vec();
  const T a2 = dot(u, u);
  if (value_of(a2) < detail::even_series_bound<real_t<T>>) {  // series in a²: smooth through a = 0
    auto a = [&] { return norm(u); };
    const T uv = dot(u, v);
    const T s = detail::sinc_of_squared(a2, a);
    return {Quaternion<T>(detail::cos_of_squared(a2, a), u * s),
            Quaternion<T>(-uv * s, v * s + u * (uv * detail::sinc_derivative_over_angle_of_squared(a2, a)))};
  }
  // Closed forms through the unit axis û = u/a, with k = û·v: q_d = (−k sin a, v sinc a +
  // û k (cos a − sinc a)). Every term is bounded by |v|, so huge screws (sclerp extrapolated to
  // t = 1e160) do not overflow in intermediate products.
  const T a = detail::angle_from_squared(a2, [&] { return norm(u); });
  const Vec3<T> axis = u / a;
  const T k = dot(axis, v), sn = sin(a), cs = cos(a), sc = sn / a;
  return {Quaternion<T>(cs, axis * sn), Quaternion<T>(-k * sn, v * sc + axis * (k * (cs - sc)))};
}

/// The principal logarithm of a unit dual quaternion: a pure dual quaternion (0, u) + ε (0, v),
/// the half screw ŝ θ̂/2, with |u| = θ/2 ∈ [0, π). Q and −Q (the same transform) have different
/// logarithms; take the `canonical` sign first (w ≥ 0) for the shortest screw. The one input
/// with no principal logarithm, q_r = −1 exactly (a 2π turn, whose screw axis is undefined), is
/// answered with the logarithm of −Q, the same transform (a pure translation): documented choice.
/// Smooth through the identity: values and derivatives of every order are right there.
template <class T>
DualQuaternion<T> log(const DualQuaternion<T>& q) {
  const Vec3<T> vr = q.real.vec();
  const T s2 = dot(vr, vr);
  if (value_of(q.real.w) < 0 && !(norm(vr) > T(0))) return log(-q);
  const Vec3<T> u = vr * detail::angle_over_sine(s2, q.real.w, [&] { return norm(vr); });  // |u| = a, half angle
  const T a2 = dot(u, u);
  auto a = [&] { return norm(u); };
  // Invert the dual part of exp: q_d = (−k sinc a, v sinc a + u k g(a)) with k = u·v.
  const T sa = detail::sinc_of_squared(a2, a);
  const T k = -q.dual.w / sa;
  const Vec3<T> v = (q.dual.vec() - u * (k * detail::sinc_derivative_over_angle_of_squared(a2, a))) / sa;
  return {Quaternion<T>::pure(u), Quaternion<T>::pure(v)};
}

/// Q^t = exp(t log Q): the screw motion of Q scaled by t (θ and d both times t). Uses the
/// principal logarithm of Q as given (see log for the sign).
template <class T>
DualQuaternion<T> pow(const DualQuaternion<T>& q, const std::type_identity_t<T>& t) {
  return exp(log(q) * t);
}

/// The square root of a unit dual quaternion: half the screw motion (shortest, w ≥ 0 taken).
template <class T>
DualQuaternion<T> sqrt(const DualQuaternion<T>& q) {
  const DualQuaternion<T> c = q.real.w < T(0) ? -q : q;
  return pow(c, T(0.5));
}

}  // namespace dq

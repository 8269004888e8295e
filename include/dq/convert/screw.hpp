// Screw motion: every rigid transform is a rotation by θ about an axis (unit direction l through
// a point c, moment m = c × l) combined with a translation d along that axis. With the dual angle
// θ̂ = θ + ε d and the dual axis ŝ = l + ε m, the unit dual quaternion is
// Q = cos(θ̂/2) + ŝ sin(θ̂/2) (VRML tutorial §2.4; Conventions).
#pragma once

#include <cmath>
#include <limits>

#include "dq/core/dual_quaternion.hpp"

namespace dq {

template <class T>
struct Screw {
  PluckerLine<T> axis{{T(1), T(0), T(0)}, {}};  ///< unit direction l and moment m
  T angle{};                                    ///< θ, radians (in [0, π] from to_screw)
  T translation{};                              ///< d, along l

  /// The dual angle θ + ε d.
  constexpr Dual<T> dual_angle() const noexcept { return {angle, translation}; }
};

/// Q = cos(θ̂/2) + (l + ε m) sin(θ̂/2), with the dual sine and cosine expanded:
/// sin(θ̂/2) = sin(θ/2) + ε (d/2) cos(θ/2), cos(θ̂/2) = cos(θ/2) − ε (d/2) sin(θ/2).
/// Exact for pure translations (θ = 0): 1 + ε (d/2) l.
template <class T>
DualQuaternion<T> from_screw(const Screw<T>& s) {
  const auto sc = detail::sin_cos(s.angle * T(0.5));
  const T half_d = s.translation * T(0.5);
  const Dual<T> sin_half{sc.sin, half_d * sc.cos}, cos_half{sc.cos, -half_d * sc.sin};
  const Vec3<T>& l = s.axis.direction;
  const Vec3<T>& m = s.axis.moment;
  return {Quaternion<T>(cos_half.real, l * sin_half.real),
          Quaternion<T>(cos_half.dual, m * sin_half.real + l * sin_half.dual)};
}

/// The screw of a unit dual quaternion, with θ ∈ [0, π]. A pure translation has θ = 0,
/// l = t/|t|, m = 0 and d = |t| (its axis is any parallel line: the one through the origin is
/// chosen); the identity gives l = (1, 0, 0) and d = 0. A rotation below the unit roundoff
/// (|q_r vector| ≤ ε, so that q_r.w = 1 to the last bit) counts as a pure translation: its axis
/// lies |t|/θ away, which for such θ can exceed the range of T, and the rotation it would keep is
/// below what a unit quaternion can hold.
template <class T>
Screw<T> to_screw(const DualQuaternion<T>& q) {
  using std::atan2;
  using std::sqrt;
  const bool flip = q.real.w < T(0);
  const DualQuaternion<T> u = flip ? -q : q;  // same transform, θ ∈ [0, π]
  const Vec3<T> t = u.translation();
  const Vec3<T> vr = u.real.vec();
  const T s = sqrt(dot(vr, vr));
  Screw<T> out;
  if (value_of(s) <= epsilon<T>()) {
    const T len = norm(t);  // hypot-based: no overflow for translations near the top of T's range
    if (len > T(0)) out.axis.direction = t / len;
    out.translation = len;
    return out;
  }
  const Vec3<T> l = vr / s;
  out.angle = T(2) * atan2(s, u.real.w);
  out.translation = dot(t, l);
  // The axis point c: m = c × l = ½ (t × l + cot(θ/2) (t − d l)).
  out.axis = {l, (cross(t, l) + (t - l * out.translation) * (u.real.w / s)) * T(0.5)};
  return out;
}

}  // namespace dq

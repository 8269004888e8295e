// Hyper-dual quaternions (Arends thesis, ch. 5): x = a + b ε1 + c ε2 + d ε1ε2 with quaternion
// coefficients a, b, c, d; ε1² = ε2² = 0 and ε1ε2 ≠ 0, the ε's commuting with quaternions.
//
// The thesis embeds a rigid transform in the ε1ε2 part, exactly as a dual quaternion uses ε
// (ε1ε2 squares to 0 too), with the conjugate x† = ā − b̄ ε1 − c̄ ε2 − d̄ ε1ε2. Note that this is
// not the conjugate induced by ε1 → −ε1, ε2 → −ε2 (which keeps the sign of ε1ε2 and would cancel
// the translation). The thesis writes the transform as r + ε1ε2 (0, T/2), which is right only for
// r = 1: the correct dual part is ½ t r, as for dual quaternions (docs/seed-errata.md).
#pragma once

#include <ostream>

#include "dq/core/dual_quaternion.hpp"

namespace dq {

template <class T>
struct HyperDualQuaternion {
  Quaternion<T> a{};                           ///< real part
  Quaternion<T> b{T(0), T(0), T(0), T(0)};     ///< ε1 part
  Quaternion<T> c{T(0), T(0), T(0), T(0)};     ///< ε2 part
  Quaternion<T> d{T(0), T(0), T(0), T(0)};     ///< ε1ε2 part

  static constexpr HyperDualQuaternion identity() noexcept { return {}; }

  /// The thesis' rigid transform, corrected: r + ε1ε2 (½ t r). Rotate by r, then translate by t.
  static constexpr HyperDualQuaternion from_rotation_translation(const Quaternion<T>& r, const Vec3<T>& t) noexcept {
    const Quaternion<T> zero(T(0), T(0), T(0), T(0));
    return {r, zero, zero, Quaternion<T>::pure(t * T(0.5)) * r};
  }
  /// Embeds a dual quaternion q_r + ε q_d as q_r + ε1ε2 q_d.
  static constexpr HyperDualQuaternion from_dual_quaternion(const DualQuaternion<T>& q) noexcept {
    const Quaternion<T> zero(T(0), T(0), T(0), T(0));
    return {q.real, zero, zero, q.dual};
  }
  /// A point as in the thesis: 1 + ε1ε2 (0, p).
  static constexpr HyperDualQuaternion point(const Vec3<T>& p) noexcept {
    const Quaternion<T> zero(T(0), T(0), T(0), T(0));
    return {Quaternion<T>::identity(), zero, zero, Quaternion<T>::pure(p)};
  }

  friend constexpr HyperDualQuaternion operator+(const HyperDualQuaternion& x, const HyperDualQuaternion& y) noexcept {
    return {x.a + y.a, x.b + y.b, x.c + y.c, x.d + y.d};
  }
  friend constexpr HyperDualQuaternion operator-(const HyperDualQuaternion& x, const HyperDualQuaternion& y) noexcept {
    return {x.a - y.a, x.b - y.b, x.c - y.c, x.d - y.d};
  }
  friend constexpr HyperDualQuaternion operator*(const HyperDualQuaternion& x, const T& s) noexcept {
    return {x.a * s, x.b * s, x.c * s, x.d * s};
  }
  /// The product: nine Hamilton products, the ε's commuting with the quaternion coefficients.
  friend constexpr HyperDualQuaternion operator*(const HyperDualQuaternion& x, const HyperDualQuaternion& y) noexcept {
    return {x.a * y.a, x.a * y.b + x.b * y.a, x.a * y.c + x.c * y.a,
            x.a * y.d + x.b * y.c + x.c * y.b + x.d * y.a};
  }
  friend constexpr bool operator==(const HyperDualQuaternion& x, const HyperDualQuaternion& y) noexcept {
    return x.a == y.a && x.b == y.b && x.c == y.c && x.d == y.d;
  }

  /// x† = ā − b̄ ε1 − c̄ ε2 − d̄ ε1ε2, the thesis' conjugate for transforming points.
  constexpr HyperDualQuaternion conjugate() const noexcept {
    return {a.conjugate(), -b.conjugate(), -c.conjugate(), -d.conjugate()};
  }

  /// p' = x (1 + ε1ε2 p) x†, read from the ε1ε2 part: R p + t for a transform built above.
  constexpr Vec3<T> transform_point(const Vec3<T>& p) const noexcept {
    return (*this * point(p) * conjugate()).d.vec();
  }

  friend std::ostream& operator<<(std::ostream& os, const HyperDualQuaternion& x) {
    return os << '[' << x.a << " + ε1" << x.b << " + ε2" << x.c << " + ε1ε2" << x.d << ']';
  }
};

}  // namespace dq

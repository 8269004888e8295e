// Dual quaternions Q = q_r + ε q_d (real part first, then dual part).
//
// A unit dual quaternion (|q_r| = 1, q_r · q_d = 0) is a rigid transform: "rotate by r, then
// translate by t" is Q = r + ε ½ t r, and t = 2 q_d q_r*. Products compose like matrices:
// (A B) applies B first. One type serves the whole algebra; functions that need the unit
// condition say so (see docs/design.md for why there is no separate unit type).
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <ostream>

#include "dq/core/dual.hpp"
#include "dq/core/quaternion.hpp"
#if DQKIT_PRODUCT_EIGHT_LANES
#include <immintrin.h>  // the eight-lane product's insertion of the dual part (detail::dual_product_lanes)
#endif

namespace dq {

/// A line in Plücker coordinates: unit direction l and moment m = p × l for any point p on it.
template <class T>
struct PluckerLine {
  Vec3<T> direction;
  Vec3<T> moment;

  /// The line through point p with direction d (normalized here).
  static PluckerLine through(const Vec3<T>& p, const Vec3<T>& d) {
    const Vec3<T> l = normalized(d);
    return {l, cross(p, l)};
  }
  /// The point of the line closest to the origin: l × m (for unit l).
  constexpr Vec3<T> closest_point_to_origin() const noexcept { return cross(direction, moment); }
};

/// A plane {x : n · x = d} with unit normal n and signed distance d from the origin.
template <class T>
struct Plane {
  Vec3<T> normal{T(0), T(0), T(1)};
  T distance{};
};

template <class T>
struct DualQuaternion;
namespace detail {
/// The dual quaternion product, written once for the scalar type and the batch kernels:
/// q_r = a_r b_r, q_d = a_r b_d + a_d b_r, with `mul` the Hamilton product to use.
template <class T, class Mul>
constexpr DualQuaternion<T> dual_product(const DualQuaternion<T>& a, const DualQuaternion<T>& b, Mul mul) noexcept {
  return {mul(a.real, b.real), mul(a.real, b.dual) + mul(a.dual, b.real)};
}
#if DQKIT_PRODUCT_EIGHT_LANES
[[gnu::always_inline]] inline DualQuaternion<float> dual_product_lanes(const DualQuaternion<float>& a,
                                                                       const DualQuaternion<float>& b) noexcept;
#endif
}  // namespace detail

template <class T>
struct DualQuaternion {
  using scalar_type = T;
  Quaternion<T> real{};                          ///< q_r: the rotation
  Quaternion<T> dual{T(0), T(0), T(0), T(0)};    ///< q_d = ½ t q_r for a rigid transform

  constexpr DualQuaternion() noexcept = default;  ///< the identity
  constexpr DualQuaternion(const Quaternion<T>& r, const Quaternion<T>& d) noexcept : real(r), dual(d) {}
  /// From the eight components in the order q_r (w, x, y, z), q_d (w, x, y, z).
  constexpr DualQuaternion(const T& rw, const T& rx, const T& ry, const T& rz, const T& dw, const T& dx,
                           const T& dy, const T& dz) noexcept
      : real(rw, rx, ry, rz), dual(dw, dx, dy, dz) {}

  static constexpr DualQuaternion identity() noexcept { return {}; }

  /// The same dual quaternion in another scalar type (each component converted with static_cast).
  template <class U>
  constexpr DualQuaternion<U> cast() const noexcept {
    return {real.template cast<U>(), dual.template cast<U>()};
  }
  /// A pure rotation by the unit quaternion r.
  static constexpr DualQuaternion from_rotation(const Quaternion<T>& r) noexcept {
    return {r, Quaternion<T>(T(0), T(0), T(0), T(0))};
  }
  /// A pure translation: 1 + ε ½ t.
  static constexpr DualQuaternion from_translation(const Vec3<T>& t) noexcept {
    return {Quaternion<T>::identity(), Quaternion<T>::pure(t * T(0.5))};
  }
  /// Rotate by the unit quaternion r, then translate by t: r + ε ½ t r.
  static constexpr DualQuaternion from_rotation_translation(const Quaternion<T>& r, const Vec3<T>& t) noexcept {
    return {r, Quaternion<T>::pure(t * T(0.5)) * r};
  }

  // ---- algebra --------------------------------------------------------------------------------
  friend constexpr DualQuaternion operator-(const DualQuaternion& q) noexcept { return {-q.real, -q.dual}; }
  friend constexpr DualQuaternion operator+(const DualQuaternion& a, const DualQuaternion& b) noexcept {
    return {a.real + b.real, a.dual + b.dual};
  }
  friend constexpr DualQuaternion operator-(const DualQuaternion& a, const DualQuaternion& b) noexcept {
    return {a.real - b.real, a.dual - b.dual};
  }
  friend constexpr DualQuaternion operator*(const DualQuaternion& a, const T& s) noexcept {
    return {a.real * s, a.dual * s};
  }
  friend constexpr DualQuaternion operator*(const T& s, const DualQuaternion& a) noexcept { return a * s; }
  friend constexpr DualQuaternion operator/(const DualQuaternion& a, const T& s) noexcept {
    return {a.real / s, a.dual / s};
  }
  /// Multiplication by a dual number s = a + εb: (a + εb)(q_r + ε q_d) = a q_r + ε (a q_d + b q_r).
  friend constexpr DualQuaternion operator*(const Dual<T>& s, const DualQuaternion& q) noexcept {
    return {q.real * s.real, q.dual * s.real + q.real * s.dual};
  }
  /// The product: q_r = a_r b_r, q_d = a_r b_d + a_d b_r (three Hamilton products). For float
  /// the products and the dual part's sum stay in vector registers, four lanes at a time, or
  /// eight where the build targets AVX (DQKIT_PRODUCT_EIGHT_LANES, detail::dual_product_lanes);
  /// bit-identical either way: the same operations in the same order per component.
  friend constexpr DualQuaternion operator*(const DualQuaternion& a, const DualQuaternion& b) noexcept {
#if DQKIT_VECTOR_EXTENSIONS
    if constexpr (std::is_same_v<T, float>) {
      if (!std::is_constant_evaluated()) {
#if DQKIT_PRODUCT_EIGHT_LANES
        return detail::dual_product_lanes(a, b);
#else
        const auto ar = detail::to_lanes(a.real), ad = detail::to_lanes(a.dual);
        const auto br = detail::to_lanes(b.real), bd = detail::to_lanes(b.dual);
        return {detail::from_lanes(detail::hamilton_lanes(ar, br)),
                detail::from_lanes(detail::hamilton_lanes(ar, bd) + detail::hamilton_lanes(ad, br))};
#endif
      }
    }
#endif
    return detail::dual_product(a, b, [](const Quaternion<T>& l, const Quaternion<T>& r) { return l * r; });
  }
  constexpr DualQuaternion& operator*=(const DualQuaternion& o) noexcept { return *this = *this * o; }
  constexpr DualQuaternion& operator+=(const DualQuaternion& o) noexcept { return *this = *this + o; }

  /// Exact, component-wise (Q and −Q differ; use approx_equal for transforms).
  friend constexpr bool operator==(const DualQuaternion& a, const DualQuaternion& b) noexcept {
    return a.real == b.real && a.dual == b.dual;
  }

  /// Q* = q_r* + ε q_d*, the quaternion conjugate; the inverse of a unit dual quaternion.
  constexpr DualQuaternion conjugate() const noexcept { return {real.conjugate(), dual.conjugate()}; }
  /// Q• = q_r − ε q_d, the dual conjugate.
  constexpr DualQuaternion dual_conjugate() const noexcept { return {real, -dual}; }
  /// Q̄ = q_r* − ε q_d*, the combined conjugate used to transform points.
  constexpr DualQuaternion combined_conjugate() const noexcept { return {real.conjugate(), -dual.conjugate()}; }

  /// Q Q* = |q_r|² + ε 2 (q_r · q_d), a dual number.
  constexpr Dual<T> squared_norm() const noexcept { return {dot(real, real), T(2) * dot(real, dual)}; }
  /// The dual-number norm ‖Q‖ = |q_r| + ε (q_r · q_d)/|q_r|.
  Dual<T> norm() const {
    const T n = real.norm();
    return {n, dot(real, dual) / n};
  }

  /// Q/‖Q‖: the nearest unit dual quaternion, enforcing both |q_r| = 1 and q_r · q_d = 0 (a plain
  /// division by |q_r|, as in GLM or the Kenwright listing, leaves q_r · q_d ≠ 0). A zero real
  /// part gives the identity (documented choice); non-finite input gives non-finite output.
  DualQuaternion normalized() const {
    using std::abs;
    const T n = real.norm();
    if (n == T(0)) {  // no rotation to normalize: the identity, keeping a NaN of the dual part
      const T z = nan_if_not_finite(dot(dual, dual));
      return {Quaternion<T>(T(1) + z, z, z, z), Quaternion<T>(z, z, z, z)};
    }
    const real_t<T> nv = value_of(n);
    // (An infinite or NaN norm is not rescaled: non-finite in, non-finite out.)
    if (nv < std::numeric_limits<real_t<T>>::min() || (nv > std::numeric_limits<real_t<T>>::max() / 4 && nv <= std::numeric_limits<real_t<T>>::max())) {
      // A denormal (or huge) real part: dividing by its norm loses its bits. Scale the whole
      // dual quaternion by a power of two first (exact) so that the real part is of order one.
      using std::ilogb;
      const int e = -ilogb(nv);
      return DualQuaternion(detail::scale_by_power_of_two(real, e), detail::scale_by_power_of_two(dual, e)).normalized();
    }
    const Quaternion<T> r = real / n;
    const Quaternion<T> d = dual / n;
    const T k = dot(r, d);
    const Quaternion<T> p = d - r * k;
    // When most of d lay along r, that projection cancelled and left rounding noise that is itself
    // along r. Then rebuild the dual part from the translation instead: with v = vec(d r*),
    // (0, v) r is orthogonal to r by construction, to the rounding of its own size.
    const T largest = std::max({abs(p.w), abs(p.x), abs(p.y), abs(p.z)});
    if (abs(k) > largest) return {r, Quaternion<T>::pure((d * r.conjugate()).vec()) * r};
    return {r, p};
  }
  void normalize() { *this = normalized(); }

  /// Whether |q_r| = 1 and q_r · q_d = 0 within `tolerance` (relative to the translation size).
  bool is_unit(const T& tolerance) const {
    using std::abs;
    const T rr = dot(real, real);
    return abs(rr - T(1)) <= tolerance && abs(dot(real, dual)) <= tolerance * (T(1) + dual.norm());
  }

  /// The inverse of any dual quaternion with q_r ≠ 0: q_r⁻¹ − ε q_r⁻¹ q_d q_r⁻¹. With q_r = 0
  /// there is no inverse: the real part is (+∞, 0, 0, 0) (see Quaternion::inverse) and the dual
  /// part is not finite.
  DualQuaternion inverse() const {
    const Quaternion<T> ri = real.inverse();
    return {ri, -(ri * dual * ri)};
  }
  /// The inverse of a unit dual quaternion: its quaternion conjugate (no division).
  constexpr DualQuaternion inverse_unit() const noexcept { return conjugate(); }

  // ---- rigid-transform access (unit dual quaternions) -------------------------------------------
  constexpr const Quaternion<T>& rotation() const noexcept { return real; }
  /// t = 2 q_d q_r* (vector part), for a unit dual quaternion.
  constexpr Vec3<T> translation() const noexcept {
    const Vec3<T> vr = real.vec(), vd = dual.vec();
    return (vd * real.w - vr * dual.w + cross(vr, vd)) * T(2);
  }

  /// R p + t for a unit dual quaternion, in a short form that shares one sum between the rotation
  /// and the translation: with real part (w, r) and dual part (w_d, d), c = r × p + d and
  /// p + 2 [w c + r × c − w_d r]: 21 multiplications and 18 additions, where R p and t computed
  /// apart take 33 and 24, and GLM's form, p + 2 [r × (r × p + w p + d) + w d − w_d r], 24 and 21
  /// (docs/operation-counts.md).
  /// For float it may run x, y and z in the lanes of one vector (DQKIT_VEC3_LANES), bit-identical.
  constexpr Vec3<T> transform_point(const Vec3<T>& p) const noexcept {
#if DQKIT_VEC3_LANES
    if constexpr (std::is_same_v<T, float>) {
      if (!std::is_constant_evaluated()) {
        using detail::float4, detail::cross_lanes;
        const detail::QuaternionParts r = detail::parts(detail::to_lanes(real)), d = detail::parts(detail::to_lanes(dual));
        const float4 vp = detail::to_lanes(p);
        const float4 c = cross_lanes(r, vp) + d.xyz;
        const float4 u = (c * r.w + cross_lanes(r, c)) - r.xyz * d.w;
        return detail::vec3_from_lanes(vp + u * float4{2, 2, 2, 2});
      }
    }
#endif
    const Vec3<T> r = real.vec(), d = dual.vec();
    const Vec3<T> c = cross(r, p) + d;
    return p + (c * real.w + cross(r, c) - r * dual.w) * T(2);
  }
  /// Q (1 + ε p) Q̄ taken literally (the seeds' definition; slower, used as the reference form).
  constexpr Vec3<T> transform_point_sandwich(const Vec3<T>& p) const noexcept {
    const DualQuaternion point{Quaternion<T>::identity(), Quaternion<T>::pure(p)};
    return (*this * point * combined_conjugate()).dual.vec();
  }
  /// A direction (free vector) is only rotated.
  constexpr Vec3<T> transform_direction(const Vec3<T>& v) const noexcept { return real.rotate(v); }
  /// Q (l + ε m) Q*: l' = R l, m' = R m + t × l'.
  constexpr PluckerLine<T> transform_line(const PluckerLine<T>& line) const noexcept {
    const Vec3<T> l = real.rotate(line.direction);
    return {l, real.rotate(line.moment) + cross(translation(), l)};
  }
  /// The plane n · x = d maps to n' · x = d + n' · t with n' = R n.
  constexpr Plane<T> transform_plane(const Plane<T>& plane) const noexcept {
    const Vec3<T> n = real.rotate(plane.normal);
    return {n, plane.distance + dot(n, translation())};
  }

  friend std::ostream& operator<<(std::ostream& os, const DualQuaternion& q) {
    return os << '[' << q.real << " + ε" << q.dual << ']';
  }
};

namespace detail {
#if DQKIT_PRODUCT_EIGHT_LANES
/// The float product with AVX's eight lanes: (a_r b_r, a_r b_d) as one eight-lane Hamilton product
/// of a_r's components (broadcast from memory) with b's signed permutations, whose low halves then
/// serve a_d b_r; the same operations in the same order as the four-lane form, so bit for bit
/// its result. Faster for independent products (DQKIT_PRODUCT_EIGHT_LANES); in a chain x = x · a
/// GCC 12 keeps x in memory and broadcasts its components from there, a store forwarding on the
/// chain's path: 6.3 against 4.8 µs per 1023 links with four lanes (bench_core, 2026-12-06),
/// still faster than GLM's 8.5. Broadcast by shuffles in registers instead, the chain took 5.2 µs
/// and independent products 2.5 instead of 1.9 µs per 1024, so a's components come from memory
/// (docs/performance.md). b enters as its two halves, the dual part inserted above the
/// real part (AVX's vinsertf128, from memory or a register), not as one 32-byte copy of its
/// memory: in a chain x = a · x that copy read a dual quaternion just stored as two 16-byte
/// halves, which a load cannot take from the stores in flight (bench_core's
/// PrependChainDualQuaternion: 9.4–10.8 against 6.0–6.6 µs per 1024 links, GLM's 7.3–7.6). (Joined with
/// a generic two-vector shuffle instead, GCC 12 loads both halves apart: one instruction more.)
[[gnu::always_inline]] inline DualQuaternion<float> dual_product_lanes(const DualQuaternion<float>& a,
                                                                       const DualQuaternion<float>& b) noexcept {
  using float8 = float __attribute__((vector_size(32)));
  const auto all8 = [](float v) { return float8{v, v, v, v, v, v, v, v}; };
  const auto all4 = [](float v) { return float4{v, v, v, v}; };
  const float8 vb = _mm256_insertf128_ps(_mm256_castps128_ps256(to_lanes(b.real)), to_lanes(b.dual), 1);
  const float8 b1 = __builtin_shufflevector(vb, vb, 1, 0, 3, 2, 5, 4, 7, 6) * float8{-1, 1, -1, 1, -1, 1, -1, 1};
  const float8 b2 = __builtin_shufflevector(vb, vb, 2, 3, 0, 1, 6, 7, 4, 5) * float8{-1, 1, 1, -1, -1, 1, 1, -1};
  const float8 b3 = __builtin_shufflevector(vb, vb, 3, 2, 1, 0, 7, 6, 5, 4) * float8{-1, -1, 1, 1, -1, -1, 1, 1};
  const float8 real_first = hamilton_sum(all8(a.real.w), all8(a.real.x), all8(a.real.y), all8(a.real.z), vb, b1, b2, b3);  // (a_r b_r, a_r b_d)
  const auto low = [](const float8& v) { return float4(__builtin_shufflevector(v, v, 0, 1, 2, 3)); };
  const float4 dual_real = hamilton_sum(all4(a.dual.w), all4(a.dual.x), all4(a.dual.y), all4(a.dual.z), low(vb), low(b1), low(b2), low(b3));
  const float4 dual = float4(__builtin_shufflevector(real_first, real_first, 4, 5, 6, 7)) + dual_real;
  return {from_lanes(low(real_first)), from_lanes(dual)};
}
#endif
template <class X>
inline constexpr bool is_dual_quaternion_v = false;
template <class T>
inline constexpr bool is_dual_quaternion_v<DualQuaternion<T>> = true;
/// The result of a call whose precondition failed with a handler that returned: NaN, never a
/// plausible transform.
template <class T>
DualQuaternion<T> nan_dual_quaternion() {
  const T n = T(std::numeric_limits<real_t<T>>::quiet_NaN());
  return {n, n, n, n, n, n, n, n};
}
}  // namespace detail

/// Approximate comparison of all eight components; with SignPolicy::same_rotation, Q and −Q
/// (the same rigid transform) compare equal.
template <class T>
bool approx_equal(const DualQuaternion<T>& a, const DualQuaternion<T>& b, const std::type_identity_t<T>& tolerance,
                  SignPolicy policy = SignPolicy::exact) {
  auto close = [&](const DualQuaternion<T>& u) {
    return approx_equal(a.real, u.real, tolerance) && approx_equal(a.dual, u.dual, tolerance);
  };
  return close(b) || (policy == SignPolicy::same_rotation && close(-b));
}

}  // namespace dq

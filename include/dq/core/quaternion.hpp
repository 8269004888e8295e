// Quaternions w + x i + y j + z k with the Hamilton product (ij = k).
//
// Stored as four named members in the order w, x, y, z; constructors and printing use that order.
// A unit quaternion (cos θ/2, n sin θ/2) rotates vectors actively, right-handed: v' = q v q*.
// q and −q are the same rotation; `canonical()` picks the representative with w ≥ 0.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <ostream>
#include <type_traits>

#include "dq/core/matrix.hpp"
#include "dq/core/scalar.hpp"
#include "dq/core/series.hpp"
#include "dq/core/vec3.hpp"

namespace dq {

namespace detail {
/// (sin a, cos a), exact (0, ±1 exactly) when a is a multiple of π/2 as rounded in T, so that
/// axis-angle rotations by 0, π and 2π give exact quaternions. Derivative scalars skip the table.
template <class T>
struct SinCos {
  T sin, cos;
};
template <class T>
SinCos<T> sin_cos(const T& a) {
  using std::cos;
  using std::sin;
  if constexpr (std::is_floating_point_v<T>) {
    // k = a ÷ (π/2) rounded to an integer, cheaply (this runs in IK's inner loops, through
    // from_rotation_vector): a product instead of a division, and rounding by adding and removing
    // 1.5 · 2^(digits − 1), exact for |k| below 2^(digits − 2) and harmless beyond (k is then not
    // below 2^20). A multiple of π/2 as rounded in T gives its k exactly; the test k · π/2 == a
    // then decides, so an approximate k only ever falls through to sin and cos.
    constexpr T half_pi = std::numbers::pi_v<T> / 2, two_over_pi = 2 / std::numbers::pi_v<T>;
    constexpr T round_bias = T(1.5) * T(1ull << (std::numeric_limits<T>::digits - 1));
    using std::abs;
    const T k = (a * two_over_pi + round_bias) - round_bias;
    if (abs(k) < T(1 << 20) && k * half_pi == a) {
      const long long quadrant = static_cast<long long>(k) & 3;  // two's complement: mod 4
      constexpr T one = 1, zero = 0;
      switch (quadrant) {
        case 0: return {zero, one};
        case 1: return {one, zero};
        case 2: return {zero, -one};
        default: return {-one, zero};
      }
    }
  }
  return {sin(a), cos(a)};
}
}  // namespace detail

template <class T>
struct Quaternion;
namespace detail {
template <class T>
constexpr Quaternion<T> hamilton(const Quaternion<T>& a, const Quaternion<T>& b) noexcept;
Quaternion<float> hamilton_lanes(const Quaternion<float>& a, const Quaternion<float>& b) noexcept;
Vec3<float> rotate_lanes(const Quaternion<float>& q, const Vec3<float>& v) noexcept;
template <class T>
Quaternion<T> exp_pure(const Vec3<T>& v);
template <class T>
Vec3<T> log_unit_vector(const Quaternion<T>& q);
}  // namespace detail

template <class T>
struct AxisAngle {
  Vec3<T> axis{T(1), T(0), T(0)};  ///< unit axis; (1, 0, 0) for the identity
  T angle{};                       ///< radians, in [0, π] when produced by dqkit
};

template <class T>
struct Quaternion {
  using scalar_type = T;
  T w{1}, x{}, y{}, z{};

  constexpr Quaternion() noexcept = default;  ///< the identity
  constexpr Quaternion(const T& w_, const T& x_, const T& y_, const T& z_) noexcept : w(w_), x(x_), y(y_), z(z_) {}
  /// From a scalar part and a vector part.
  constexpr Quaternion(const T& w_, const Vec3<T>& v) noexcept : w(w_), x(v.x), y(v.y), z(v.z) {}

  static constexpr Quaternion identity() noexcept { return {}; }
  /// The pure quaternion (0, v).
  static constexpr Quaternion pure(const Vec3<T>& v) noexcept { return {T(0), v}; }

  constexpr Vec3<T> vec() const noexcept { return {x, y, z}; }

  /// The same quaternion in another scalar type (each component converted with static_cast).
  template <class U>
  constexpr Quaternion<U> cast() const noexcept {
    return {static_cast<U>(w), static_cast<U>(x), static_cast<U>(y), static_cast<U>(z)};
  }

  // ---- algebra --------------------------------------------------------------------------------
  friend constexpr Quaternion operator-(const Quaternion& q) noexcept { return {-q.w, -q.x, -q.y, -q.z}; }
  friend constexpr Quaternion operator+(const Quaternion& a, const Quaternion& b) noexcept {
    return {a.w + b.w, a.x + b.x, a.y + b.y, a.z + b.z};
  }
  friend constexpr Quaternion operator-(const Quaternion& a, const Quaternion& b) noexcept {
    return {a.w - b.w, a.x - b.x, a.y - b.y, a.z - b.z};
  }
  friend constexpr Quaternion operator*(const Quaternion& a, const T& s) noexcept {
    return {a.w * s, a.x * s, a.y * s, a.z * s};
  }
  friend constexpr Quaternion operator*(const T& s, const Quaternion& a) noexcept { return a * s; }
  friend constexpr Quaternion operator/(const Quaternion& a, const T& s) noexcept {
    return {a.w / s, a.x / s, a.y / s, a.z / s};
  }
  /// The Hamilton product: 16 multiplications, 12 additions (detail::hamilton, the one formula).
  /// For float it runs four components at a time (detail::hamilton_lanes), with the same
  /// operations in the same order per component, so the result is bit-identical.
  friend constexpr Quaternion operator*(const Quaternion& a, const Quaternion& b) noexcept {
#if DQKIT_VECTOR_EXTENSIONS
    if constexpr (std::is_same_v<T, float>) {
      if (!std::is_constant_evaluated()) return detail::hamilton_lanes(a, b);
    }
#endif
    return detail::hamilton(a, b);
  }
  constexpr Quaternion& operator+=(const Quaternion& o) noexcept { return *this = *this + o; }
  constexpr Quaternion& operator-=(const Quaternion& o) noexcept { return *this = *this - o; }
  constexpr Quaternion& operator*=(const Quaternion& o) noexcept { return *this = *this * o; }
  constexpr Quaternion& operator*=(const T& s) noexcept { return *this = *this * s; }

  /// Exact, component-wise: q and −q are different quaternions (use approx_equal for rotations).
  friend constexpr bool operator==(const Quaternion& a, const Quaternion& b) noexcept {
    return a.w == b.w && a.x == b.x && a.y == b.y && a.z == b.z;
  }

  constexpr Quaternion conjugate() const noexcept { return {w, -x, -y, -z}; }
  constexpr T squared_norm() const noexcept { return w * w + x * x + y * y + z * z; }

  /// |q|, without overflow or underflow for huge or tiny components.
  T norm() const {
    using std::sqrt;
    const T n2 = squared_norm();
    if (in_safe_range(n2)) return sqrt(n2);
    const T s = max_abs();
    if (!(s > T(0)) || !(value_of(s) < std::numeric_limits<real_t<T>>::infinity())) return s;  // 0, NaN, ∞
    return s * sqrt((*this / s).squared_norm());
  }

  /// q/|q|. The zero quaternion has no direction: the result is the identity (documented choice,
  /// never NaN). Non-finite input gives non-finite output (NaN propagates). Components near the
  /// limits of T (huge, tiny or denormal) are rescaled first, so the result is still unit.
  Quaternion normalized() const {
    using std::sqrt;
    const T n2 = squared_norm();
    if (in_safe_range(n2)) [[likely]] return *this * (T(1) / sqrt(n2));
    return normalized_rescaled(n2);
  }
  void normalize() { *this = normalized(); }

  /// q⁻¹ = q*/|q|², without overflow or underflow in |q|² (so (1e-200, 0, 0, 0) inverts to
  /// 1e200). The zero quaternion has no inverse: it gives (+∞, 0, 0, 0), as 1/0 = +∞ for reals.
  Quaternion inverse() const {
    const T n = norm();
    if (n == T(0)) return {T(std::numeric_limits<real_t<T>>::infinity()), T(0), T(0), T(0)};
    return conjugate() / n / n;
  }

  /// The representative of ±q with w ≥ 0; where w = 0, the first non-zero of x, y, z positive.
  constexpr Quaternion canonical() const noexcept {
    const bool flip = w < T(0) || (w == T(0) && (x < T(0) || (x == T(0) && (y < T(0) || (y == T(0) && z < T(0))))));
    return flip ? -*this : *this;
  }

  // ---- rotations --------------------------------------------------------------------------------
  /// Rotation by `angle` radians about `axis` (normalized here; a zero axis gives the identity).
  /// Angles that are multiples of π (0, π, 2π, ...) give exact components.
  static Quaternion from_axis_angle(const Vec3<T>& axis, const T& angle) {
    const T n = norm_of(axis);
    if (n == T(0)) return {T(1) + nan_if_not_finite(angle), T(0), T(0), T(0)};  // a NaN angle stays NaN
    const auto sc = detail::sin_cos(angle * T(0.5));
    return {sc.cos, (axis / n) * sc.sin};  // not sin/n: that overflows for a denormal axis
  }
  static Quaternion from_axis_angle(const AxisAngle<T>& aa) { return from_axis_angle(aa.axis, aa.angle); }

  /// Axis and angle of the canonical representative: angle in [0, π], computed with atan2 so
  /// that it is accurate near 0 and π (acos is not). The identity gives axis (1, 0, 0), angle 0;
  /// there the angle's derivative (Dual scalars) is the one-sided one, 2|v'|/w, as for |x| at 0.
  /// Assumes a unit quaternion (a non-unit one gives the axis-angle of its direction).
  AxisAngle<T> to_axis_angle() const {
    using std::atan2;
    const Quaternion c = canonical();
    const T s = dq::norm(c.vec());  // hypot: no underflow, and the one-sided derivative at 0
    const T angle = T(2) * atan2(s, c.w);
    if (!(s > T(0))) {  // the identity, or NaN (which stays NaN in the axis too)
      const T nan_or_zero = nan_if_not_finite(c.w + s);
      return {Vec3<T>{T(1) + nan_or_zero, nan_or_zero, nan_or_zero}, angle};
    }
    return {c.vec() / s, angle};
  }

  /// From a rotation vector (axis × angle, radians): exp of the pure quaternion v/2. Smooth
  /// through v = 0 (values and derivatives), exact for rotations so small their square underflows,
  /// and exact, as from_axis_angle, where |v|/2 is a multiple of π/2 as rounded (π and 2π about an axis).
  static Quaternion from_rotation_vector(const Vec3<T>& v) { return detail::exp_pure(v * T(0.5)); }
  /// The rotation vector of the canonical representative, |v| ∈ [0, π]: 2 log(q) for unit q.
  /// Smooth through the identity (values and derivatives).
  Vec3<T> to_rotation_vector() const { return detail::log_unit_vector(canonical()) * T(2); }

  /// Rotates v (q unit): v + 2w (u × v) + 2 u × (u × v): 18 multiplications, 12 additions.
  /// For float it may run x, y and z in the lanes of one vector (detail::rotate_lanes,
  /// DQKIT_VEC3_LANES), bit-identical.
  constexpr Vec3<T> rotate(const Vec3<T>& v) const noexcept {
#if DQKIT_VEC3_LANES
    if constexpr (std::is_same_v<T, float>) {
      if (!std::is_constant_evaluated()) return detail::rotate_lanes(*this, v);
    }
#endif
    const Vec3<T> u = vec();
    const Vec3<T> t = cross(u, v) * T(2);
    return v + t * w + cross(u, t);
  }
  /// Rotates v by the sandwich q (0, v) q* (two Hamilton products), the textbook form.
  constexpr Vec3<T> rotate_sandwich(const Vec3<T>& v) const noexcept { return (*this * pure(v) * conjugate()).vec(); }

  /// The shortest rotation taking direction a to direction b (neither need be unit). For
  /// antiparallel directions the rotation is by π about an axis orthogonal to a (any is valid;
  /// dqkit picks the one from a's smallest component). A zero input gives the identity.
  static Quaternion from_two_vectors(const Vec3<T>& a, const Vec3<T>& b) {
    const T na = norm_of(a), nb = norm_of(b);
    if (na == T(0) || nb == T(0)) return identity();
    const Vec3<T> ua = a / na, ub = b / nb;
    const T c = dot(ua, ub);
    if (value_of(c) < real_t<T>(-1) + real_t<T>(8) * epsilon<T>()) {
      // Near antiparallel the cross product loses its direction: rotate by π about ⟂ a, then
      // correct the small remainder exactly.
      const Quaternion half_turn = pure(any_orthogonal(ua));
      const Vec3<T> turned = half_turn.rotate(ua);
      return (from_unit_close(turned, ub) * half_turn).normalized();
    }
    return from_unit_close(ua, ub);
  }

  /// The 3x3 rotation matrix of a unit quaternion (CONVENTIONS.md).
  constexpr Mat3<T> to_matrix() const noexcept {
    const T xx = x * x, yy = y * y, zz = z * z, xy = x * y, xz = x * z, yz = y * z;
    const T wx = w * x, wy = w * y, wz = w * z;
    return Mat3<T>::from_rows(T(1) - T(2) * (yy + zz), T(2) * (xy - wz), T(2) * (xz + wy),  //
                              T(2) * (xy + wz), T(1) - T(2) * (xx + zz), T(2) * (yz - wx),  //
                              T(2) * (xz - wy), T(2) * (yz + wx), T(1) - T(2) * (xx + yy));
  }

  /// The unit quaternion of a rotation matrix (Shepperd's method: the largest of the four
  /// diagonal combinations is used, so no branch divides by a small number). Returns the
  /// canonical representative. A matrix that is not orthonormal gives the rotation of its
  /// nearest quaternion in the least-squares sense only approximately: orthonormalize first.
  static Quaternion from_matrix(const Mat3<T>& m) {
    using std::sqrt;
    const T tr = m(0, 0) + m(1, 1) + m(2, 2);
    Quaternion q;
    if (tr >= m(0, 0) && tr >= m(1, 1) && tr >= m(2, 2)) {
      const T s = sqrt(T(1) + tr) * T(2);  // s = 4w
      q = {s / T(4), (m(2, 1) - m(1, 2)) / s, (m(0, 2) - m(2, 0)) / s, (m(1, 0) - m(0, 1)) / s};
    } else if (m(0, 0) >= m(1, 1) && m(0, 0) >= m(2, 2)) {
      const T s = sqrt(T(1) + m(0, 0) - m(1, 1) - m(2, 2)) * T(2);  // s = 4x
      q = {(m(2, 1) - m(1, 2)) / s, s / T(4), (m(0, 1) + m(1, 0)) / s, (m(0, 2) + m(2, 0)) / s};
    } else if (m(1, 1) >= m(2, 2)) {
      const T s = sqrt(T(1) + m(1, 1) - m(0, 0) - m(2, 2)) * T(2);  // s = 4y
      q = {(m(0, 2) - m(2, 0)) / s, (m(0, 1) + m(1, 0)) / s, s / T(4), (m(1, 2) + m(2, 1)) / s};
    } else {
      const T s = sqrt(T(1) + m(2, 2) - m(0, 0) - m(1, 1)) * T(2);  // s = 4z
      q = {(m(1, 0) - m(0, 1)) / s, (m(0, 2) + m(2, 0)) / s, (m(1, 2) + m(2, 1)) / s, s / T(4)};
    }
    return q.normalized().canonical();
  }

  friend std::ostream& operator<<(std::ostream& os, const Quaternion& q) {
    return os << '(' << q.w << ", " << q.x << ", " << q.y << ", " << q.z << ')';
  }

 private:
  static bool in_safe_range(const T& n2) {
    const real_t<T> v = value_of(n2);
    return v >= std::numeric_limits<real_t<T>>::min() && v <= std::numeric_limits<real_t<T>>::max();
  }
  /// normalized() where |q|² underflows or overflows: kept out of line, so that the common path
  /// inlines into its callers (slerp took twice the time with normalized() as a call).
  [[gnu::noinline]] Quaternion normalized_rescaled(const T& n2) const {
    using std::sqrt;
    if (n2 == T(0) && max_abs() == T(0)) return identity();
    const Quaternion u = *this / max_abs();  // the largest component becomes ±1
    return u * (T(1) / sqrt(u.squared_norm()));
  }
  T max_abs() const {
    using std::abs;
    T s = abs(w);
    for (const T* c : {&x, &y, &z}) s = abs(*c) > s ? abs(*c) : s;
    return s;
  }
  /// |v|: the fast √(v·v) where v·v neither underflows nor overflows, hypot otherwise (so that the
  /// axis of a rotation by 1e-20 rad in float is still exact).
  static T norm_of(const Vec3<T>& v) {
    using std::sqrt;
    const T n2 = dot(v, v);
    return in_safe_range(n2) ? sqrt(n2) : dq::norm(v);
  }
  // Unit a, b not antiparallel: q = (1 + a·b, a × b) normalized (the half-way construction).
  static Quaternion from_unit_close(const Vec3<T>& a, const Vec3<T>& b) {
    return Quaternion(T(1) + dot(a, b), cross(a, b)).normalized();
  }
};

namespace detail {
/// The Hamilton product, written once: the scalar types, the four-lane float product below and
/// the batch kernels (forward_kinematics.hpp) all compute exactly this, term by term. The four
/// products of each component are summed in pairs, two additions deep instead of three: a chain
/// of products (forward kinematics, x = x * a) waits for one addition less per product.
template <class T>
constexpr Quaternion<T> hamilton(const Quaternion<T>& a, const Quaternion<T>& b) noexcept {
  return {(a.w * b.w - a.x * b.x) - (a.y * b.y + a.z * b.z), (a.w * b.x + a.x * b.w) + (a.y * b.z - a.z * b.y),
          (a.w * b.y - a.x * b.z) + (a.y * b.w + a.z * b.x), (a.w * b.z + a.x * b.y) - (a.y * b.x - a.z * b.w)};
}

#if DQKIT_VECTOR_EXTENSIONS
// The four-lane float product. Quaternions move into and out of vectors whole (memcpy: one
// 16-byte load or register move), and the left operand's components are broadcast from its
// vector by shuffles: GCC then keeps a loop-carried quaternion (x = x · a) in one vector register.
// (Built from or returned as four scalars, a chained dual quaternion became eight scalars, more
// than SSE2's sixteen registers hold with the products: half of them went through integer
// registers on every link.)
using float4 = float __attribute__((vector_size(16)));
static_assert(sizeof(Quaternion<float>) == sizeof(float4) && std::is_standard_layout_v<Quaternion<float>> &&
              std::is_trivially_copyable_v<Quaternion<float>>, "to_lanes and from_lanes copy w, x, y, z as four floats");
[[gnu::always_inline]] inline float4 to_lanes(const Quaternion<float>& q) noexcept {
  float4 v;
  std::memcpy(&v, &q, sizeof v);
  return v;
}
[[gnu::always_inline]] inline Quaternion<float> from_lanes(const float4& v) noexcept {
  Quaternion<float> q;
  std::memcpy(static_cast<void*>(&q), &v, sizeof v);  // trivially copyable (std::bit_cast made GCC keep chains in memory)
  return q;
}
/// The product's sum from a's components (each in every lane) and b's signed permutations, in that
/// order of operations; also used by the eight-lane dual quaternion product (dual_product_lanes).
template <class V>
[[gnu::always_inline]] inline V hamilton_sum(const V& aw, const V& ax, const V& ay, const V& az, const V& b, const V& b1,
                                             const V& b2, const V& b3) noexcept {
  return (aw * b + ax * b1) + (ay * b2 + az * b3);
}
/// detail::hamilton with the four components in the lanes of one vector: r = (a_w b
/// + a_x (−b_x, b_w, −b_z, b_y)) + (a_y (−b_y, b_z, b_w, −b_x) + a_z (−b_z, −b_y, b_x, b_w)), summed
/// in the scalar formula's pairs (x − y and x + (−y) round alike, as do (−x) + (−y) and −(x + y),
/// so each lane is the scalar formula's value, up to the sign of an exact zero). Written with the
/// compiler's generic vector extensions, not with intrinsics of one instruction set: the same
/// source serves every target a translation unit is compiled for (docs/design.md).
[[gnu::always_inline]] inline float4 hamilton_lanes(const float4& va, const float4& vb) noexcept {
  const float4 b1 = __builtin_shufflevector(vb, vb, 1, 0, 3, 2) * float4{-1, 1, -1, 1};
  const float4 b2 = __builtin_shufflevector(vb, vb, 2, 3, 0, 1) * float4{-1, 1, 1, -1};
  const float4 b3 = __builtin_shufflevector(vb, vb, 3, 2, 1, 0) * float4{-1, -1, 1, 1};
  return hamilton_sum(__builtin_shufflevector(va, va, 0, 0, 0, 0), __builtin_shufflevector(va, va, 1, 1, 1, 1),
                      __builtin_shufflevector(va, va, 2, 2, 2, 2), __builtin_shufflevector(va, va, 3, 3, 3, 3), vb, b1, b2, b3);
}
inline Quaternion<float> hamilton_lanes(const Quaternion<float>& a, const Quaternion<float>& b) noexcept {
  return from_lanes(hamilton_lanes(to_lanes(a), to_lanes(b)));
}

// Three-vectors in lanes 0-2 (x, y, z; lane 3 is carried along and dropped), for the rotation
// and the point transform: a cross product a × b is a_yzx b_zxy − a_zxy b_yzx, lane by lane the
// scalar cross's products and difference, so the results are the scalar formulas' bit for bit.
// Lane 3 repeats lane 0 in every operand (x, y, z, x), so it computes lane 0's operations on lane
// 0's values: it raises no floating-point exception that the scalar formula does not, and needs
// no masking (zeros there took four bitwise ands and two loads more per point transform).
static_assert(sizeof(Vec3<float>) == 3 * sizeof(float) && std::is_trivially_copyable_v<Vec3<float>>,
              "to_lanes and vec3_from_lanes copy x, y, z as three floats");
[[gnu::always_inline]] inline float4 to_lanes(const Vec3<float>& v) noexcept {
  // x and y as one 8-byte load, z as a 4-byte one (a 12-byte memcpy into a vector went through
  // the stack; built from three scalars, GCC spilled one).
  using float2 = float __attribute__((vector_size(8)));
  float2 xy;
  std::memcpy(&xy, &v, sizeof xy);
  return __builtin_shufflevector(xy, float2{v.z, 0.0f}, 0, 1, 2, 0);
}
[[gnu::always_inline]] inline Vec3<float> vec3_from_lanes(const float4& r) noexcept {
  Vec3<float> v;
  std::memcpy(static_cast<void*>(&v), &r, sizeof v);
  return v;
}
/// A quaternion's parts, from its lanes (w, x, y, z): the vector part as (x, y, z, x) and rotated,
/// (y, z, x, y) and (z, x, y, z), and the scalar part as (w, w, w, w).
struct QuaternionParts {
  float4 xyz, yzx, zxy, w;
};
[[gnu::always_inline]] inline QuaternionParts parts(const float4& q) noexcept {
  return {__builtin_shufflevector(q, q, 1, 2, 3, 1), __builtin_shufflevector(q, q, 2, 3, 1, 2),
          __builtin_shufflevector(q, q, 3, 1, 2, 3), __builtin_shufflevector(q, q, 0, 0, 0, 0)};
}
/// (y, z, x, y) and (z, x, y, z) of a vector (x, y, z, x): lane 3 stays lane 0's.
[[gnu::always_inline]] inline float4 yzx(const float4& v) noexcept { return __builtin_shufflevector(v, v, 1, 2, 0, 1); }
[[gnu::always_inline]] inline float4 zxy(const float4& v) noexcept { return __builtin_shufflevector(v, v, 2, 0, 1, 2); }
/// u × b for u a quaternion's vector part: u_yzx b_zxy − u_zxy b_yzx, lane by lane dq::cross.
[[gnu::always_inline]] inline float4 cross_lanes(const QuaternionParts& u, const float4& b) noexcept {
  return u.yzx * zxy(b) - u.zxy * yzx(b);
}
/// Quaternion::rotate, v + t w + u × t with t = 2 (u × v), in lanes.
inline Vec3<float> rotate_lanes(const Quaternion<float>& q, const Vec3<float>& v) noexcept {
  const QuaternionParts u = parts(to_lanes(q));
  const float4 vv = to_lanes(v);
  const float4 t = cross_lanes(u, vv) * float4{2, 2, 2, 2};
  return vec3_from_lanes((vv + t * u.w) + cross_lanes(u, t));
}
#endif
}  // namespace detail

namespace detail {
/// q · 2^e, exactly (barring overflow), for every scalar (derivative parts scaled alike); in
/// steps, since 2^e alone is not representable for the exponents that rescale a denormal.
template <class T>
Quaternion<T> scale_by_power_of_two(Quaternion<T> q, int e) {
  using R = real_t<T>;
  using std::ldexp;
  constexpr int step = std::numeric_limits<R>::max_exponent - 1;
  for (; e > step; e -= step) q = q * T(ldexp(R(1), step));
  for (; e < -step; e += step) q = q * T(ldexp(R(1), -step));
  return q * T(ldexp(R(1), e));
}
}  // namespace detail

template <class T>
constexpr T dot(const Quaternion<T>& a, const Quaternion<T>& b) noexcept {
  return a.w * b.w + a.x * b.x + a.y * b.y + a.z * b.z;
}

namespace detail {
/// exp of the pure quaternion (0, v): (cos|v|, v sinc|v|), smooth through v = 0 (cos and sinc as
/// series in |v|², so derivatives of every order are right there).
template <class T>
Quaternion<T> exp_pure(const Vec3<T>& v) {
  const T theta2 = dot(v, v);
  auto theta = [&] { return norm(v); };
  if constexpr (!has_derivatives_v<T>) {  // values: one angle, sin and cos of it (one sincos)
    if (theta2 < square_root_epsilon<real_t<T>>) return {T(1) - theta2 / T(2), v * (T(1) - theta2 / T(6))};
    const T a = angle_from_squared(theta2, theta);
    const SinCos<T> sc = sin_cos(a);  // exact at multiples of π/2, as from_axis_angle
    return {sc.cos, v * (sc.sin / a)};
  }
  return {cos_of_squared(theta2, theta), v * sinc_of_squared(theta2, theta)};
}
/// The vector part of log q for a unit q: v atan2(|v|, w)/|v|, smooth through v = 0 for w > 0;
/// a negative real q (a rotation by 2π) gives π along x, one of the valid choices.
template <class T>
Vec3<T> log_unit_vector(const Quaternion<T>& q) {
  const Vec3<T> v = q.vec();
  if (value_of(q.w) < 0 && !(norm(v) > T(0))) return {pi_v<T> + v.x, v.y, v.z};  // NaN stays NaN
  return v * angle_over_sine(dot(v, v), q.w, [&] { return norm(v); });
}
}  // namespace detail

/// exp(q) = e^w (cos|v|, v̂ sin|v|), for any quaternion; smooth through v = 0.
template <class T>
Quaternion<T> exp(const Quaternion<T>& q) {
  using std::exp;
  return detail::exp_pure(q.vec()) * exp(q.w);
}

/// log(q) = (ln|q|, v̂ atan2(|v|, w)), the principal logarithm; log(0) has w = −∞. For a
/// negative real q (a rotation by 2π) the vector part is π along x, one of the valid choices.
/// Smooth through v = 0 for w > 0 (values and derivatives).
template <class T>
Quaternion<T> log(const Quaternion<T>& q) {
  using std::log;
  const T n = q.norm();
  if (n == T(0)) return {log(n), T(0), T(0), T(0)};  // log 0 = −∞, with no direction
  return {log(n), detail::log_unit_vector(q / n)};
}

/// q^t = exp(t log q); for unit q this is the rotation by t times q's angle about q's axis.
template <class T>
Quaternion<T> pow(const Quaternion<T>& q, const std::type_identity_t<T>& t) {
  return exp(log(q) * t);
}

/// The rotation angle between a and b (unit), in [0, π]: the angle of a* b, with q ≡ −q.
template <class T>
T angular_distance(const Quaternion<T>& a, const Quaternion<T>& b) {
  using std::abs;
  using std::atan2;
  using std::sqrt;
  const Quaternion<T> d = a.conjugate() * b;
  return T(2) * atan2(sqrt(dot(d.vec(), d.vec())), abs(d.w));
}

namespace detail {
template <class X>
inline constexpr bool is_quaternion_v = false;
template <class T>
inline constexpr bool is_quaternion_v<Quaternion<T>> = true;
}  // namespace detail

/// Whether q and −q count as equal in a comparison.
enum class SignPolicy {
  exact,          ///< compare the four components as they are (algebraic equality)
  same_rotation,  ///< q and −q are the same rotation
};

/// Approximate comparison with an explicit tolerance on every component (max-norm).
template <class T>
bool approx_equal(const Quaternion<T>& a, const Quaternion<T>& b, const std::type_identity_t<T>& tolerance,
                  SignPolicy policy = SignPolicy::exact) {
  using std::abs;
  auto close = [&](const Quaternion<T>& u) {
    return abs(a.w - u.w) <= tolerance && abs(a.x - u.x) <= tolerance && abs(a.y - u.y) <= tolerance &&
           abs(a.z - u.z) <= tolerance;
  };
  return close(b) || (policy == SignPolicy::same_rotation && close(-b));
}

}  // namespace dq

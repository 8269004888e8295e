// Euler angles in all twelve sequences, intrinsic or extrinsic (always said explicitly).
//
// Intrinsic XYZ(a, b, c) is R = Rx(a) Ry(b) Rz(c): rotations about the moving axes, X first.
// Extrinsic XYZ(a, b, c) is R = Rz(c) Ry(b) Rx(a): rotations about the fixed axes, X first.
// Angles are radians and are listed in the order the sequence names their axes.
//
// Extraction works on the quaternion directly (no matrix, no asin): every sequence is reduced to
// two angle pairs θ± = (a ± c)/2 and the middle angle from atan2 of two hypotenuses, so that it is
// accurate everywhere, including near gimbal lock. At a singularity it returns a valid triple
// that reproduces the rotation with the *third* angle set to 0, and says it was singular.
#pragma once

#include <array>
#include <cmath>
#include <string_view>

#include "dq/core/dual_quaternion.hpp"
#include "dq/core/quaternion.hpp"

namespace dq {

enum class EulerOrder { XYZ, XZY, YXZ, YZX, ZXY, ZYX, XYX, XZX, YXY, YZY, ZXZ, ZYZ };
enum class EulerFrame { intrinsic, extrinsic };

inline constexpr std::array<EulerOrder, 12> all_euler_orders{
    EulerOrder::XYZ, EulerOrder::XZY, EulerOrder::YXZ, EulerOrder::YZX, EulerOrder::ZXY, EulerOrder::ZYX,
    EulerOrder::XYX, EulerOrder::XZX, EulerOrder::YXY, EulerOrder::YZY, EulerOrder::ZXZ, EulerOrder::ZYZ};

/// The three axis indices (0 = X, 1 = Y, 2 = Z) of a sequence, in the order named.
constexpr std::array<int, 3> euler_axes(EulerOrder order) noexcept {
  switch (order) {
    case EulerOrder::XYZ: return {0, 1, 2};
    case EulerOrder::XZY: return {0, 2, 1};
    case EulerOrder::YXZ: return {1, 0, 2};
    case EulerOrder::YZX: return {1, 2, 0};
    case EulerOrder::ZXY: return {2, 0, 1};
    case EulerOrder::ZYX: return {2, 1, 0};
    case EulerOrder::XYX: return {0, 1, 0};
    case EulerOrder::XZX: return {0, 2, 0};
    case EulerOrder::YXY: return {1, 0, 1};
    case EulerOrder::YZY: return {1, 2, 1};
    case EulerOrder::ZXZ: return {2, 0, 2};
    case EulerOrder::ZYZ: return {2, 1, 2};
  }
  return {0, 1, 2};
}

constexpr std::string_view to_string(EulerOrder order) noexcept {
  constexpr std::array<std::string_view, 12> names{"XYZ", "XZY", "YXZ", "YZX", "ZXY", "ZYX",
                                                   "XYX", "XZX", "YXY", "YZY", "ZXZ", "ZYZ"};
  return names[static_cast<std::size_t>(order)];
}

/// Tait–Bryan (three different axes) or proper Euler (first axis repeated).
constexpr bool is_proper_euler(EulerOrder order) noexcept {
  const auto ax = euler_axes(order);
  return ax[0] == ax[2];
}

template <class T>
struct EulerAngles {
  T a{}, b{}, c{};  ///< the first, middle and third angle, in the sequence's order (radians)
};

template <class T>
struct EulerExtraction {
  EulerAngles<T> angles;
  bool singular = false;  ///< gimbal lock: only a sum or difference of a and c was determined
};

namespace detail {
template <class T>
Quaternion<T> axis_rotation(int axis, const T& angle) {
  const auto sc = sin_cos(angle * T(0.5));
  Quaternion<T> q(sc.cos, T(0), T(0), T(0));
  (axis == 0 ? q.x : axis == 1 ? q.y : q.z) = sc.sin;
  return q;
}
template <class T>
const T& component(const Quaternion<T>& q, int axis) {
  return axis == 0 ? q.x : axis == 1 ? q.y : q.z;
}
/// Wraps an angle to (−π, π].
template <class T>
T wrap_angle(T a) {
  const real_t<T> two_pi = real_t<T>(2) * pi_v<T>;
  if (value_of(a) > pi_v<T> || value_of(a) <= -pi_v<T>) a = a - T(two_pi) * T(std::round(value_of(a) / two_pi));
  if (value_of(a) <= -pi_v<T>) a = a + T(two_pi);
  return a;
}
/// Sign of the permutation (i, j, k): +1 when e_i × e_j = e_k.
constexpr int permutation_sign(int i, int j) noexcept { return ((j - i + 3) % 3 == 1) ? 1 : -1; }
}  // namespace detail

/// The rotation of an Euler triple, as a unit quaternion (product of three axis rotations).
template <class T>
Quaternion<T> from_euler(EulerOrder order, EulerFrame frame, const T& a, const T& b, const T& c) {
  const auto ax = euler_axes(order);
  const Quaternion<T> qa = detail::axis_rotation(ax[0], a), qb = detail::axis_rotation(ax[1], b),
                      qc = detail::axis_rotation(ax[2], c);
  return frame == EulerFrame::intrinsic ? qa * qb * qc : qc * qb * qa;
}
template <class T>
Quaternion<T> from_euler(EulerOrder order, EulerFrame frame, const EulerAngles<T>& e) {
  return from_euler(order, frame, e.a, e.b, e.c);
}

/// The rotation matrix of an Euler triple as the product of three elementary rotation matrices,
/// the way the seeds build it (an independent path from from_euler, and the operation-count
/// baseline).
template <class T>
Mat3<T> euler_to_matrix(EulerOrder order, EulerFrame frame, const T& a, const T& b, const T& c) {
  using std::cos;
  using std::sin;
  auto elementary = [](int axis, const T& angle) {
    const T s = sin(angle), co = cos(angle);
    switch (axis) {
      case 0: return Mat3<T>::from_rows(T(1), T(0), T(0), T(0), co, -s, T(0), s, co);
      case 1: return Mat3<T>::from_rows(co, T(0), s, T(0), T(1), T(0), -s, T(0), co);
      default: return Mat3<T>::from_rows(co, -s, T(0), s, co, T(0), T(0), T(0), T(1));
    }
  };
  const auto ax = euler_axes(order);
  const Mat3<T> ma = elementary(ax[0], a), mb = elementary(ax[1], b), mc = elementary(ax[2], c);
  return frame == EulerFrame::intrinsic ? ma * mb * mc : mc * mb * ma;
}

namespace detail {
/// The two angle pairs of q for the intrinsic sequence (i, j, k): (A, B) carries θ+ = (a+c)/2,
/// (C, D) carries θ− = (a−c)/2, and the middle angle follows from their lengths.
template <class T>
struct EulerPairs {
  T A, B, C, D;
};
template <class T>
EulerPairs<T> euler_pairs(const Quaternion<T>& q, const std::array<int, 3>& ax, bool proper) {
  const int i = ax[0], j = ax[1];
  const int k = proper ? 3 - i - j : ax[2];
  const T eps = T(permutation_sign(i, j));
  const T qi = component(q, i), qj = component(q, j), qk = component(q, k);
  if (proper) return {q.w, qi, qj, eps * qk};
  // Tait–Bryan: with q_j' = ε q_j, q = (w, q_i, q_j', q_k) follows the proper pattern rotated
  // by 45° in the (w, q_j') and (q_i, q_k) planes.
  const T qj2 = eps * qj;
  return {q.w + qj2, qi + qk, q.w - qj2, qi - qk};
}
}  // namespace detail

/// Angular distance (radians, ≥ 0) of q's middle angle from the sequence's singularity
/// (b = ±π/2 for Tait–Bryan, b ∈ {0, π} for proper Euler). 0 means gimbal lock.
template <class T>
T euler_singularity_distance(const Quaternion<T>& q, EulerOrder order, EulerFrame frame) {
  using std::atan2;
  using std::hypot;
  std::array<int, 3> ax = euler_axes(order);
  if (frame == EulerFrame::extrinsic) std::swap(ax[0], ax[2]);  // see to_euler
  const auto p = detail::euler_pairs(q, ax, is_proper_euler(order));
  const T plus = hypot(p.A, p.B), minus = hypot(p.C, p.D);
  return T(2) * atan2(plus < minus ? plus : minus, plus < minus ? minus : plus);
}

/// Extracts Euler angles from a unit quaternion. Angles are in (−π, π], the middle one in
/// [−π/2, π/2] (Tait–Bryan) or [0, π] (proper Euler). At gimbal lock (the middle angle within a
/// few ulps of its singular value) the third angle is 0 and `singular` is true. Never NaN for
/// finite input.
template <class T>
EulerExtraction<T> to_euler(const Quaternion<T>& q, EulerOrder order, EulerFrame frame) {
  using std::atan2;
  using std::hypot;
  std::array<int, 3> ax = euler_axes(order);
  // Extrinsic (i, j, k)(a, b, c) is intrinsic (k, j, i)(c, b, a).
  const bool extrinsic = frame == EulerFrame::extrinsic;
  if (extrinsic) std::swap(ax[0], ax[2]);
  const bool proper = ax[0] == ax[2];
  const auto p = detail::euler_pairs(q, ax, proper);
  const T plus = hypot(p.A, p.B), minus = hypot(p.C, p.D);
  const T scale = plus + minus;
  T mid = T(2) * atan2(minus, plus);  // proper: b ∈ [0, π]
  if (!proper) mid = T(2) * atan2(plus, minus) - T(pi_v<T> / 2);  // Tait–Bryan: b ∈ [−π/2, π/2]
  if (!proper && detail::permutation_sign(ax[0], ax[1]) < 0) mid = -mid;

  const real_t<T> tol = real_t<T>(8) * epsilon<T>() * value_of(scale);
  const bool lost_minus = value_of(minus) <= tol;  // θ− undetermined
  const bool lost_plus = value_of(plus) <= tol;    // θ+ undetermined
  const T theta_plus = atan2(p.B, p.A), theta_minus = atan2(p.D, p.C);
  T first, third;  // of the intrinsic sequence: first = θ+ + θ−, third = θ+ − θ−
  EulerExtraction<T> out;
  if (lost_minus || lost_plus) {
    out.singular = true;
    // The listed third angle is set to 0: for an extrinsic order it is the intrinsic first.
    const T known = lost_minus ? theta_plus : theta_minus;  // the determined half-sum/difference
    const T sign = lost_minus ? T(1) : T(-1);                // third = θ+ − θ−
    if (extrinsic) {
      first = T(0);
      third = T(2) * known * sign;
    } else {
      third = T(0);
      first = T(2) * known;
    }
  } else {
    first = theta_plus + theta_minus;
    third = theta_plus - theta_minus;
  }
  first = detail::wrap_angle(first);
  third = detail::wrap_angle(third);
  out.angles = extrinsic ? EulerAngles<T>{third, mid, first} : EulerAngles<T>{first, mid, third};
  return out;
}
/// The Euler angles of a rigid transform's rotation (its real part); the translation is not used.
template <class T>
EulerExtraction<T> to_euler(const DualQuaternion<T>& q, EulerOrder order, EulerFrame frame) {
  return to_euler(q.real, order, frame);
}

}  // namespace dq

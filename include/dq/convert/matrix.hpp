// Conversions between dual quaternions and homogeneous matrices (4x4 and 3x4), and the repair of
// a drifted rotation matrix (orthonormalization by Gram–Schmidt or by the polar decomposition).
#pragma once

#include <cmath>

#include "dq/core/dual_quaternion.hpp"
#include "dq/core/matrix.hpp"

namespace dq {

/// The 3x4 matrix [R | t] of a unit dual quaternion.
template <class T>
constexpr Mat34<T> to_mat34(const DualQuaternion<T>& q) noexcept {
  const Mat3<T> r = q.real.to_matrix();
  const Vec3<T> t = q.translation();
  Mat34<T> m;
  for (int c = 0; c < 3; ++c)
    for (int row = 0; row < 3; ++row) m(row, c) = r(row, c);
  m(0, 3) = t.x;
  m(1, 3) = t.y;
  m(2, 3) = t.z;
  return m;
}

/// The 4x4 homogeneous matrix of a unit dual quaternion (last row 0 0 0 1).
template <class T>
constexpr Mat4<T> to_mat4(const DualQuaternion<T>& q) noexcept {
  const Mat34<T> a = to_mat34(q);
  Mat4<T> m;
  for (int c = 0; c < 4; ++c)
    for (int row = 0; row < 3; ++row) m(row, c) = a(row, c);
  m(3, 3) = T(1);
  return m;
}

template <class T, int R>
Mat3<T> rotation_block(const Mat<T, R, 4>& m) {
  Mat3<T> r;
  for (int c = 0; c < 3; ++c)
    for (int row = 0; row < 3; ++row) r(row, c) = m(row, c);
  return r;
}

/// The unit dual quaternion of a rigid 3x4 or 4x4 matrix (the bottom row of a 4x4 is not used,
/// but a NaN or ∞ there makes the result NaN). The rotation block should be orthonormal; see
/// orthonormalize_polar for drifted input.
template <class T, int R>
DualQuaternion<T> from_matrix(const Mat<T, R, 4>& m) {
  static_assert(R == 3 || R == 4);
  const DualQuaternion<T> q = DualQuaternion<T>::from_rotation_translation(Quaternion<T>::from_matrix(rotation_block(m)),
                                                                           {m(0, 3), m(1, 3), m(2, 3)});
  if constexpr (R == 4) {
    const T z = nan_if_not_finite(m(3, 0) + m(3, 1) + m(3, 2) + m(3, 3));
    return {q.real + Quaternion<T>(z, z, z, z), q.dual};
  }
  return q;
}

/// The unit quaternion of a 3x3 rotation matrix (Quaternion::from_matrix), named as the rigid
/// transforms' from_matrix.
template <class T>
Quaternion<T> from_matrix(const Mat3<T>& m) {
  return Quaternion<T>::from_matrix(m);
}

/// Gram–Schmidt on the columns (x kept, y made orthogonal to x, z = x × y): cheap, but biased
/// towards the first column.
template <class T>
Mat3<T> orthonormalize_gram_schmidt(const Mat3<T>& m) {
  const Vec3<T> c0{m(0, 0), m(1, 0), m(2, 0)}, c1{m(0, 1), m(1, 1), m(2, 1)};
  const Vec3<T> x = normalized(c0);
  const Vec3<T> y = normalized(c1 - x * dot(x, c1));
  const Vec3<T> z = cross(x, y);
  return Mat3<T>::from_rows(x.x, y.x, z.x, x.y, y.y, z.y, x.z, y.z, z.z);
}

/// The orthogonal factor of the polar decomposition, the rotation nearest to m in the Frobenius
/// norm, by the scaled Newton iteration X ← ½(X + X⁻ᵀ) (Higham). Converges quadratically; stops
/// when the update is below a few ulps or after `max_iterations`.
template <class T>
Mat3<T> orthonormalize_polar(const Mat3<T>& m, int max_iterations = 20) {
  using std::abs;
  Mat3<T> x = m;
  for (int it = 0; it < max_iterations; ++it) {
    // X⁻ᵀ = cofactor(X) / det(X).
    Mat3<T> cof;
    cof(0, 0) = x(1, 1) * x(2, 2) - x(1, 2) * x(2, 1);
    cof(0, 1) = x(1, 2) * x(2, 0) - x(1, 0) * x(2, 2);
    cof(0, 2) = x(1, 0) * x(2, 1) - x(1, 1) * x(2, 0);
    cof(1, 0) = x(0, 2) * x(2, 1) - x(0, 1) * x(2, 2);
    cof(1, 1) = x(0, 0) * x(2, 2) - x(0, 2) * x(2, 0);
    cof(1, 2) = x(0, 1) * x(2, 0) - x(0, 0) * x(2, 1);
    cof(2, 0) = x(0, 1) * x(1, 2) - x(0, 2) * x(1, 1);
    cof(2, 1) = x(0, 2) * x(1, 0) - x(0, 0) * x(1, 2);
    cof(2, 2) = x(0, 0) * x(1, 1) - x(0, 1) * x(1, 0);
    const T det = x(0, 0) * cof(0, 0) + x(0, 1) * cof(0, 1) + x(0, 2) * cof(0, 2);
    if (det == T(0)) break;  // singular: no unique nearest rotation
    const Mat3<T> next = (x + cof * (T(1) / det)) * T(0.5);
    T change = T(0);
    for (std::size_t i = 0; i < 9; ++i) change = abs(next.m[i] - x.m[i]) > change ? abs(next.m[i] - x.m[i]) : change;
    x = next;
    if (value_of(change) <= real_t<T>(4) * epsilon<T>()) break;
  }
  return x;
}

/// |RᵀR − I| in the max-norm: how far a rotation block is from orthonormal.
template <class T>
T orthonormality_error(const Mat3<T>& m) {
  using std::abs;
  const Mat3<T> e = transpose(m) * m - Mat3<T>::identity();
  T worst = T(0);
  for (const T& v : e.m) worst = abs(v) > worst ? abs(v) : worst;
  return worst;
}

}  // namespace dq

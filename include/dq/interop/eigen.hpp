// Conversions to and from Eigen (header-only; include only where Eigen is available).
//
// Eigen::Quaternion's constructor takes (w, x, y, z) but stores x, y, z, w; these functions go
// through the named accessors, so no ordering mistake is possible. Eigen also uses the Hamilton
// product and column vectors, so no other convention changes at this boundary.
#pragma once

#include <Eigen/Geometry>

#include "dq/convert/matrix.hpp"
#include "dq/core/dual_quaternion.hpp"

namespace dq::eigen {

template <class T>
Eigen::Quaternion<T> to_eigen(const Quaternion<T>& q) {
  return Eigen::Quaternion<T>(q.w, q.x, q.y, q.z);
}
template <class T>
Quaternion<T> from_eigen(const Eigen::Quaternion<T>& q) {
  return {q.w(), q.x(), q.y(), q.z()};
}
template <class T>
Eigen::Matrix<T, 3, 1> to_eigen(const Vec3<T>& v) {
  return {v.x, v.y, v.z};
}
template <class T>
Vec3<T> from_eigen(const Eigen::Matrix<T, 3, 1>& v) {
  return {v.x(), v.y(), v.z()};
}
template <class T>
Eigen::Matrix<T, 4, 4> to_eigen(const Mat4<T>& m) {
  return Eigen::Map<const Eigen::Matrix<T, 4, 4>>(m.data());  // both column-major
}
template <class T>
Mat4<T> from_eigen(const Eigen::Matrix<T, 4, 4>& e) {
  Mat4<T> m;
  Eigen::Map<Eigen::Matrix<T, 4, 4>>(m.data()) = e;
  return m;
}
/// A unit dual quaternion as an Eigen isometry (rotation, then translation).
template <class T>
Eigen::Transform<T, 3, Eigen::Isometry> to_isometry(const DualQuaternion<T>& q) {
  Eigen::Transform<T, 3, Eigen::Isometry> iso = Eigen::Transform<T, 3, Eigen::Isometry>::Identity();
  iso.linear() = to_eigen(q.real).toRotationMatrix();
  iso.translation() = to_eigen(q.translation());
  return iso;
}
/// The unit dual quaternion of an isometry (its linear part must be a rotation).
template <class T>
DualQuaternion<T> from_isometry(const Eigen::Transform<T, 3, Eigen::Isometry>& iso) {
  const Eigen::Quaternion<T> r(iso.linear());
  return DualQuaternion<T>::from_rotation_translation(from_eigen(r), from_eigen(Eigen::Matrix<T, 3, 1>(iso.translation())));
}

}  // namespace dq::eigen

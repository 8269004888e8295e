// The seeds' baseline interpolations, kept for comparison: linear interpolation of Euler angles
// and of axis-angle pairs. Neither is a geodesic; Euler interpolation near gimbal lock takes
// detours (examples/gimbal_lock.cpp shows it).
#pragma once

#include "dq/convert/euler.hpp"

namespace dq {

/// Each of the three angles interpolated linearly (no wrapping: the angles as given).
template <class T>
Quaternion<T> euler_interpolate(EulerOrder order, EulerFrame frame, const EulerAngles<T>& a, const EulerAngles<T>& b,
                                const std::type_identity_t<T>& t) {
  auto lerp = [&](const T& x, const T& y) { return x + (y - x) * t; };
  return from_euler(order, frame, lerp(a.a, b.a), lerp(a.b, b.b), lerp(a.c, b.c));
}

/// The axis (normalized after a linear blend) and the angle interpolated separately.
template <class T>
Quaternion<T> axis_angle_interpolate(const AxisAngle<T>& a, const AxisAngle<T>& b, const std::type_identity_t<T>& t) {
  const Vec3<T> axis = a.axis * (T(1) - t) + b.axis * t;
  return Quaternion<T>::from_axis_angle(axis, a.angle + (b.angle - a.angle) * t);
}

}  // namespace dq

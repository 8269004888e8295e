// The VRML97 / X3D Transform node (rotation "x y z angle", translation, center) and dual
// quaternions, in both directions, for every input.
//
// A Transform maps p to T·C·R·C⁻¹·p (scale and scaleOrientation are not rigid and are not
// represented). The VRML tutorial's toDualQuaternion/fromDualQuaternion treat axes shorter than
// 0.01 and rotations under about 1.15° as none, use acos near 0 and π, and lose the translation
// of a dual quaternion with a small real part; dqkit does none of these (docs/seed-errata.md).
#pragma once

#include <cmath>

#include "dq/core/dual_quaternion.hpp"

namespace dq {

template <class T>
struct VrmlTransform {
  Vec3<T> axis{T(0), T(0), T(1)};  ///< rotation axis (any length > 0; VRML's default 0 0 1)
  T angle{};                       ///< rotation angle, radians
  Vec3<T> translation{};
  Vec3<T> center{};                ///< the rotation's centre
};

/// The unit dual quaternion of a Transform. A zero (or non-finite-length) axis has no direction:
/// the rotation is then the identity, whatever the angle (documented choice).
template <class T>
DualQuaternion<T> from_vrml(const VrmlTransform<T>& v) {
  const Quaternion<T> r = Quaternion<T>::from_axis_angle(v.axis, v.angle);
  // T·C·R·C⁻¹ = rotate by r, then translate by translation + center − R center.
  return DualQuaternion<T>::from_rotation_translation(r, v.translation + v.center - r.rotate(v.center));
}

/// The Transform of a unit dual quaternion, for a given center (default the origin). The
/// rotation is the canonical axis-angle (angle in [0, π]); the identity gives VRML's default
/// "0 0 1 0". The input is normalized first, so a drifted or scaled dual quaternion is accepted;
/// a zero real part has no rotation and gives the identity.
template <class T>
VrmlTransform<T> to_vrml(const DualQuaternion<T>& q, const Vec3<T>& center = {}) {
  const DualQuaternion<T> u = q.normalized();
  VrmlTransform<T> v;
  const AxisAngle<T> aa = u.real.to_axis_angle();
  if (aa.angle != T(0)) {
    v.axis = aa.axis;
    v.angle = aa.angle;
  }
  v.center = center;
  v.translation = u.translation() - center + u.real.rotate(center);
  return v;
}

}  // namespace dq

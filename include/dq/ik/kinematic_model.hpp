// A kinematic model over a runtime Skeleton: the degrees of freedom of each joint, their limits,
// and forward kinematics from a parameter vector q, generic over the scalar (double, float,
// Dual<T> for exact Jacobians, HyperDual<T> for second derivatives) and over the transform
// (dual quaternions, or 4x4 matrices for the seeds' comparison).
//
// Joint j's local transform is rest_j · D_1(q) · D_2(q) · … with its DOFs in order:
//   revolute   rotation by q_i about a unit axis of the joint's frame,
//   prismatic  translation by q_i along a unit axis,
//   ball       rotation by the rotation vector (q_i, q_i+1, q_i+2) (the exponential map; three
//              parameters, smooth through the identity),
//   free       translation (q_i, q_i+1, q_i+2), then a ball (q_i+3 … q_i+5): a root that moves.
// Each parameter has limits [lower, upper] (a box; ±∞ for none).
#pragma once

#include <cmath>
#include <cstddef>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "dq/anim/skeleton.hpp"
#include "dq/core/matrix.hpp"
#include "dq/util/assert.hpp"
#include "dq/util/expected.hpp"

namespace dq {

enum class DofType { revolute, prismatic, ball, free };

/// Number of parameters of a DOF of this type.
constexpr std::size_t parameter_count(DofType t) noexcept {
  return t == DofType::ball ? 3 : t == DofType::free ? 6 : 1;
}

struct Dof {
  int joint = 0;                    ///< runtime joint index
  DofType type = DofType::revolute;
  Vec3<double> axis{1, 0, 0};       ///< axis in the joint's frame (revolute, prismatic): any non-zero length, normalized by build
  std::string name;
};

struct ParameterLimits {
  double lower = -std::numeric_limits<double>::infinity();
  double upper = std::numeric_limits<double>::infinity();
};

/// The DOFs of a skeleton. Built with `KinematicModel::build` (validated), then immutable.
class KinematicModel {
 public:
  /// Validates and builds: every DOF names an existing joint, DOFs come in joint order, axes are
  /// unit, limits are ordered (one ParameterLimits per parameter; empty = unlimited).
  static Expected<KinematicModel> build(Skeleton skeleton, std::vector<Dof> dofs, std::vector<ParameterLimits> limits = {});

  /// Every joint with channels a ball joint (3 parameters), the roots free (6): the model IK
  /// uses for captured or imported skeletons. End Sites have no DOF.
  static KinematicModel ball_joints(const Skeleton& skeleton);
  /// The 16-link, 36-DOF biped of the Kenwright paper (Biped), with its limits.
  static const KinematicModel& biped();
  /// A 7-DOF arm (three shoulder axes, elbow, three wrist axes; link lengths 0.34, 0.40, 0.40,
  /// 0.126 m, limits of a KUKA LBR iiwa 7): the IK benchmark's arm.
  static const KinematicModel& arm7();

  const Skeleton& skeleton() const noexcept { return skeleton_; }
  std::span<const Dof> dofs() const noexcept { return dofs_; }
  std::size_t parameters() const noexcept { return limits_.size(); }
  std::span<const ParameterLimits> limits() const noexcept { return limits_; }
  /// First parameter of DOF d; its parameters are [offset(d), offset(d) + parameter_count).
  std::size_t offset(std::size_t d) const noexcept { return offsets_[d]; }
  /// DOFs of joint j: [joint_dofs_begin(j), joint_dofs_begin(j + 1)).
  std::size_t joint_dofs_begin(std::size_t j) const noexcept { return joint_begin_[j]; }
  /// Index of the parameter with this DOF name (first parameter of a ball/free DOF), or −1.
  int find_parameter(std::string_view name) const noexcept;

  /// q clamped to the limits.
  void clamp(std::span<double> q) const;
  /// Whether q is within the limits (to `slack`).
  bool within_limits(std::span<const double> q, double slack = 0) const;

 private:
  Skeleton skeleton_;
  std::vector<Dof> dofs_;
  std::vector<std::size_t> offsets_;
  std::vector<std::size_t> joint_begin_;
  std::vector<ParameterLimits> limits_;
};

// ---- transforms: dual quaternions or matrices, one interface --------------------------------------

/// The operations forward kinematics needs from a transform type X over scalar T.
template <class X>
struct TransformOps;

template <class T>
struct TransformOps<DualQuaternion<T>> {
  using X = DualQuaternion<T>;
  template <class U>
  using rebind = DualQuaternion<U>;
  static X rotation(const Quaternion<T>& r) { return X::from_rotation(r); }
  static X translation(const Vec3<T>& t) { return X::from_translation(t); }
  static X from(const DualQuaternion<double>& q) {
    return {Quaternion<T>(T(q.real.w), T(q.real.x), T(q.real.y), T(q.real.z)),
            Quaternion<T>(T(q.dual.w), T(q.dual.x), T(q.dual.y), T(q.dual.z))};
  }
  /// x · rotation(r), without the products by the rotation's zero dual part.
  static X rotated(const X& x, const Quaternion<T>& r) { return {x.real * r, x.dual * r}; }
  static Vec3<T> rotate(const X& x, const Vec3<T>& v) { return x.real.rotate(v); }
  static Vec3<T> origin(const X& x) { return x.translation(); }
  static Vec3<T> apply(const X& x, const Vec3<T>& p) { return x.transform_point(p); }
  static Quaternion<T> rotation_part(const X& x) { return x.real; }
};

template <class T>
struct TransformOps<Mat4<T>> {
  using X = Mat4<T>;
  template <class U>
  using rebind = Mat4<U>;
  static X rotation(const Quaternion<T>& r) { return embed(r.to_matrix(), {}); }
  static X translation(const Vec3<T>& t) { return embed(Mat3<T>::identity(), t); }
  static X from(const DualQuaternion<double>& q) {
    const Quaternion<T> r(T(q.real.w), T(q.real.x), T(q.real.y), T(q.real.z));
    const Vec3<double> t = q.translation();
    return embed(r.to_matrix(), {T(t.x), T(t.y), T(t.z)});
  }
  /// x · rotation(r): the 3x3 block times r's matrix; the translation column is unchanged.
  static X rotated(const X& x, const Quaternion<T>& r) {
    const Mat3<T> m = r.to_matrix();
    X out = x;
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) out(i, k) = x(i, 0) * m(0, k) + x(i, 1) * m(1, k) + x(i, 2) * m(2, k);
    return out;
  }
  static Vec3<T> rotate(const X& x, const Vec3<T>& v) {
    return {x(0, 0) * v.x + x(0, 1) * v.y + x(0, 2) * v.z, x(1, 0) * v.x + x(1, 1) * v.y + x(1, 2) * v.z,
            x(2, 0) * v.x + x(2, 1) * v.y + x(2, 2) * v.z};
  }
  static Vec3<T> origin(const X& x) { return {x(0, 3), x(1, 3), x(2, 3)}; }
  static Vec3<T> apply(const X& x, const Vec3<T>& p) { return rotate(x, p) + origin(x); }
  static Quaternion<T> rotation_part(const X& x) {
    Mat3<T> r;
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) r(i, k) = x(i, k);
    return Quaternion<T>::from_matrix(r);
  }

 private:
  static X embed(const Mat3<T>& r, const Vec3<T>& t) {
    X m = X::identity();
    for (int i = 0; i < 3; ++i) {
      for (int k = 0; k < 3; ++k) m(i, k) = r(i, k);
      m(i, 3) = t[i];
    }
    return m;
  }
};

namespace detail {
template <class T>
Vec3<T> axis_as(const Vec3<double>& a) {
  return {T(a.x), T(a.y), T(a.z)};
}
}  // namespace detail

/// The rotation by `angle` about the unit `axis`: (cos ½angle, axis sin ½angle), one sine and
/// cosine (the exponential map of angle·axis, written for a unit axis). Plain sin and cos (one
/// sincos call): detail::sin_cos's exact quadrants cost a division and a rounding per joint, and a
/// joint angle is an arbitrary value, not a multiple of π/2 that must come out exact.
template <class T>
Quaternion<T> revolute_rotation(const Vec3<double>& axis, const T& angle) {
  using std::cos;
  using std::sin;
  const T half = angle * T(0.5);
  return {cos(half), detail::axis_as<T>(axis) * sin(half)};
}

/// x · D, where D is DOF d's transform for its parameters p (p[0], or p[0..2] for a ball, p[0..5]
/// for free): a rotation is applied without the products by its zero dual part.
template <class X, class T>
X then_dof(const X& x, const Dof& d, const T* p) {
  using Ops = TransformOps<X>;
  switch (d.type) {
    case DofType::revolute: return Ops::rotated(x, revolute_rotation(d.axis, p[0]));
    case DofType::prismatic: return x * Ops::translation(detail::axis_as<T>(d.axis) * p[0]);
    case DofType::ball: return Ops::rotated(x, Quaternion<T>::from_rotation_vector({p[0], p[1], p[2]}));
    case DofType::free:
      return Ops::rotated(x * Ops::translation({p[0], p[1], p[2]}), Quaternion<T>::from_rotation_vector({p[3], p[4], p[5]}));
  }
  return x;
}

/// Local transforms of every joint for parameters q. Preconditions: q has model.parameters()
/// values, local one entry per joint.
template <class X, class T>
void local_transforms(const KinematicModel& model, std::span<const T> q, std::span<X> local) {
  using Ops = TransformOps<X>;
  const std::size_t joints = model.skeleton().size();
  DQ_PRECONDITION(q.size() == model.parameters() && local.size() == joints,
                  "local_transforms needs model.parameters() values and one output per joint");
  const auto dofs = model.dofs();
  for (std::size_t j = 0; j < joints; ++j) {
    X x = Ops::from(model.skeleton().rest_pose()[j]);
    for (std::size_t d = model.joint_dofs_begin(j); d < model.joint_dofs_begin(j + 1); ++d)
      x = then_dof(x, dofs[d], q.data() + model.offset(d));
    local[j] = x;
  }
}

/// Model-space transforms of every joint for parameters q (forward kinematics of the model).
/// Preconditions: as local_transforms (checked here too: a handler that returns leaves world as it was).
template <class X, class T>
void model_transforms(const KinematicModel& model, std::span<const T> q, std::span<X> world) {
  DQ_PRECONDITION(q.size() == model.parameters() && world.size() == model.skeleton().size(),
                  "model_transforms needs model.parameters() values and one output per joint");
  local_transforms<X, T>(model, q, world);
  const auto parents = model.skeleton().parents();
  for (std::size_t j = 0; j < world.size(); ++j)
    if (parents[j] >= 0) world[j] = world[static_cast<std::size_t>(parents[j])] * world[j];
}

}  // namespace dq

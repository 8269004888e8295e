// The 16-link, 36-degree-of-freedom biped of the Kenwright paper (§10.2) as a built-in rig.
//
// The paper gives the link and DOF counts and a figure, not the layout; dqkit's layout (docs/
// hierarchies.md) is a standard anthropometric one that matches both counts:
//
//   link        parent     DOF  joint type
//   pelvis      —           6   free (3 translation + 3 rotation), the root
//   abdomen     pelvis      3   ball (lumbar)
//   chest       abdomen     2   flexion/extension, lateral bend (thoracic)
//   head        chest       3   ball (neck)
//   upper_arm   chest       3   ball (shoulder), left and right
//   forearm     upper_arm   1   hinge (elbow)
//   hand        forearm     1   hinge (wrist flexion)
//   thigh       pelvis      3   ball (hip)
//   shin        thigh       1   hinge (knee)
//   foot        shin        2   ankle flexion + inversion
//   total: 4 + 2 × 3 + 2 × 3 = 16 links; 6 + 3 + 2 + 3 + 2 × (3 + 1 + 1) + 2 × (3 + 1 + 2) = 36 DOF
//
// Rotational DOFs are angles about the joint's local axes (x: flexion, y: twist, z: abduction),
// applied in the order listed (intrinsic); each has limits in radians. Dimensions are metres for
// an adult of 1.75 m.
#pragma once

#include <array>
#include <span>
#include <string_view>

#include "dq/anim/skeleton.hpp"
#include "dq/util/assert.hpp"

namespace dq {

enum class DofKind { translation, rotation };

struct BipedDof {
  int joint;          ///< runtime joint index in the biped skeleton
  DofKind kind;
  int axis;           ///< 0 = x, 1 = y, 2 = z (local axes of the joint)
  double lower, upper;  ///< limits (radians for rotations, metres for translations)
  std::string_view name;
};

class Biped {
 public:
  static constexpr std::size_t links = 16;
  static constexpr std::size_t dofs = 36;

  /// Builds the rig (its skeleton and DOF table).
  static const Biped& instance();

  const Skeleton& skeleton() const noexcept { return skeleton_; }
  std::span<const BipedDof> dof_table() const noexcept { return dofs_; }

  /// Local transforms of all 16 joints for a DOF vector q (36 values): the rest offset, then the
  /// joint's translations and rotations. Values outside the limits are used as given; use clamp()
  /// first to respect the limits. Generic over the scalar: with Dual<double> values it gives the
  /// exact derivatives of every joint's transform. Preconditions: 36 values, 16 outputs.
  template <class T>
  void pose(std::span<const T> q, std::span<DualQuaternion<T>> local) const {
    DQ_PRECONDITION(q.size() == dofs && local.size() == links, "Biped::pose needs 36 values and 16 outputs");
    std::array<Vec3<T>, links> translation{};
    std::array<Quaternion<T>, links> rotation{};
    for (std::size_t j = 0; j < links; ++j) {
      const Vec3<double> t = skeleton_.rest_pose()[j].translation();
      translation[j] = {T(t.x), T(t.y), T(t.z)};
    }
    for (std::size_t i = 0; i < dofs; ++i) {
      const BipedDof& d = dofs_[i];
      const auto j = static_cast<std::size_t>(d.joint);
      if (d.kind == DofKind::translation) {
        translation[j][d.axis] += q[i];
      } else {
        Vec3<T> axis{T(0), T(0), T(0)};
        axis[d.axis] = T(1);
        rotation[j] = rotation[j] * Quaternion<T>::from_rotation_vector(axis * q[i]);
      }
    }
    for (std::size_t j = 0; j < links; ++j) local[j] = DualQuaternion<T>::from_rotation_translation(rotation[j], translation[j]);
  }
  /// The same for double, callable with containers.
  void pose(std::span<const double> q, std::span<DualQuaternion<double>> local) const { pose<double>(q, local); }
  /// q with every value clamped to its limits.
  std::array<double, dofs> clamp(std::span<const double> q) const;

 private:
  Biped();
  Skeleton skeleton_;
  std::array<BipedDof, dofs> dofs_{};
};

}  // namespace dq

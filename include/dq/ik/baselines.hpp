// The IK methods animation runtimes use, as baselines beside the damped least squares solver:
// cyclic coordinate descent (CCD), FABRIK, and the analytic two-bone solver with a pole vector.
// (Kenwright's projected Gauss–Seidel is IkMethod::gauss_seidel of the solver.)
#pragma once

#include <span>

#include "dq/ik/kinematic_model.hpp"
#include "dq/ik/solver.hpp"

namespace dq {

/// The result of the analytic two-bone solver: world-space rotations that move the chain
/// root → mid → end so that end reaches the target (or points at it from full reach).
struct TwoBoneSolution {
  Quaternion<double> root_rotation;  ///< applied to the root joint's world rotation (about the root)
  Quaternion<double> mid_rotation;   ///< then applied to the mid joint's world rotation (about the mid joint)
  Vec3<double> mid;                  ///< the new mid position
  Vec3<double> end;                  ///< the new end position
  bool reachable = true;             ///< false: the target is beyond (or within) reach; end is as close as it gets
};

/// Two bones (lengths |mid − root| and |end − mid| kept) with the mid joint in the plane of root,
/// target and `pole` (the side the knee or elbow points to). Closed form: the mid angle from the
/// law of cosines. A pole on the root–target line is replaced by the current mid position.
TwoBoneSolution two_bone_ik(const Vec3<double>& root, const Vec3<double>& mid, const Vec3<double>& end,
                            const Vec3<double>& target, const Vec3<double>& pole);

struct BaselineOptions {
  int max_iterations = 200;
  double tolerance = 1e-10;  ///< position error (model units)
};

/// Cyclic coordinate descent for a position task: every DOF of the effector's chain, from the
/// effector up, turned (revolute, ball) or slid (prismatic) to bring the effector point closest to
/// the target, clamped to its limits; free DOFs are left as they are. Updates q in place.
IkResult ccd(const KinematicModel& model, const IkTask& task, std::span<double> q, const BaselineOptions& options = {});

/// FABRIK (Aristidou and Lasenby) for a position task on a chain of ball joints (a model from
/// KinematicModel::ball_joints): forward and backward passes over the joint positions, then each
/// ball joint rotated onto its new bone direction (limits applied by clamping). Updates q in place.
IkResult fabrik(const KinematicModel& model, const IkTask& task, std::span<double> q, const BaselineOptions& options = {});

}  // namespace dq

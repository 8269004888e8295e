#include "dq/ik/kinematic_model.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "dq/anim/biped.hpp"

namespace dq {

Expected<KinematicModel> KinematicModel::build(Skeleton skeleton, std::vector<Dof> dofs, std::vector<ParameterLimits> limits) {
  KinematicModel m;
  const std::size_t joints = skeleton.size();
  std::size_t parameters = 0;
  int previous_joint = 0;
  for (std::size_t d = 0; d < dofs.size(); ++d) {
    Dof& dof = dofs[d];
    const std::string where = "DOF " + std::to_string(d) + (dof.name.empty() ? "" : " (" + dof.name + ")");
    if (dof.joint < 0 || static_cast<std::size_t>(dof.joint) >= joints) return Error{where + ": joint index out of range"};
    if (dof.joint < previous_joint) return Error{where + ": DOFs must come in joint order"};
    if (dof.type == DofType::revolute || dof.type == DofType::prismatic) {
      const double n = norm(dof.axis);
      if (!(n > 0) || !std::isfinite(n)) return Error{where + ": the axis has no direction (zero or not finite)"};
      dof.axis = dof.axis / n;  // unit to rounding: revolute_rotation relies on it
    }
    previous_joint = dof.joint;
    m.offsets_.push_back(parameters);
    parameters += parameter_count(dof.type);
  }
  if (limits.empty()) limits.resize(parameters);
  if (limits.size() != parameters)
    return Error{"expected " + std::to_string(parameters) + " parameter limits, got " + std::to_string(limits.size())};
  for (std::size_t i = 0; i < parameters; ++i)
    if (!(limits[i].lower <= limits[i].upper)) return Error{"parameter " + std::to_string(i) + ": lower limit above upper (or NaN)"};
  m.joint_begin_.assign(joints + 1, dofs.size());
  for (std::size_t d = dofs.size(); d-- > 0;) m.joint_begin_[static_cast<std::size_t>(dofs[d].joint)] = d;
  for (std::size_t j = joints; j-- > 0;) m.joint_begin_[j] = std::min(m.joint_begin_[j], m.joint_begin_[j + 1]);
  m.skeleton_ = std::move(skeleton);
  m.dofs_ = std::move(dofs);
  m.limits_ = std::move(limits);
  return m;
}

KinematicModel KinematicModel::ball_joints(const Skeleton& skeleton) {
  std::vector<Dof> dofs;
  for (std::size_t j = 0; j < skeleton.size(); ++j) {
    if (skeleton.is_end_site(j)) continue;
    const bool root = skeleton.parents()[j] < 0;
    dofs.push_back({static_cast<int>(j), root ? DofType::free : DofType::ball, {1, 0, 0}, std::string(skeleton.names()[j])});
  }
  Expected<KinematicModel> m = build(skeleton, std::move(dofs));
  if (!m) throw std::logic_error("ball-joint model: " + m.error().message);  // built from a valid skeleton: a bug
  return std::move(*m);
}

const KinematicModel& KinematicModel::biped() {
  static const KinematicModel model = [] {
    const Biped& b = Biped::instance();
    std::vector<Dof> dofs;
    std::vector<ParameterLimits> limits;
    for (const BipedDof& d : b.dof_table()) {
      Vec3<double> axis{};
      axis[d.axis] = 1;
      dofs.push_back({d.joint, d.kind == DofKind::translation ? DofType::prismatic : DofType::revolute, axis, std::string(d.name)});
      limits.push_back({d.lower, d.upper});
    }
    Expected<KinematicModel> m = build(b.skeleton(), std::move(dofs), std::move(limits));
    if (!m) throw std::logic_error("biped model: " + m.error().message);
    return std::move(*m);
  }();
  return model;
}

const KinematicModel& KinematicModel::arm7() {
  static const KinematicModel model = [] {
    constexpr double deg = std::numbers::pi / 180;
    // Joints 1–7 alternate z and y axes (z up); links: base 0.34, upper arm 0.40, forearm 0.40,
    // flange 0.126 m. Limits of the LBR iiwa 7: ±170, ±120, ±170, ±120, ±170, ±120, ±175 degrees.
    RawSkeleton raw;
    const double offsets[] = {0.0, 0.34, 0.0, 0.40, 0.0, 0.40, 0.0, 0.126};
    int parent = -1;
    for (int j = 0; j < 8; ++j)
      parent = raw.add(j < 7 ? "a" + std::to_string(j + 1) : "flange", parent,
                       DualQuaternion<double>::from_translation({0, 0, offsets[j]}), j == 7);
    Expected<Skeleton> s = build_skeleton(raw);
    if (!s) throw std::logic_error("arm7 skeleton: " + s.error().message);
    std::vector<Dof> dofs;
    std::vector<ParameterLimits> limits;
    const double range[] = {170, 120, 170, 120, 170, 120, 175};
    for (int j = 0; j < 7; ++j) {
      dofs.push_back({j, DofType::revolute, j % 2 == 0 ? Vec3<double>{0, 0, 1} : Vec3<double>{0, 1, 0}, "a" + std::to_string(j + 1)});
      limits.push_back({-range[j] * deg, range[j] * deg});
    }
    Expected<KinematicModel> m = build(std::move(*s), std::move(dofs), std::move(limits));
    if (!m) throw std::logic_error("arm7 model: " + m.error().message);
    return std::move(*m);
  }();
  return model;
}

int KinematicModel::find_parameter(std::string_view name) const noexcept {
  for (std::size_t d = 0; d < dofs_.size(); ++d)
    if (dofs_[d].name == name) return static_cast<int>(offsets_[d]);
  return -1;
}

void KinematicModel::clamp(std::span<double> q) const {
  DQ_PRECONDITION(q.size() == limits_.size(), "KinematicModel::clamp needs one value per parameter");
  for (std::size_t i = 0; i < q.size(); ++i) q[i] = std::clamp(q[i], limits_[i].lower, limits_[i].upper);
}

bool KinematicModel::within_limits(std::span<const double> q, double slack) const {
  DQ_PRECONDITION(q.size() == limits_.size(), "KinematicModel::within_limits needs one value per parameter", false);
  for (std::size_t i = 0; i < q.size(); ++i)
    if (!(q[i] >= limits_[i].lower - slack && q[i] <= limits_[i].upper + slack)) return false;
  return true;
}

}  // namespace dq

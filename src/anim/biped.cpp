#include "dq/anim/biped.hpp"

#include <algorithm>
#include <stdexcept>

namespace dq {

namespace {
constexpr double kDeg = std::numbers::pi / 180;

struct LinkSpec {
  std::string_view name;
  std::string_view parent;
  Vec3<double> offset;  // from the parent joint, metres, in the rest pose (y up, z forward)
};

constexpr std::array<LinkSpec, Biped::links> kLinks{{
    {"pelvis", "", {0, 1.00, 0}},
    {"abdomen", "pelvis", {0, 0.10, 0}},
    {"chest", "abdomen", {0, 0.20, 0}},
    {"head", "chest", {0, 0.25, 0}},
    {"left_upper_arm", "chest", {0.18, 0.20, 0}},
    {"left_forearm", "left_upper_arm", {0.30, 0, 0}},
    {"left_hand", "left_forearm", {0.26, 0, 0}},
    {"right_upper_arm", "chest", {-0.18, 0.20, 0}},
    {"right_forearm", "right_upper_arm", {-0.30, 0, 0}},
    {"right_hand", "right_forearm", {-0.26, 0, 0}},
    {"left_thigh", "pelvis", {0.10, -0.05, 0}},
    {"left_shin", "left_thigh", {0, -0.45, 0}},
    {"left_foot", "left_shin", {0, -0.43, 0}},
    {"right_thigh", "pelvis", {-0.10, -0.05, 0}},
    {"right_shin", "right_thigh", {0, -0.45, 0}},
    {"right_foot", "right_shin", {0, -0.43, 0}},
}};

struct DofSpec {
  std::string_view joint;
  DofKind kind;
  int axis;
  double lower, upper;
  std::string_view name;
};

// Limits: ranges of motion of an adult (degrees, from standard anthropometric tables), and a
// pelvis free to move ±2 m horizontally and 0.5 m vertically.
constexpr std::array<DofSpec, Biped::dofs> kDofs{{
    {"pelvis", DofKind::translation, 0, -2.0, 2.0, "pelvis_tx"},
    {"pelvis", DofKind::translation, 1, -0.5, 0.5, "pelvis_ty"},
    {"pelvis", DofKind::translation, 2, -2.0, 2.0, "pelvis_tz"},
    {"pelvis", DofKind::rotation, 1, -180 * kDeg, 180 * kDeg, "pelvis_yaw"},
    {"pelvis", DofKind::rotation, 0, -90 * kDeg, 90 * kDeg, "pelvis_pitch"},
    {"pelvis", DofKind::rotation, 2, -90 * kDeg, 90 * kDeg, "pelvis_roll"},
    {"abdomen", DofKind::rotation, 0, -30 * kDeg, 45 * kDeg, "lumbar_flexion"},
    {"abdomen", DofKind::rotation, 1, -30 * kDeg, 30 * kDeg, "lumbar_twist"},
    {"abdomen", DofKind::rotation, 2, -25 * kDeg, 25 * kDeg, "lumbar_bend"},
    {"chest", DofKind::rotation, 0, -20 * kDeg, 30 * kDeg, "thoracic_flexion"},
    {"chest", DofKind::rotation, 2, -20 * kDeg, 20 * kDeg, "thoracic_bend"},
    {"head", DofKind::rotation, 0, -50 * kDeg, 60 * kDeg, "neck_flexion"},
    {"head", DofKind::rotation, 1, -80 * kDeg, 80 * kDeg, "neck_twist"},
    {"head", DofKind::rotation, 2, -45 * kDeg, 45 * kDeg, "neck_bend"},
    {"left_upper_arm", DofKind::rotation, 0, -60 * kDeg, 180 * kDeg, "left_shoulder_flexion"},
    {"left_upper_arm", DofKind::rotation, 1, -90 * kDeg, 90 * kDeg, "left_shoulder_twist"},
    {"left_upper_arm", DofKind::rotation, 2, -90 * kDeg, 90 * kDeg, "left_shoulder_abduction"},
    {"left_forearm", DofKind::rotation, 1, 0, 150 * kDeg, "left_elbow"},
    {"left_hand", DofKind::rotation, 2, -70 * kDeg, 80 * kDeg, "left_wrist"},
    {"right_upper_arm", DofKind::rotation, 0, -60 * kDeg, 180 * kDeg, "right_shoulder_flexion"},
    {"right_upper_arm", DofKind::rotation, 1, -90 * kDeg, 90 * kDeg, "right_shoulder_twist"},
    {"right_upper_arm", DofKind::rotation, 2, -90 * kDeg, 90 * kDeg, "right_shoulder_abduction"},
    {"right_forearm", DofKind::rotation, 1, -150 * kDeg, 0, "right_elbow"},
    {"right_hand", DofKind::rotation, 2, -80 * kDeg, 70 * kDeg, "right_wrist"},
    {"left_thigh", DofKind::rotation, 0, -120 * kDeg, 30 * kDeg, "left_hip_flexion"},
    {"left_thigh", DofKind::rotation, 1, -45 * kDeg, 45 * kDeg, "left_hip_twist"},
    {"left_thigh", DofKind::rotation, 2, -30 * kDeg, 45 * kDeg, "left_hip_abduction"},
    {"left_shin", DofKind::rotation, 0, 0, 150 * kDeg, "left_knee"},
    {"left_foot", DofKind::rotation, 0, -50 * kDeg, 20 * kDeg, "left_ankle_flexion"},
    {"left_foot", DofKind::rotation, 2, -35 * kDeg, 20 * kDeg, "left_ankle_inversion"},
    {"right_thigh", DofKind::rotation, 0, -120 * kDeg, 30 * kDeg, "right_hip_flexion"},
    {"right_thigh", DofKind::rotation, 1, -45 * kDeg, 45 * kDeg, "right_hip_twist"},
    {"right_thigh", DofKind::rotation, 2, -45 * kDeg, 30 * kDeg, "right_hip_abduction"},
    {"right_shin", DofKind::rotation, 0, 0, 150 * kDeg, "right_knee"},
    {"right_foot", DofKind::rotation, 0, -50 * kDeg, 20 * kDeg, "right_ankle_flexion"},
    {"right_foot", DofKind::rotation, 2, -20 * kDeg, 35 * kDeg, "right_ankle_inversion"},
}};
}  // namespace

Biped::Biped() {
  RawSkeleton raw;
  for (const LinkSpec& l : kLinks) {
    int parent = -1;
    for (std::size_t i = 0; i < raw.joints.size(); ++i)
      if (raw.joints[i].name == l.parent) parent = static_cast<int>(i);
    raw.add(std::string(l.name), parent, DualQuaternion<double>::from_translation(l.offset));
  }
  Expected<Skeleton> s = build_skeleton(raw);
  if (!s) throw std::logic_error("biped rig is invalid: " + s.error().message);  // a bug, not input
  skeleton_ = std::move(*s);
  for (std::size_t i = 0; i < dofs; ++i) {
    const DofSpec& d = kDofs[i];
    dofs_[i] = {skeleton_.find(d.joint), d.kind, d.axis, d.lower, d.upper, d.name};
  }
}

const Biped& Biped::instance() {
  static const Biped biped;
  return biped;
}

std::array<double, Biped::dofs> Biped::clamp(std::span<const double> q) const {
  std::array<double, dofs> out{};
  DQ_PRECONDITION(q.size() == dofs, "Biped::clamp needs 36 values", out);
  for (std::size_t i = 0; i < dofs; ++i) out[i] = std::clamp(q[i], dofs_[i].lower, dofs_[i].upper);
  return out;
}

}  // namespace dq

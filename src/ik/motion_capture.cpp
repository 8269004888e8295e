#include "dq/ik/motion_capture.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "dq/ik/solver.hpp"

namespace dq {

namespace {
constexpr double kDegree = std::numbers::pi / 180;

bool is_rotation(BvhChannel c) { return c == BvhChannel::Xrotation || c == BvhChannel::Yrotation || c == BvhChannel::Zrotation; }
int axis_of(BvhChannel c) {
  switch (c) {
    case BvhChannel::Xposition:
    case BvhChannel::Xrotation: return 0;
    case BvhChannel::Yposition:
    case BvhChannel::Yrotation: return 1;
    default: return 2;
  }
}
}  // namespace

Expected<BvhKinematics> bvh_kinematics(const BvhFile& bvh) {
  Expected<Skeleton> skeleton = bvh_skeleton(bvh);
  if (!skeleton) return skeleton.error();
  const auto raw = skeleton->raw_indices();
  std::vector<Dof> dofs;
  std::vector<std::size_t> channel_of;
  for (std::size_t j = 0; j < skeleton->size(); ++j) {
    const BvhJoint& b = bvh.joints[static_cast<std::size_t>(raw[j])];
    for (bool rotations : {false, true})  // positions first: BVH translates, then rotates
      for (std::size_t k = 0; k < b.channels.size(); ++k) {
        if (is_rotation(b.channels[k]) != rotations) continue;
        Vec3<double> axis{};
        axis[axis_of(b.channels[k])] = 1;
        dofs.push_back({static_cast<int>(j), rotations ? DofType::revolute : DofType::prismatic, axis,
                        b.name + "." + std::string(to_string(b.channels[k]))});
        channel_of.push_back(b.first_channel + k);
      }
  }
  Expected<KinematicModel> model = KinematicModel::build(std::move(*skeleton), std::move(dofs));
  if (!model) return model.error();
  return BvhKinematics{std::move(*model), std::move(channel_of)};
}

void BvhKinematics::to_parameters(std::span<const double> frame, std::span<double> q) const {
  DQ_PRECONDITION(q.size() == channel_of.size(), "to_parameters needs one value per parameter");
  for (std::size_t i = 0; i < q.size(); ++i) {
    const double v = frame[channel_of[i]];
    q[i] = model.dofs()[i].type == DofType::revolute ? v * kDegree : v;
  }
}

void BvhKinematics::to_frame(std::span<const double> q, std::span<const std::uint8_t> which, std::span<double> frame) const {
  DQ_PRECONDITION(q.size() == channel_of.size() && which.size() == q.size(), "to_frame needs one value and one flag per parameter");
  for (std::size_t i = 0; i < q.size(); ++i)
    if (which[i]) frame[channel_of[i]] = model.dofs()[i].type == DofType::revolute ? q[i] / kDegree : q[i];
}

namespace {

/// The feet: named, or found by name (one per side when the names say left and right).
Expected<std::vector<int>> find_feet(const Skeleton& s, const std::vector<std::string>& names) {
  std::vector<int> feet;
  if (!names.empty()) {
    for (const std::string& n : names) {
      const int j = s.find(n);
      if (j < 0) return Error{"no joint named '" + n + "' for a foot"};
      feet.push_back(j);
    }
    return feet;
  }
  for (const char* key : {"Toe", "Foot", "Ankle"}) {
    for (std::size_t j = 0; j < s.size(); ++j) {
      if (s.is_end_site(j)) continue;
      const std::string& name = s.names()[j];
      if (name.find(key) == std::string::npos) continue;
      // The topmost match of a chain (LeftToeBase, not a child LeftToeBase_End).
      const int p = s.parents()[j];
      if (p >= 0 && s.names()[static_cast<std::size_t>(p)].find(key) != std::string::npos) continue;
      feet.push_back(static_cast<int>(j));
    }
    if (feet.size() >= 2) return feet;
    feet.clear();
  }
  return Error{"no foot joints found by name (Toe, Foot, Ankle): name them"};
}

/// Frames of contact: low and slow, debounced (gaps bridged, short runs dropped).
std::vector<std::pair<std::size_t, std::size_t>> contacts(const std::vector<Vec3<double>>& p, double frame_time, double height,
                                                          double speed, const FixFeetOptions& o) {
  const std::size_t n = p.size();
  double lowest = p.empty() ? 0 : p[0].y;
  for (const auto& v : p) lowest = std::min(lowest, v.y);
  std::vector<std::uint8_t> on(n, 0);
  for (std::size_t f = 0; f < n; ++f) {
    const std::size_t a = f > 0 ? f - 1 : f, b = f + 1 < n ? f + 1 : f;
    const double v = b > a ? norm(p[b] - p[a]) / (static_cast<double>(b - a) * frame_time) : 0;
    on[f] = p[f].y <= lowest + height && v <= speed;
  }
  std::vector<std::pair<std::size_t, std::size_t>> runs;
  for (std::size_t f = 0; f < n;) {
    if (!on[f]) {
      ++f;
      continue;
    }
    std::size_t e = f;
    while (e + 1 < n && on[e + 1]) ++e;
    if (!runs.empty() && f - runs.back().second - 1 <= static_cast<std::size_t>(o.merge_gap_frames))
      runs.back().second = e;
    else
      runs.emplace_back(f, e);
    f = e + 1;
  }
  std::erase_if(runs, [&](const auto& r) { return r.second - r.first + 1 < static_cast<std::size_t>(o.min_contact_frames); });
  return runs;
}

double smoothstep(double x) {
  x = std::clamp(x, 0.0, 1.0);
  return x * x * (3 - 2 * x);
}

}  // namespace

Expected<FixFeetReport> fix_foot_sliding(BvhFile& bvh, const FixFeetOptions& options) {
  if (bvh.frame_count == 0) return Error{"the file has no motion to fix"};
  if (!(bvh.frame_time > 0)) return Error{"the frame time must be positive"};
  if (std::isnan(options.height) || std::isnan(options.speed) || options.height == std::numeric_limits<double>::infinity() ||
      options.speed == std::numeric_limits<double>::infinity())
    return Error{"the contact height and speed must be numbers below infinity (negative: chosen from the leg's length)"};
  if (options.min_contact_frames < 1 || options.merge_gap_frames < 0 || options.blend_frames < 0)
    return Error{"min_contact_frames must be 1 or more, merge_gap_frames and blend_frames 0 or more"};
  Expected<BvhKinematics> kin = bvh_kinematics(bvh);
  if (!kin) return kin.error();
  const KinematicModel& model = kin->model;
  const Skeleton& skeleton = model.skeleton();
  Expected<std::vector<int>> feet = find_feet(skeleton, options.feet);
  if (!feet) return feet.error();
  const std::size_t frames = bvh.frame_count, joints = skeleton.size(), n = model.parameters();

  // Forward kinematics of every frame, before.
  std::vector<double> q(n);
  std::vector<DualQuaternion<double>> world(joints);
  std::vector<std::vector<Vec3<double>>> before(joints, std::vector<Vec3<double>>(frames));
  auto positions = [&](std::vector<std::vector<Vec3<double>>>& out) {
    for (std::size_t f = 0; f < frames; ++f) {
      kin->to_parameters(bvh.frame(f), q);
      model_transforms<DualQuaternion<double>, double>(model, q, world);
      for (std::size_t j = 0; j < joints; ++j) out[j][f] = world[j].translation();
    }
  };
  positions(before);

  FixFeetReport report;
  std::vector<std::uint8_t> leg(n, 0), all_legs(n, 0), moved_joint(joints, 0);
  IkOptions ik;
  ik.max_restarts = 0;
  ik.rest_weight = 0.05;  // stay near the captured pose in the leg's null space
  std::vector<double> captured(n);
  for (int foot : *feet) {
    // The leg: the foot's ancestors below the root (the root's channels move the whole body); its
    // length (joint to joint, foot to hip) scales the default thresholds.
    std::fill(leg.begin(), leg.end(), 0);
    double leg_length = 0;
    const auto parent = [&](int j) { return skeleton.parents()[static_cast<std::size_t>(j)]; };
    for (int j = parent(foot); j >= 0 && parent(j) >= 0; j = parent(j)) {
      const auto ju = static_cast<std::size_t>(j);
      if (parent(parent(j)) >= 0) leg_length += norm(skeleton.rest_pose()[ju].translation());
      moved_joint[ju] = 1;
      for (std::size_t d = model.joint_dofs_begin(ju); d < model.joint_dofs_begin(ju + 1); ++d)
        leg[model.offset(d)] = all_legs[model.offset(d)] = 1;
      if (std::find(report.leg_joints.begin(), report.leg_joints.end(), skeleton.names()[ju]) == report.leg_joints.end())
        report.leg_joints.push_back(skeleton.names()[ju]);
    }
    for (std::size_t j = static_cast<std::size_t>(foot); j < skeleton.subtree_end(static_cast<std::size_t>(foot)); ++j) moved_joint[j] = 1;
    const std::vector<Vec3<double>>& path = before[static_cast<std::size_t>(foot)];
    leg_length += norm(skeleton.rest_pose()[static_cast<std::size_t>(foot)].translation());
    ik.position_tolerance = 1e-9 * leg_length;  // files come in metres, centimetres or inches
    IkSolver solver(model, ik);
    solver.set_free_parameters(leg);
    const double height = options.height >= 0 ? options.height : 0.1 * leg_length;
    const double speed = options.speed >= 0 ? options.speed : 1.0 * leg_length;
    FootContactReport fr;
    fr.joint = skeleton.names()[static_cast<std::size_t>(foot)];
    fr.contacts = contacts(path, bvh.frame_time, height, speed, options);
    // The pin of each contact (its mean position) and the blend weight of each frame.
    std::vector<double> weight(frames, 0);
    std::vector<Vec3<double>> pin(frames);
    for (const auto& [a, b] : fr.contacts) {
      Vec3<double> mean{};
      for (std::size_t f = a; f <= b; ++f) mean = mean + path[f];
      mean = mean / static_cast<double>(b - a + 1);
      const auto blend = static_cast<std::size_t>(std::max(options.blend_frames, 0));
      const std::size_t lo = a >= blend ? a - blend : 0, hi = std::min(frames - 1, b + blend);
      for (std::size_t f = lo; f <= hi; ++f) {
        double w = 1;
        if (f < a) w = smoothstep(static_cast<double>(f - lo + 1) / static_cast<double>(a - lo + 1));
        if (f > b) w = smoothstep(static_cast<double>(hi - f + 1) / static_cast<double>(hi - b + 1));
        if (w > weight[f]) weight[f] = w, pin[f] = mean;
      }
    }
    for (std::size_t f = 0; f < frames; ++f) {
      if (weight[f] <= 0) continue;
      const std::span<double> values(bvh.motion.data() + f * bvh.channel_count(), bvh.channel_count());
      kin->to_parameters(values, q);
      captured = q;
      const Vec3<double> target = path[f] + (pin[f] - path[f]) * weight[f];
      const IkTask task = IkTask::reach(foot, target);
      const IkResult r = solver.solve(std::span(&task, 1), q, captured);
      if (r.status != IkStatus::converged) ++report.unconverged_frames;
      report.max_pin_error = std::max(report.max_pin_error, r.position_error);
      kin->to_frame(q, leg, values);
    }
    report.feet.push_back(std::move(fr));
  }

  // Measurements, after.
  std::vector<std::vector<Vec3<double>>> after(joints, std::vector<Vec3<double>>(frames));
  positions(after);
  for (std::size_t j = 0; j < joints; ++j)
    for (std::size_t f = 0; f < frames; ++f) {
      const double d = norm(after[j][f] - before[j][f]);
      double& slot = moved_joint[j] ? report.max_leg_joint_motion : report.max_other_joint_motion;
      slot = std::max(slot, d);
    }
  for (std::size_t k = 0; k < report.feet.size(); ++k) {
    FootContactReport& fr = report.feet[k];
    const auto foot = static_cast<std::size_t>((*feet)[k]);
    auto horizontal = [](const Vec3<double>& a, const Vec3<double>& b) { return std::hypot(a.x - b.x, a.z - b.z); };
    for (const auto& [a, b] : fr.contacts)
      for (std::size_t f = a + 1; f <= b; ++f) {
        const double s0 = horizontal(before[foot][f], before[foot][f - 1]), s1 = horizontal(after[foot][f], after[foot][f - 1]);
        fr.slide_before += s0, fr.slide_after += s1;
        fr.max_slide_step_before = std::max(fr.max_slide_step_before, s0);
        fr.max_slide_step_after = std::max(fr.max_slide_step_after, s1);
      }
  }
  return report;
}

}  // namespace dq

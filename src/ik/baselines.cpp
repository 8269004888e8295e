#include "dq/ik/baselines.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "dq/ik/jacobian.hpp"

namespace dq {

TwoBoneSolution two_bone_ik(const Vec3<double>& root, const Vec3<double>& mid, const Vec3<double>& end,
                            const Vec3<double>& target, const Vec3<double>& pole) {
  const double a = norm(mid - root), b = norm(end - mid);
  const Vec3<double> to_target = target - root;
  const double distance = norm(to_target);
  TwoBoneSolution s;
  // The reach is [|a − b|, a + b]; outside it the chain points at the target as far as it goes.
  const double c = std::clamp(distance, std::abs(a - b), a + b);
  s.reachable = distance == c;
  const Vec3<double> u = distance > 0 ? to_target / distance : normalized(end - root);
  // The bend plane: spanned by u and the pole's component orthogonal to u (or the current mid's).
  Vec3<double> side = pole - root;
  side = side - u * dot(u, side);
  if (norm(side) <= 1e-12 * (a + b)) {
    side = (mid - root) - u * dot(u, mid - root);
    if (norm(side) <= 1e-12 * (a + b)) side = any_orthogonal(u);
  }
  const Vec3<double> v = normalized(side);
  // Law of cosines: the angle at the root between the first bone and the root–target line.
  const double cos_alpha = c > 0 ? std::clamp((a * a + c * c - b * b) / (2 * a * c), -1.0, 1.0) : 1.0;
  const double sin_alpha = std::sqrt(std::max(0.0, 1 - cos_alpha * cos_alpha));
  s.mid = root + (u * cos_alpha + v * sin_alpha) * a;
  s.end = root + u * c;
  s.root_rotation = Quaternion<double>::from_two_vectors(mid - root, s.mid - root);
  s.mid_rotation = Quaternion<double>::from_two_vectors(s.root_rotation.rotate(end - mid), s.end - s.mid);
  return s;
}

namespace {

IkResult invalid(const char* why) {
  IkResult r;
  r.status = IkStatus::invalid_input;
  r.message = why;
  r.position_error = r.orientation_error = std::numeric_limits<double>::quiet_NaN();  // no solve ran: no error to show as 0
  return r;
}

const char* check_position_task(const KinematicModel& model, const IkTask& task, std::span<const double> q) {
  if (task.kind != TaskKind::position) return "this baseline solves position tasks only";
  if (task.joint < 0 || static_cast<std::size_t>(task.joint) >= model.skeleton().size()) return "the effector is not a joint of the model";
  if (q.size() != model.parameters()) return "q must have one value per model parameter";
  for (double v : q)
    if (!std::isfinite(v)) return "q has a non-finite value";
  const Vec3<double> t = task.target.translation();
  for (double v : {t.x, t.y, t.z, task.point.x, task.point.y, task.point.z})
    if (!std::isfinite(v)) return "the task has a non-finite value";
  return nullptr;
}

/// Turns ball DOF d (acting in world frame F) by the world rotation `delta` about F's origin.
void turn_ball(const KinematicModel& model, std::size_t d, const DualQuaternion<double>& frame, const Quaternion<double>& delta,
               std::span<double> q) {
  double* r = q.data() + model.offset(d);
  const Quaternion<double> local = Quaternion<double>::from_rotation_vector({r[0], r[1], r[2]});
  const Vec3<double> v = (frame.real.conjugate() * delta * frame.real * local).to_rotation_vector();
  for (std::size_t k = 0; k < 3; ++k) {
    const auto l = model.limits()[model.offset(d) + k];
    r[k] = std::clamp(v[static_cast<int>(k)], l.lower, l.upper);
  }
}

struct Chain {
  std::vector<DualQuaternion<double>> world, frames;
  std::vector<Twist<double>> columns;
  explicit Chain(const KinematicModel& m) : world(m.skeleton().size()), frames(m.dofs().size()), columns(m.parameters()) {}
  Vec3<double> update(const KinematicModel& m, std::span<const double> q, const IkTask& task) {
    screw_jacobian<DualQuaternion<double>, double>(m, q, world, columns, frames);
    return world[static_cast<std::size_t>(task.joint)].transform_point(task.point);
  }
};

}  // namespace

IkResult ccd(const KinematicModel& model, const IkTask& task, std::span<double> q, const BaselineOptions& options) {
  if (const char* why = check_position_task(model, task, q)) return invalid(why);
  model.clamp(q);
  const Vec3<double> target = task.target.translation();
  const auto effector = static_cast<std::size_t>(task.joint);
  Chain chain(model);
  Vec3<double> x = chain.update(model, q, task);
  IkResult result;
  for (; result.iterations < options.max_iterations && norm(target - x) > options.tolerance; ++result.iterations) {
    for (std::size_t d = model.dofs().size(); d-- > 0;) {
      if (!moves(model, d, effector)) continue;
      const Dof& dof = model.dofs()[d];
      const std::size_t i = model.offset(d);
      const DualQuaternion<double>& frame = chain.frames[d];
      const Vec3<double> pivot = frame.translation();
      switch (dof.type) {
        case DofType::revolute: {
          const Vec3<double> w = chain.columns[i].angular;
          Vec3<double> a = x - pivot, b = target - pivot;
          a = a - w * dot(w, a);
          b = b - w * dot(w, b);
          q[i] = std::clamp(q[i] + std::atan2(dot(w, cross(a, b)), dot(a, b)), model.limits()[i].lower, model.limits()[i].upper);
          break;
        }
        case DofType::prismatic:
          q[i] = std::clamp(q[i] + dot(chain.columns[i].linear, target - x), model.limits()[i].lower, model.limits()[i].upper);
          break;
        case DofType::ball: turn_ball(model, d, frame, Quaternion<double>::from_two_vectors(x - pivot, target - pivot), q); break;
        case DofType::free: continue;  // the root stays where it is
      }
      x = chain.update(model, q, task);
    }
  }
  result.position_error = norm(target - x);
  result.status = result.position_error <= options.tolerance ? IkStatus::converged : IkStatus::iteration_limit;
  return result;
}

IkResult fabrik(const KinematicModel& model, const IkTask& task, std::span<double> q, const BaselineOptions& options) {
  if (const char* why = check_position_task(model, task, q)) return invalid(why);
  // The chain: the effector's ancestors that have a ball DOF, base first, then the effector point.
  std::vector<std::size_t> joints, ball_dof;
  for (int j = task.joint; j >= 0; j = model.skeleton().parents()[static_cast<std::size_t>(j)]) {
    const auto ju = static_cast<std::size_t>(j);
    const std::size_t b = model.joint_dofs_begin(ju), e = model.joint_dofs_begin(ju + 1);
    if (j == task.joint && e == b) continue;  // an effector without DOFs (an End Site) rides on its parent
    if (e - b != 1 || model.dofs()[b].type != DofType::ball) break;  // up to a joint that is not a ball
    joints.push_back(ju);
    ball_dof.push_back(b);
  }
  std::reverse(joints.begin(), joints.end());
  std::reverse(ball_dof.begin(), ball_dof.end());
  if (joints.empty()) return invalid("FABRIK needs a chain of ball joints above the effector");
  model.clamp(q);
  Chain chain(model);
  const Vec3<double> target = task.target.translation();
  Vec3<double> x = chain.update(model, q, task);
  std::vector<Vec3<double>> p(joints.size() + 1);
  std::vector<double> length(joints.size());
  IkResult result;
  for (; result.iterations < options.max_iterations && norm(target - x) > options.tolerance; ++result.iterations) {
    for (std::size_t k = 0; k < joints.size(); ++k) p[k] = chain.world[joints[k]].translation();
    p.back() = x;
    for (std::size_t k = 0; k < joints.size(); ++k) length[k] = norm(p[k + 1] - p[k]);
    const Vec3<double> base = p.front();
    // Backward pass from the target, forward pass from the base.
    p.back() = target;
    for (std::size_t k = joints.size(); k-- > 0;) p[k] = p[k + 1] + normalized(p[k] - p[k + 1]) * length[k];
    p.front() = base;
    for (std::size_t k = 0; k < joints.size(); ++k) p[k + 1] = p[k] + normalized(p[k + 1] - p[k]) * length[k];
    // Rotate each ball joint, base first, so that its bone points at its new child position.
    for (std::size_t k = 0; k < joints.size(); ++k) {
      const Vec3<double> pivot = chain.world[joints[k]].translation();
      const Vec3<double> child = k + 1 < joints.size() ? chain.world[joints[k + 1]].translation() : x;
      turn_ball(model, ball_dof[k], chain.frames[ball_dof[k]], Quaternion<double>::from_two_vectors(child - pivot, p[k + 1] - pivot), q);
      x = chain.update(model, q, task);
    }
  }
  result.position_error = norm(target - x);
  result.status = result.position_error <= options.tolerance ? IkStatus::converged : IkStatus::iteration_limit;
  return result;
}

}  // namespace dq

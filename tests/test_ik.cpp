// Inverse kinematics: the kinematic model, its Jacobian (against Dual<T> forward-mode derivatives
// and finite differences), and the solvers (reachable targets, limits, unreachable targets).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <atomic>
#include <cstdlib>
#include <limits>
#include <new>
#include <random>
#include <vector>

#include "dq/anim/biped.hpp"
#include "dq/anim/forward_kinematics.hpp"
#include "dq/ik/baselines.hpp"
#include "dq/ik/jacobian.hpp"
#include "dq/ik/kinematic_model.hpp"
#include "dq/ik/motion_capture.hpp"
#include "dq/ik/solver.hpp"
#include "models.hpp"
#include "support.hpp"

// Counts heap allocations, so that a test can show a solve makes none. (The replacement pairs
// malloc with free, which GCC cannot see through once std::allocator is inlined.)
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
std::atomic<long> g_allocations{0};
void* operator new(std::size_t size) {
  ++g_allocations;
  if (void* p = std::malloc(size ? size : 1)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }

namespace {

using namespace dq;

std::vector<double> random_parameters(const KinematicModel& m, std::mt19937_64& rng, double unlimited = 1.0) {
  std::vector<double> q(m.parameters());
  for (std::size_t i = 0; i < q.size(); ++i) {
    const auto l = m.limits()[i];
    const double lo = std::isfinite(l.lower) ? l.lower : -unlimited, hi = std::isfinite(l.upper) ? l.upper : unlimited;
    q[i] = std::uniform_real_distribution<double>(lo, hi)(rng);
  }
  return q;
}

std::array<double, 8> parts(const DualQuaternion<double>& q) {
  return {q.real.w, q.real.x, q.real.y, q.real.z, q.dual.w, q.dual.x, q.dual.y, q.dual.z};
}

// dQ_j/dq_i from Dual<double> forward kinematics (parameter i seeded) against ½ Ξ_i Q_j from the
// screw Jacobian, for every joint and parameter; and against central differences.
void check_jacobian(const KinematicModel& m, const std::vector<double>& q) {
  const std::size_t n = m.parameters(), joints = m.skeleton().size();
  std::vector<DualQuaternion<double>> world(joints);
  std::vector<Twist<double>> cols(n);
  screw_jacobian<DualQuaternion<double>, double>(m, q, world, cols);
  std::vector<DualQuaternion<double>> plain(joints);
  model_transforms<DualQuaternion<double>, double>(m, q, plain);
  for (std::size_t j = 0; j < joints; ++j) EXPECT_TRUE(approx_equal(world[j], plain[j], 1e-14)) << "joint " << j;
  using D = Dual<double>;
  std::vector<D> qd(n);
  std::vector<DualQuaternion<D>> wd(joints);
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t k = 0; k < n; ++k) qd[k] = D(q[k], k == i ? 1.0 : 0.0);
    model_transforms<DualQuaternion<D>, D>(m, qd, wd);
    std::vector<double> qp = q, qm = q;
    const double h = 1e-6;
    qp[i] += h;
    qm[i] -= h;
    std::vector<DualQuaternion<double>> wp(joints), wm(joints);
    model_transforms<DualQuaternion<double>, double>(m, qp, wp);
    model_transforms<DualQuaternion<double>, double>(m, qm, wm);
    std::size_t dof = 0;
    while (dof + 1 < m.dofs().size() && m.offset(dof + 1) <= i) ++dof;
    for (std::size_t j = 0; j < joints; ++j) {
      const auto analytic = parts(moves(m, dof, j) ? cols[i].as_dual_quaternion() * world[j] * 0.5 : DualQuaternion<double>(0, 0, 0, 0, 0, 0, 0, 0));
      const auto fp = parts(wp[j]), fm = parts(wm[j]);
      const DualQuaternion<D>& x = wd[j];
      const std::array<double, 8> forward{x.real.w.dual, x.real.x.dual, x.real.y.dual, x.real.z.dual,
                                          x.dual.w.dual, x.dual.x.dual, x.dual.y.dual, x.dual.z.dual};
      for (std::size_t c = 0; c < 8; ++c) {
        EXPECT_NEAR(analytic[c], forward[c], 1e-12) << "parameter " << i << " joint " << j << " component " << c;
        EXPECT_NEAR(analytic[c], (fp[c] - fm[c]) / (2 * h), 1e-8) << "parameter " << i << " joint " << j;
      }
    }
  }
}

TEST(KinematicModel, ScrewJacobianEqualsForwardModeAndFiniteDifferences) {
  std::mt19937_64 rng(11);
  for (const KinematicModel* m : {&KinematicModel::arm7(), &KinematicModel::biped()}) {
    check_jacobian(*m, std::vector<double>(m->parameters(), 0.0));  // the rest pose
    for (int k = 0; k < 5; ++k) check_jacobian(*m, random_parameters(*m, rng));
  }
  // Singular configurations of the arm: straight (all zero) was above; elbow and wrist folded.
  std::vector<double> q(7, 0.0);
  q[3] = 0;
  q[5] = 0;
  q[1] = 1e-9;
  check_jacobian(KinematicModel::arm7(), q);
  // Ball and free joints, including rotation vectors at and near zero and near π.
  RawSkeleton raw;
  const int a = raw.add("root", -1, DualQuaternion<double>::from_translation({0.1, 0.2, 0.3}));
  const int b = raw.add("mid", a, DualQuaternion<double>::from_rotation_translation(Quaternion<double>::from_axis_angle({1, 1, 0}, 0.4), {0, 0.5, 0}));
  raw.add("tip", b, DualQuaternion<double>::from_translation({0.3, 0, 0.1}));
  const KinematicModel balls = KinematicModel::ball_joints(*build_skeleton(raw));
  ASSERT_EQ(balls.parameters(), 6u + 3u + 3u);
  check_jacobian(balls, std::vector<double>(12, 0.0));
  check_jacobian(balls, {0.1, -0.2, 0.3, 1e-9, 0, -1e-9, 0.2, 0.3, -0.1, 3.0, 0.5, 0.1});
  check_jacobian(balls, random_parameters(balls, rng, 2.0));
}

TEST(KinematicModel, AxesOfAnyLengthAreNormalizedAndZeroAxesRefused) {
  RawSkeleton raw;
  raw.add("tip", raw.add("base", -1, DualQuaternion<double>::identity()), DualQuaternion<double>::from_translation({1, 0, 0}));
  const Skeleton skeleton = *build_skeleton(raw);
  const Expected<KinematicModel> scaled = KinematicModel::build(skeleton, {{0, DofType::revolute, {0, 0, 3}, "yaw"}});
  ASSERT_TRUE(scaled.has_value()) << scaled.error().message;
  EXPECT_EQ(scaled->dofs()[0].axis, (Vec3<double>{0, 0, 1}));
  // A quarter turn about the axis given as (0, 0, 3) takes the tip from +x to +y.
  const std::vector<double> q{std::numbers::pi / 2};
  std::vector<DualQuaternion<double>> world(2);
  model_transforms<DualQuaternion<double>, double>(*scaled, q, world);
  EXPECT_LE(norm(world[1].translation() - Vec3<double>{0, 1, 0}), 1e-15);
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  for (const Vec3<double>& axis : {Vec3<double>{0, 0, 0}, Vec3<double>{0, nan, 1}, Vec3<double>{inf, 0, 0}}) {
    const Expected<KinematicModel> bad = KinematicModel::build(skeleton, {{0, DofType::prismatic, axis, "slide"}});
    ASSERT_FALSE(bad.has_value());
    EXPECT_NE(bad.error().message.find("the axis has no direction"), std::string::npos) << bad.error().message;
  }
}

TEST(KinematicModel, ForwardKinematicsWithWrongSizesReportsAndWritesNothing) {
  // With a handler that returns, the violated precondition returns from the function: no read
  // or write past the model's joints (an output of 100 used to be walked to its end).
  static int calls = 0;
  const PreconditionHandler previous = set_precondition_handler([](const PreconditionViolation&) { ++calls; });
  const KinematicModel& arm = KinematicModel::arm7();
  const std::vector<double> q(7, 0.2), short_q(6, 0.2);
  const DualQuaternion<double> marker = DualQuaternion<double>::from_translation({7, 7, 7});
  std::vector<DualQuaternion<double>> long_world(100, marker), world(arm.skeleton().size(), marker);
  model_transforms<DualQuaternion<double>, double>(arm, q, long_world);
  model_transforms<DualQuaternion<double>, double>(arm, short_q, world);
  set_precondition_handler(previous);
  EXPECT_EQ(calls, 2);
  for (const auto& x : long_world) EXPECT_EQ(x, marker);
  for (const auto& x : world) EXPECT_EQ(x, marker);
}

TEST(KinematicModel, BipedPoseIsGenericOverTheScalar) {
  // Biped::pose with Dual<double> values: the derivative of each joint's transform by one DOF,
  // against central differences of the double version.
  const Biped& biped = Biped::instance();
  std::mt19937_64 rng(17);
  const auto q = random_parameters(KinematicModel::biped(), rng);
  for (std::size_t i = 0; i < Biped::dofs; i += 5) {
    std::vector<Dual<double>> qd(q.begin(), q.end());
    qd[i].dual = 1;
    std::vector<DualQuaternion<Dual<double>>> d(Biped::links);
    biped.pose<Dual<double>>(qd, d);
    std::vector<double> qp = q, qm = q;
    qp[i] += 1e-6;
    qm[i] -= 1e-6;
    std::vector<DualQuaternion<double>> p(Biped::links), m(Biped::links);
    biped.pose(qp, p);
    biped.pose(qm, m);
    for (std::size_t j = 0; j < Biped::links; ++j) {
      const auto fp = parts(p[j]), fm = parts(m[j]);
      const DualQuaternion<Dual<double>>& x = d[j];
      const std::array<double, 8> fwd{x.real.w.dual, x.real.x.dual, x.real.y.dual, x.real.z.dual,
                                       x.dual.w.dual, x.dual.x.dual, x.dual.y.dual, x.dual.z.dual};
      for (std::size_t c = 0; c < 8; ++c) EXPECT_NEAR(fwd[c], (fp[c] - fm[c]) / 2e-6, 1e-8) << "dof " << i << " joint " << j;
    }
  }
}

TEST(KinematicModel, BipedModelMatchesTheBipedRig) {
  const Biped& biped = Biped::instance();
  const KinematicModel& m = KinematicModel::biped();
  ASSERT_EQ(m.parameters(), Biped::dofs);
  std::mt19937_64 rng(5);
  for (int k = 0; k < 20; ++k) {
    const auto q = random_parameters(m, rng);
    std::vector<DualQuaternion<double>> a(Biped::links), b(Biped::links);
    biped.pose(q, a);
    local_transforms<DualQuaternion<double>, double>(m, q, b);
    for (std::size_t j = 0; j < Biped::links; ++j) EXPECT_TRUE(approx_equal(a[j], b[j], 1e-14, SignPolicy::same_rotation)) << j;
    std::vector<Mat4<double>> mats(Biped::links);
    std::vector<DualQuaternion<double>> world(Biped::links);
    model_transforms<Mat4<double>, double>(m, q, mats);
    model_transforms<DualQuaternion<double>, double>(m, q, world);
    for (std::size_t j = 0; j < Biped::links; ++j) EXPECT_LE(test::max_abs_diff(mats[j], to_mat4(world[j])), 1e-13);
  }
}


/// The world transform of `joint` at q.
DualQuaternion<double> frame_at(const KinematicModel& m, const std::vector<double>& q, int joint) {
  std::vector<DualQuaternion<double>> w(m.skeleton().size());
  model_transforms<DualQuaternion<double>, double>(m, q, w);
  return w[static_cast<std::size_t>(joint)];
}

TEST(IkSolver, ReachableArmTargetsConvergeTo1e9WithinLimits) {
  // Targets from forward kinematics of random poses within the limits: reachable by construction.
  const KinematicModel& arm = KinematicModel::arm7();
  const int flange = arm.skeleton().find("flange");
  IkSolver solver(arm);
  std::mt19937_64 rng(2024);
  int converged = 0, total = 10000;
  long iterations = 0;
  for (int k = 0; k < total; ++k) {
    const auto goal = random_parameters(arm, rng);
    const IkTask task = IkTask::frame(flange, frame_at(arm, goal, flange));
    std::vector<double> q(7, 0.0);
    const IkResult r = solver.solve(std::span(&task, 1), q);
    ASSERT_NE(r.status, IkStatus::invalid_input) << r.message;
    ASSERT_TRUE(arm.within_limits(q)) << k;
    iterations += r.iterations;
    if (r.status != IkStatus::converged) continue;
    ++converged;
    // Independent check of the reported errors: the pose reached, through forward kinematics.
    const DualQuaternion<double> got = frame_at(arm, q, flange);
    EXPECT_LE(norm(got.translation() - task.target.translation()), 1e-9) << k;
    EXPECT_LE(angular_distance(got.real, task.target.real), 1e-9) << k;
  }
  const double rate = static_cast<double>(converged) / total;
  RecordProperty("success_rate", std::to_string(rate));
  RecordProperty("mean_iterations", std::to_string(static_cast<double>(iterations) / total));
  EXPECT_GE(rate, 0.999);
}

TEST(IkSolver, BipedLimbsConvergeTo1e9) {
  // Each limb's effector (feet and hands) to a pose reached by random joint values within the
  // limits, the whole 36-DOF body free to help; and all four at once (reported: harder, with
  // local minima that restarts escape).
  const KinematicModel& biped = KinematicModel::biped();
  const int effectors[] = {biped.skeleton().find("left_foot"), biped.skeleton().find("right_foot"),
                           biped.skeleton().find("left_hand"), biped.skeleton().find("right_hand")};
  IkSolver solver(biped);
  std::mt19937_64 rng(77);
  int converged = 0, total = 0;
  for (int k = 0; k < 2000; ++k) {
    const auto goal = random_parameters(biped, rng);
    const int e = effectors[k % 4];
    const IkTask task = IkTask::frame(e, frame_at(biped, goal, e));
    std::vector<double> q(biped.parameters(), 0.0);
    const IkResult r = solver.solve(std::span(&task, 1), q);
    ASSERT_TRUE(biped.within_limits(q));
    ++total;
    if (r.status != IkStatus::converged) continue;
    ++converged;
    const DualQuaternion<double> got = frame_at(biped, q, e);
    EXPECT_LE(norm(got.translation() - task.target.translation()), 1e-9);
    EXPECT_LE(angular_distance(got.real, task.target.real), 1e-9);
  }
  RecordProperty("limb_success_rate", std::to_string(static_cast<double>(converged) / total));
  EXPECT_GE(converged * 1000, total * 999);
  int all_four = 0;
  const int four_total = 50;
  for (int k = 0; k < four_total; ++k) {
    const auto goal = random_parameters(biped, rng);
    std::array<IkTask, 4> tasks;
    for (std::size_t e = 0; e < 4; ++e) tasks[e] = IkTask::frame(effectors[e], frame_at(biped, goal, effectors[e]));
    std::vector<double> q(biped.parameters(), 0.0);
    all_four += solver.solve(tasks, q).status == IkStatus::converged;
    ASSERT_TRUE(biped.within_limits(q));
  }
  RecordProperty("four_effector_success_rate", std::to_string(static_cast<double>(all_four) / four_total));
  EXPECT_GE(all_four, four_total * 8 / 10);
}

TEST(IkSolver, UnreachableTargetsReturnTheClosestReach) {
  // The arm reaches 0.40 + 0.40 + 0.126 m from its shoulder (0.34 m up). A point 2 m away along x
  // from the shoulder is out of reach: the closest pose stretches towards it.
  const KinematicModel& arm = KinematicModel::arm7();
  const int flange = arm.skeleton().find("flange");
  IkSolver solver(arm);
  const Vec3<double> shoulder{0, 0, 0.34}, target = shoulder + Vec3<double>{2, 0, 0};
  const IkTask task = IkTask::reach(flange, target);
  std::vector<double> q(7, 0.1);
  const IkResult r = solver.solve(std::span(&task, 1), q);
  EXPECT_EQ(r.status, IkStatus::unreachable);
  EXPECT_NEAR(r.position_error, 2 - 0.926, 1e-7);
  EXPECT_NEAR(norm(frame_at(arm, q, flange).translation() - target), 2 - 0.926, 1e-7);
  EXPECT_TRUE(arm.within_limits(q));
}

TEST(IkSolver, InvalidInputIsAnErrorAndLeavesQUntouched) {
  const KinematicModel& arm = KinematicModel::arm7();
  IkSolver solver(arm);
  std::vector<double> q(7, 0.25);
  const std::vector<double> before = q;
  IkTask bad = IkTask::reach(7, {0.3, 0.2, 0.5});
  auto expect_invalid = [&](const IkTask& t, std::span<double> qq, const char* what) {
    const IkResult r = solver.solve(std::span(&t, 1), qq);
    EXPECT_EQ(r.status, IkStatus::invalid_input) << what;
    EXPECT_NE(std::string(r.message), "") << what;
    EXPECT_TRUE(std::isnan(r.position_error) && std::isnan(r.orientation_error)) << what << ": no solve ran, so no error of 0";
    EXPECT_EQ(q, before) << what;
  };
  IkTask nan_target = bad;
  nan_target.target.dual.x = std::nan("");
  expect_invalid(nan_target, q, "NaN target");
  IkTask not_unit = IkTask::frame(7, DualQuaternion<double>(2, 0, 0, 0, 0, 0, 0, 0));
  expect_invalid(not_unit, q, "non-unit target");
  IkTask no_joint = bad;
  no_joint.joint = 42;
  expect_invalid(no_joint, q, "effector not in the skeleton");
  std::vector<double> short_q(6, 0.0);
  expect_invalid(bad, short_q, "wrong DOF vector size");
  std::vector<double> nan_q = q;
  nan_q[2] = std::nan("");
  const IkResult r = solver.solve(std::span(&bad, 1), nan_q);
  EXPECT_EQ(r.status, IkStatus::invalid_input);
  IkTask slightly_off = IkTask::frame(7, DualQuaternion<double>(1 + 1e-5, 0, 0, 0, 0, 0, 0, 0));
  expect_invalid(slightly_off, q, "target 1e-5 off unit");
  IkTask no_direction = IkTask::onto_line(7, {0.4, 0, 0.6}, {0, 0, 0});
  expect_invalid(no_direction, q, "line without a direction");
  IkTask wrong_level = bad;
  wrong_level.priority = kIkPriorityLevels;
  expect_invalid(wrong_level, q, "priority beyond the levels");
  const std::vector<IkTask> too_many(kIkMaxTasks + 1, bad);
  EXPECT_EQ(solver.solve(too_many, q).status, IkStatus::invalid_input);
  EXPECT_EQ(q, before);
  // Options out of range: a negative iteration count returned iteration_limit without a word.
  const IkTask reachable = IkTask::reach(7, {0.3, 0.2, 0.5});
  for (const auto& [change, what] : std::initializer_list<std::pair<void (*)(IkOptions&), const char*>>{
           {[](IkOptions& o) { o.max_iterations = -1; }, "max_iterations"},
           {[](IkOptions& o) { o.max_restarts = -1; }, "max_restarts"},
           {[](IkOptions& o) { o.position_tolerance = std::nan(""); }, "position_tolerance"},
           {[](IkOptions& o) { o.orientation_tolerance = HUGE_VAL; }, "orientation_tolerance"},
           {[](IkOptions& o) { o.initial_damping = 0; }, "initial_damping"},
           {[](IkOptions& o) { o.rest_weight = -1; }, "rest_weight"},
           {[](IkOptions& o) { o.method = static_cast<IkMethod>(7); }, "method"}}) {
    IkOptions options;
    change(options);
    IkSolver with(arm, options);
    const IkResult refused = with.solve(std::span(&reachable, 1), q);
    EXPECT_EQ(refused.status, IkStatus::invalid_input) << what;
    EXPECT_NE(std::string(refused.message).find(what), std::string::npos) << refused.message;
    EXPECT_EQ(q, before) << what;
  }
}

TEST(IkSolver, TargetsFromFloatDataAndAxesOfAnyLengthAreNormalized) {
  // A pose target that went through float (unit to about 1e-7, not to 1e-9), and a line whose
  // direction is not unit: solved as their normalized selves, to the full tolerance.
  const KinematicModel& arm = KinematicModel::arm7();
  const int flange = arm.skeleton().find("flange");
  IkSolver solver(arm);
  std::vector<double> reached(7, 0.3);
  const DualQuaternion<double> exact = frame_at(arm, reached, flange);
  const DualQuaternion<double> from_float = exact.cast<float>().cast<double>();
  ASSERT_FALSE(from_float.is_unit(1e-9));
  std::vector<double> q(7, 0.1);
  IkTask pose = IkTask::frame(flange, from_float);
  IkResult r = solver.solve(std::span(&pose, 1), q);
  ASSERT_EQ(r.status, IkStatus::converged) << r.message;
  const DualQuaternion<double> got = frame_at(arm, q, flange), want = from_float.normalized();
  EXPECT_LE(norm(got.translation() - want.translation()), 1e-9);
  EXPECT_LE(angular_distance(got.real, want.real), 1e-9);

  const Vec3<double> through{0.4, 0.0, 0.6}, direction{0, 2, 0.4};  // |direction| ≈ 2.04
  IkTask line = IkTask::onto_line(flange, through, direction);
  std::vector<double> q2(7, 0.1);
  r = solver.solve(std::span(&line, 1), q2);
  ASSERT_EQ(r.status, IkStatus::converged) << r.message;
  const Vec3<double> d = normalized(direction), e = through - frame_at(arm, q2, flange).translation();
  EXPECT_LE(norm(e - d * dot(d, e)), 1e-9);
}

TEST(IkSolver, SolvesAllocateNothing) {
  const KinematicModel& biped = KinematicModel::biped();
  IkSolver solver(biped);
  std::mt19937_64 rng(3);
  const auto goal = random_parameters(biped, rng);
  const int foot = biped.skeleton().find("left_foot"), hand = biped.skeleton().find("right_hand");
  const std::array<IkTask, 2> tasks{IkTask::frame(foot, frame_at(biped, goal, foot)), IkTask::reach(hand, frame_at(biped, goal, hand).translation())};
  std::vector<double> q(biped.parameters(), 0.0);
  const long before = g_allocations.load();
  const IkResult r = solver.solve(tasks, q);
  EXPECT_EQ(g_allocations.load() - before, 0);
  EXPECT_EQ(r.status, IkStatus::converged);
  // The arm's 6-row (pose) and 3-row (position) systems take the fixed-size path.
  const KinematicModel& arm = KinematicModel::arm7();
  const int flange = arm.skeleton().find("flange");
  IkSolver arm_solver(arm);
  const auto arm_goal = random_parameters(arm, rng);
  const DualQuaternion<double> target = frame_at(arm, arm_goal, flange);
  for (const IkTask& task : {IkTask::frame(flange, target), IkTask::reach(flange, target.translation())}) {
    std::vector<double> qa(7, 0.0);
    const long arm_before = g_allocations.load();
    const IkResult ra = arm_solver.solve(std::span(&task, 1), qa);
    EXPECT_EQ(g_allocations.load() - arm_before, 0);
    EXPECT_EQ(ra.status, IkStatus::converged);
  }
}

TEST(IkSolver, MatricesNewtonAndGaussSeidelSolveTheSameTargets) {
  const KinematicModel& arm = KinematicModel::arm7();
  const int flange = arm.skeleton().find("flange");
  IkSolver dq_solver(arm);
  MatrixIkSolver matrix_solver(arm);
  IkOptions newton_options;
  newton_options.method = IkMethod::newton;
  IkSolver newton(arm, newton_options);
  IkOptions gs_options;
  gs_options.method = IkMethod::gauss_seidel;
  gs_options.max_iterations = 400;
  IkSolver gauss_seidel(arm, gs_options);
  std::mt19937_64 rng(99);
  int ok[4] = {0, 0, 0, 0};
  const int total = 100;
  for (int k = 0; k < total; ++k) {
    const auto goal = random_parameters(arm, rng);
    const IkTask task = IkTask::frame(flange, frame_at(arm, goal, flange));
    int s = 0;
    auto run = [&](auto& solver) {
      std::vector<double> q(7, 0.0);
      const IkResult r = solver.solve(std::span(&task, 1), q);
      EXPECT_TRUE(arm.within_limits(q));
      const DualQuaternion<double> got = frame_at(arm, q, flange);
      if (r.status == IkStatus::converged) {
        EXPECT_LE(norm(got.translation() - task.target.translation()), 1e-9);
      }
      ok[s++] += r.status == IkStatus::converged;
    };
    run(dq_solver);
    run(matrix_solver);
    run(newton);
    run(gauss_seidel);
  }
  EXPECT_GE(ok[0], 99);
  EXPECT_GE(ok[1], 99);
  EXPECT_GE(ok[2], 95);
  EXPECT_GE(ok[3], 80);
  RecordProperty("converged_dq_matrix_newton_gs",
                 std::to_string(ok[0]) + " " + std::to_string(ok[1]) + " " + std::to_string(ok[2]) + " " + std::to_string(ok[3]));
}

TEST(IkSolver, PrioritiesAndTheNullSpace) {
  const KinematicModel& arm = KinematicModel::arm7();
  const int flange = arm.skeleton().find("flange"), elbow = arm.skeleton().find("a4");
  // Level 0: the flange on a reachable point. Level 1: the elbow towards a point it cannot reach
  // while level 0 holds. Level 0 must be met exactly; level 1 as well as the null space allows.
  std::vector<double> goal{0.3, 0.6, -0.2, -1.1, 0.4, 0.7, 0.1};
  const Vec3<double> p = frame_at(arm, goal, flange).translation();
  std::array<IkTask, 2> tasks{IkTask::reach(flange, p), IkTask::reach(elbow, {0.5, 0.5, 1.5})};
  tasks[1].priority = 1;
  IkSolver solver(arm);
  std::vector<double> q(7, 0.0);
  solver.solve(tasks, q);
  EXPECT_LE(norm(frame_at(arm, q, flange).translation() - p), 1e-9);
  std::vector<double> q_alone(7, 0.0);
  solver.solve(std::span(tasks.data(), 1), q_alone);
  EXPECT_LT(norm(frame_at(arm, q, elbow).translation() - tasks[1].target.translation()),
            norm(frame_at(arm, q_alone, elbow).translation() - tasks[1].target.translation()));
  // The secondary objective: with a rest pose, the redundant arm reaches the same point and ends
  // closer to the rest pose than without it.
  IkOptions pull;
  pull.rest_weight = 0.1;
  IkSolver rested(arm, pull);
  const std::vector<double> rest(7, 0.2);
  std::vector<double> q_rest(7, 0.0), q_free(7, 0.0);
  rested.solve(std::span(tasks.data(), 1), q_rest, rest);
  solver.solve(std::span(tasks.data(), 1), q_free, rest);
  EXPECT_LE(norm(frame_at(arm, q_rest, flange).translation() - p), 1e-9);
  auto dist = [&](const std::vector<double>& a) {
    double s = 0;
    for (std::size_t i = 0; i < 7; ++i) s += (a[i] - rest[i]) * (a[i] - rest[i]);
    return s;
  };
  EXPECT_LT(dist(q_rest), dist(q_free));
}

TEST(IkSolver, AimAndPointOnLineTasks) {
  const KinematicModel& arm = KinematicModel::arm7();
  const int flange = arm.skeleton().find("flange");
  IkSolver solver(arm);
  // Aim the flange's z axis at a point, and put the flange on a line.
  const Vec3<double> look{0.6, -0.4, 0.2};
  const std::array<IkTask, 2> tasks{IkTask::aim_at(flange, {0, 0, 1}, look),
                                    IkTask::onto_line(flange, {0.4, 0.0, 0.6}, normalized(Vec3<double>{0, 1, 0.2}))};
  std::vector<double> q(7, 0.1);
  const IkResult r = solver.solve(tasks, q);
  ASSERT_EQ(r.status, IkStatus::converged);
  const DualQuaternion<double> f = frame_at(arm, q, flange);
  const Vec3<double> z = f.real.rotate({0, 0, 1}), to = normalized(look - f.translation());
  EXPECT_LE(norm(z - to), 1e-9);
  const Vec3<double> d = normalized(Vec3<double>{0, 1, 0.2}), e = Vec3<double>{0.4, 0.0, 0.6} - f.translation();
  EXPECT_LE(norm(e - d * dot(d, e)), 1e-9);
}

TEST(IkBaselines, TwoBoneReachesWithTheKneeTowardsThePole) {
  std::mt19937_64 rng(8);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int k = 0; k < 1000; ++k) {
    const Vec3<double> root{u(rng), u(rng), u(rng)}, mid = root + Vec3<double>{u(rng), u(rng), u(rng)};
    const Vec3<double> end = mid + Vec3<double>{u(rng), u(rng), u(rng)};
    const double a = norm(mid - root), b = norm(end - mid);
    const Vec3<double> pole{u(rng) * 5, u(rng) * 5, u(rng) * 5};
    // A reachable target (strictly inside the reach) and one beyond it.
    const Vec3<double> dir = normalized(Vec3<double>{u(rng), u(rng), u(rng)});
    const double reach = std::abs(a - b) + (a + b - std::abs(a - b)) * (0.05 + 0.9 * (u(rng) + 1) / 2);
    const Vec3<double> target = root + dir * reach;
    const TwoBoneSolution s = two_bone_ik(root, mid, end, target, pole);
    EXPECT_TRUE(s.reachable);
    EXPECT_LE(norm(s.end - target), 1e-12 * (1 + reach));
    EXPECT_NEAR(norm(s.mid - root), a, 1e-12);
    EXPECT_NEAR(norm(s.end - s.mid), b, 1e-12);
    // The rotations move the chain there: rotate the bones rigidly.
    const Vec3<double> new_mid = root + s.root_rotation.rotate(mid - root);
    const Vec3<double> new_end = new_mid + s.mid_rotation.rotate(s.root_rotation.rotate(end - mid));
    EXPECT_LE(norm(new_mid - s.mid), 1e-12);
    EXPECT_LE(norm(new_end - s.end), 1e-12);
    // The knee lies in the plane of root, target and pole, on the pole's side.
    const Vec3<double> n = cross(target - root, pole - root);
    if (norm(n) > 1e-6) {
      EXPECT_NEAR(dot(normalized(n), s.mid - root), 0, 1e-12);
    }
    const Vec3<double> off_line = (s.mid - root) - dir * dot(dir, s.mid - root), pole_side = (pole - root) - dir * dot(dir, pole - root);
    if (norm(pole_side) > 1e-6 && norm(off_line) > 1e-9) {
      EXPECT_GT(dot(off_line, pole_side), 0);
    }
    const TwoBoneSolution far = two_bone_ik(root, mid, end, root + dir * (a + b + 1), pole);
    EXPECT_FALSE(far.reachable);
    EXPECT_LE(norm(far.end - (root + dir * (a + b))), 1e-12);
  }
}

TEST(IkBaselines, CcdAndFabrikReachPositionTargets) {
  const KinematicModel& arm = KinematicModel::arm7();
  const int flange = arm.skeleton().find("flange");
  std::mt19937_64 rng(31);
  int ccd_ok = 0;
  for (int k = 0; k < 100; ++k) {
    const auto goal = random_parameters(arm, rng);
    const IkTask task = IkTask::reach(flange, frame_at(arm, goal, flange).translation());
    std::vector<double> q(7, 0.1);
    const IkResult r = ccd(arm, task, q, {2000, 1e-9});
    EXPECT_TRUE(arm.within_limits(q));
    if (r.status == IkStatus::converged) {
      ++ccd_ok;
      EXPECT_LE(norm(frame_at(arm, q, flange).translation() - task.target.translation()), 1e-9);
    }
  }
  RecordProperty("ccd_converged_of_100", std::to_string(ccd_ok));
  EXPECT_GE(ccd_ok, 80);
  // FABRIK on a five-bone chain of ball joints (what captured skeletons get), unlimited.
  RawSkeleton raw;
  int parent = raw.add("root", -1);
  for (int j = 0; j < 5; ++j) parent = raw.add("b" + std::to_string(j), parent, DualQuaternion<double>::from_translation({0, 0.3, 0}));
  raw.add("tip", parent, DualQuaternion<double>::from_translation({0, 0.3, 0}), true);
  const KinematicModel chain = KinematicModel::ball_joints(*build_skeleton(raw));
  const int tip = chain.skeleton().find("tip");
  int fabrik_ok = 0;
  for (int k = 0; k < 100; ++k) {
    auto goal = random_parameters(chain, rng);
    for (std::size_t i = 0; i < 6; ++i) goal[i] = 0;  // the root stays
    const IkTask task = IkTask::reach(tip, frame_at(chain, goal, tip).translation());
    std::vector<double> q(chain.parameters(), 0.0);
    q[7] = 0.1;  // not perfectly straight
    if (fabrik(chain, task, q, {500, 1e-9}).status == IkStatus::converged) {
      ++fabrik_ok;
      EXPECT_LE(norm(frame_at(chain, q, tip).translation() - task.target.translation()), 1e-9);
    }
  }
  RecordProperty("fabrik_converged_of_100", std::to_string(fabrik_ok));
  EXPECT_GE(fabrik_ok, 95);
  std::vector<double> arm_q(7, 0.0);  // the arm has revolute joints, not a chain of balls
  EXPECT_EQ(fabrik(arm, IkTask::reach(flange, {0.3, 0, 0.5}), arm_q).status, IkStatus::invalid_input);
}

TEST(MotionCapture, ChannelModelReproducesTheBvhTransforms) {
  DQKIT_REQUIRE_MODELS();
  for (const char* file : {"01_01.bvh", "Boxing_Toes.bvh"}) {
    const Expected<BvhFile> bvh = read_bvh_file(test::assimp_models() / "BVH" / file);
    ASSERT_TRUE(bvh) << bvh.error().message;
    const Expected<BvhKinematics> kin = bvh_kinematics(*bvh);
    ASSERT_TRUE(kin) << kin.error().message;
    EXPECT_EQ(kin->model.parameters(), bvh->channel_count());
    const Skeleton& s = kin->model.skeleton();
    std::vector<double> q(kin->model.parameters());
    std::vector<DualQuaternion<double>> local(s.size());
    for (std::size_t f : {std::size_t{0}, bvh->frame_count / 2, bvh->frame_count - 1}) {
      kin->to_parameters(bvh->frame(f), q);
      local_transforms<DualQuaternion<double>, double>(kin->model, q, local);
      for (std::size_t j = 0; j < s.size(); ++j) {
        const DualQuaternion<double> want = bvh_local_transform(*bvh, static_cast<std::size_t>(s.raw_indices()[j]), f);
        EXPECT_TRUE(approx_equal(local[j], want, 1e-9 * (1 + norm(want.translation())), SignPolicy::same_rotation)) << file << " joint " << j;
      }
      // And back: writing every parameter reproduces the frame.
      std::vector<double> frame(bvh->channel_count(), 0.0);
      kin->to_frame(q, std::vector<std::uint8_t>(q.size(), 1), frame);
      for (std::size_t c = 0; c < frame.size(); ++c) EXPECT_NEAR(frame[c], bvh->frame(f)[c], 1e-12 * (1 + std::abs(frame[c])));
    }
  }
}

TEST(MotionCapture, FixFeetPinsContactsAndLeavesTheRestExactly) {
  DQKIT_REQUIRE_MODELS();
  const Expected<BvhFile> original = read_bvh_file(test::assimp_models() / "BVH" / "01_01.bvh");
  ASSERT_TRUE(original);
  BvhFile fixed = *original;
  const Expected<FixFeetReport> report = fix_foot_sliding(fixed);
  ASSERT_TRUE(report) << report.error().message;
  ASSERT_EQ(report->feet.size(), 2u);
  for (const FootContactReport& foot : report->feet) {
    EXPECT_FALSE(foot.contacts.empty()) << foot.joint;
    // Each contact is one pin held through it: the foot no longer slides (the capture's feet slid
    // 34 and 37 cm over their contacts; what is left is the solver's tolerance, 1e-9 of the leg).
    EXPECT_GT(foot.slide_before, 10.0) << foot.joint;
    EXPECT_LT(foot.slide_after, 1e-4) << foot.joint;
  }
  EXPECT_EQ(report->max_other_joint_motion, 0.0);
  EXPECT_LT(report->max_pin_error, 1e-4);  // centimetres: under a micrometre
  // Every channel outside the legs is bit for bit the same; leg channels changed.
  const Expected<BvhKinematics> kin = bvh_kinematics(*original);
  ASSERT_TRUE(kin);
  std::size_t changed = 0;
  for (std::size_t i = 0; i < kin->model.parameters(); ++i) {
    const Dof& d = kin->model.dofs()[i];
    const std::string& joint = kin->model.skeleton().names()[static_cast<std::size_t>(d.joint)];
    const bool in_leg = std::find(report->leg_joints.begin(), report->leg_joints.end(), joint) != report->leg_joints.end();
    for (std::size_t f = 0; f < original->frame_count; ++f) {
      const double a = original->frame(f)[kin->channel_of[i]], b = fixed.frame(f)[kin->channel_of[i]];
      if (!in_leg) {
        ASSERT_EQ(a, b) << joint << " frame " << f;
      } else {
        changed += a != b;
      }
    }
  }
  EXPECT_GT(changed, 0u);
  // The file written is valid BVH with the same hierarchy and channels.
  const Expected<BvhFile> back = read_bvh(write_bvh(fixed).value(), "fixed.bvh");
  ASSERT_TRUE(back) << back.error().message;
  EXPECT_EQ(back->joints.size(), original->joints.size());
  EXPECT_EQ(back->channel_count(), original->channel_count());
  // Unknown foot names are an error, not a guess.
  BvhFile copy = *original;
  FixFeetOptions named;
  named.feet = {"NoSuchToe"};
  const Expected<FixFeetReport> unknown = fix_foot_sliding(copy, named);
  ASSERT_FALSE(unknown);
  EXPECT_EQ(unknown.error().message, "no joint named 'NoSuchToe' for a foot");  // the library's words, not a CLI flag
  // Options out of range are errors, and the file is untouched.
  for (const auto& change : std::initializer_list<void (*)(FixFeetOptions&)>{
           [](FixFeetOptions& o) { o.height = std::nan(""); }, [](FixFeetOptions& o) { o.speed = HUGE_VAL; },
           [](FixFeetOptions& o) { o.min_contact_frames = 0; }, [](FixFeetOptions& o) { o.blend_frames = -1; }}) {
    FixFeetOptions options;
    change(options);
    EXPECT_FALSE(fix_foot_sliding(copy, options));
    EXPECT_EQ(copy.motion, original->motion);
  }
}

}  // namespace

// Inverse kinematics benchmarks: solves per second, success rate, iterations and the median time
// of one solve, for the 7-DOF arm and the 36-DOF biped with four effectors; dqkit's solver driven
// by dual quaternions and by 4x4 matrices, its Newton and Gauss–Seidel variants, and KDL's
// ChainIkSolverPos_LMA and ChainIkSolverPos_NR_JL on the same arm and the same targets, in the
// same binary. Success: the returned pose within the joint limits and within 1e-9 m and 1e-9 rad of
// the target (and, reported beside it, 1e-6), checked with dqkit's forward kinematics for every
// solver (not the solver's own report).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <kdl/chain.hpp>
#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl/chainiksolverpos_lma.hpp>
#include <kdl/chainiksolverpos_nr_jl.hpp>
#include <kdl/chainiksolvervel_pinv.hpp>
#include <numbers>
#include <random>
#include <vector>

#include "dq/ik/solver.hpp"

namespace {

using namespace dq;

constexpr double kTolerance = 1e-9;

struct Target {
  std::vector<DualQuaternion<double>> frames;  // one per effector
};

std::vector<double> random_parameters(const KinematicModel& m, std::mt19937_64& rng) {
  std::vector<double> q(m.parameters());
  for (std::size_t i = 0; i < q.size(); ++i) q[i] = std::uniform_real_distribution<double>(m.limits()[i].lower, m.limits()[i].upper)(rng);
  return q;
}

std::vector<DualQuaternion<double>> world_at(const KinematicModel& m, std::span<const double> q) {
  std::vector<DualQuaternion<double>> w(m.skeleton().size());
  model_transforms<DualQuaternion<double>, double>(m, q, w);
  return w;
}

/// Reachable targets: forward kinematics of random poses within the limits (fixed seed).
std::vector<Target> targets(const KinematicModel& m, std::span<const int> effectors, std::size_t count) {
  std::mt19937_64 rng(4242);
  std::vector<Target> out;
  for (std::size_t k = 0; k < count; ++k) {
    const auto w = world_at(m, random_parameters(m, rng));
    Target t;
    for (int e : effectors) t.frames.push_back(w[static_cast<std::size_t>(e)]);
    out.push_back(std::move(t));
  }
  return out;
}

bool reached(const KinematicModel& m, std::span<const double> q, std::span<const int> effectors, const Target& t,
             double tolerance = kTolerance, bool limits = true) {
  const auto w = world_at(m, q);
  for (std::size_t e = 0; e < effectors.size(); ++e) {
    const DualQuaternion<double>& got = w[static_cast<std::size_t>(effectors[e])];
    if (norm(got.translation() - t.frames[e].translation()) > tolerance) return false;
    if (angular_distance(got.real, t.frames[e].real) > tolerance) return false;
  }
  return !limits || m.within_limits(q, 1e-12);
}

/// Runs `solve(target, q)` over the target pool, one per benchmark iteration, timing each solve;
/// reports solves/s, the success rate, the mean iterations and the median time of one solve. Only
/// the solves are timed: their results are kept and checked after the loop (pausing the timers
/// every iteration would add a clock read of the process's CPU time, a system call, to each solve).
template <class Solve>
void run(benchmark::State& state, const KinematicModel& m, std::span<const int> effectors, const std::vector<Target>& pool, Solve solve) {
  const auto solves = static_cast<std::size_t>(state.max_iterations);
  std::vector<std::vector<double>> results(solves, std::vector<double>(m.parameters()));
  std::vector<double> times(solves);
  std::size_t k = 0;
  long iterations = 0;
  for (auto _ : state) {
    std::vector<double>& q = results[k];
    std::fill(q.begin(), q.end(), 0.0);
    const auto start = std::chrono::steady_clock::now();
    iterations += solve(pool[k % pool.size()], q);
    times[k++] = std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start).count();
  }
  std::size_t successes = 0, loose = 0, unlimited = 0;
  for (std::size_t i = 0; i < solves; ++i) {
    const Target& t = pool[i % pool.size()];
    successes += reached(m, results[i], effectors, t);
    loose += reached(m, results[i], effectors, t, 1e-6);
    unlimited += reached(m, results[i], effectors, t, kTolerance, false);
  }
  std::nth_element(times.begin(), times.begin() + static_cast<std::ptrdiff_t>(solves / 2), times.end());
  const auto total = static_cast<double>(solves);
  state.counters["success_rate"] = static_cast<double>(successes) / total;
  state.counters["success_1e-6"] = static_cast<double>(loose) / total;
  state.counters["success_ignoring_limits"] = static_cast<double>(unlimited) / total;
  state.counters["iterations"] = static_cast<double>(iterations) / total;
  state.counters["median_us"] = times[solves / 2];
  state.counters["solves_per_s"] = benchmark::Counter(total, benchmark::Counter::kIsRate);
}

const KinematicModel& arm() { return KinematicModel::arm7(); }
const std::vector<int>& arm_effector() {
  static const std::vector<int> e{arm().skeleton().find("flange")};
  return e;
}
const std::vector<Target>& arm_targets() {
  static const auto t = targets(arm(), arm_effector(), 2000);
  return t;
}

/// dqkit stops at 1e-9 m and 1e-9 rad, the success criterion (the default is 1e-10).
IkOptions same_tolerance() {
  IkOptions options;
  options.position_tolerance = kTolerance;
  options.orientation_tolerance = kTolerance;
  return options;
}

template <class Solver>
void ArmDqkit(benchmark::State& state, IkMethod method) {
  IkOptions options = same_tolerance();
  options.method = method;
  if (method == IkMethod::gauss_seidel) options.max_iterations = 400;
  Solver solver(arm(), options);
  run(state, arm(), arm_effector(), arm_targets(), [&](const Target& t, std::vector<double>& q) {
    const IkTask task = IkTask::frame(arm_effector()[0], t.frames[0]);
    return solver.solve(std::span(&task, 1), q).iterations;
  });
}
void ArmDualQuaternionLM(benchmark::State& s) { ArmDqkit<IkSolver>(s, IkMethod::levenberg_marquardt); }
void ArmMatrixLM(benchmark::State& s) { ArmDqkit<MatrixIkSolver>(s, IkMethod::levenberg_marquardt); }
void ArmDualQuaternionNewtonHyperDual(benchmark::State& s) { ArmDqkit<IkSolver>(s, IkMethod::newton); }
void ArmDualQuaternionGaussSeidel(benchmark::State& s) { ArmDqkit<IkSolver>(s, IkMethod::gauss_seidel); }

/// The same arm as a KDL chain: segment i is joint i (about z or y) followed by the offset to the
/// next joint, as in KinematicModel::arm7.
KDL::Chain kdl_arm() {
  KDL::Chain chain;
  const double to_next[] = {0.34, 0.0, 0.40, 0.0, 0.40, 0.0, 0.126};
  for (int j = 0; j < 7; ++j)
    chain.addSegment(KDL::Segment(KDL::Joint(j % 2 == 0 ? KDL::Joint::RotZ : KDL::Joint::RotY),
                                  KDL::Frame(KDL::Vector(0, 0, to_next[j]))));
  return chain;
}
/// KDL measures an orientation error with Rotation::GetRot, which reports no rotation at all when
/// the matrix is within KDL::epsilon (default 1e-6) of symmetric: a rotation error below about
/// 5e-7 rad reads as 0, and neither KDL solver could then converge to 1e-9 rad. The benchmark sets
/// it to 1e-12 (then GetRot's angle is exact to 3e-16 relative for angles from 1e-3 down to 1e-11, measured).
void see_small_rotations() { KDL::epsilon = 1e-12; }

/// A KDL joint angle in [−π, π]: LMA knows no limits and may return a turn more or less than a
/// joint can take; the same joint position one turn back counts (a user would wrap it too).
double wrapped(double angle) { return std::remainder(angle, 2 * std::numbers::pi); }

KDL::Frame to_kdl(const DualQuaternion<double>& f) {
  const Vec3<double> t = f.translation();
  return KDL::Frame(KDL::Rotation::Quaternion(f.real.x, f.real.y, f.real.z, f.real.w), KDL::Vector(t.x, t.y, t.z));
}

void ArmKdlLMA(benchmark::State& state) {
  const KDL::Chain chain = kdl_arm();
  // Unit weights on position and rotation (KDL's default weighs rotation by 0.01) and eps 1e-9 on
  // the norm of the 6-vector error (KDL's default is 1e-5): the same goal as dqkit's, a tolerance
  // at most √2 stricter (dqkit bounds each of the two norms by 1e-9).
  Eigen::Matrix<double, 6, 1> weights;
  weights.setOnes();
  see_small_rotations();
  KDL::ChainIkSolverPos_LMA solver(chain, weights, kTolerance, 500, 1e-15);
  KDL::JntArray q0(7), out(7);
  run(state, arm(), arm_effector(), arm_targets(), [&](const Target& t, std::vector<double>& q) {
    q0.data.setZero();
    solver.CartToJnt(q0, to_kdl(t.frames[0]), out);
    for (unsigned i = 0; i < 7; ++i) q[i] = wrapped(out(i));
    return solver.lastNrOfIter;
  });
}

void ArmKdlNRJL(benchmark::State& state) {
  const KDL::Chain chain = kdl_arm();
  KDL::JntArray lo(7), hi(7);
  for (unsigned i = 0; i < 7; ++i) lo(i) = arm().limits()[i].lower, hi(i) = arm().limits()[i].upper;
  KDL::ChainFkSolverPos_recursive fk(chain);
  KDL::ChainIkSolverVel_pinv vel(chain);
  see_small_rotations();
  KDL::ChainIkSolverPos_NR_JL solver(chain, lo, hi, fk, vel, 500, kTolerance);
  KDL::JntArray q0(7), out(7);
  run(state, arm(), arm_effector(), arm_targets(), [&](const Target& t, std::vector<double>& q) {
    q0.data.setZero();
    solver.CartToJnt(q0, to_kdl(t.frames[0]), out);
    for (unsigned i = 0; i < 7; ++i) q[i] = wrapped(out(i));
    return 0;  // NR_JL does not report its iterations
  });
}

const KinematicModel& biped() { return KinematicModel::biped(); }
const std::vector<int>& biped_effectors() {
  static const std::vector<int> e{biped().skeleton().find("left_foot"), biped().skeleton().find("right_foot"),
                                  biped().skeleton().find("left_hand"), biped().skeleton().find("right_hand")};
  return e;
}
const std::vector<Target>& biped_targets() {
  static const auto t = targets(biped(), biped_effectors(), 200);
  return t;
}
template <class Solver>
void BipedFourEffectors(benchmark::State& state) {
  Solver solver(biped(), same_tolerance());
  std::vector<IkTask> tasks(4);
  run(state, biped(), biped_effectors(), biped_targets(), [&](const Target& t, std::vector<double>& q) {
    for (std::size_t e = 0; e < 4; ++e) tasks[e] = IkTask::frame(biped_effectors()[e], t.frames[e]);
    return solver.solve(tasks, q).iterations;
  });
}

}  // namespace

BENCHMARK(ArmDualQuaternionLM)->Iterations(2000);
BENCHMARK(ArmMatrixLM)->Iterations(2000);
BENCHMARK(ArmDualQuaternionNewtonHyperDual)->Iterations(2000);
BENCHMARK(ArmDualQuaternionGaussSeidel)->Iterations(2000);
BENCHMARK(ArmKdlLMA)->Iterations(2000);
BENCHMARK(ArmKdlNRJL)->Iterations(2000);
BENCHMARK(BipedFourEffectors<IkSolver>)->Iterations(200);
BENCHMARK(BipedFourEffectors<MatrixIkSolver>)->Iterations(200);
BENCHMARK_MAIN();

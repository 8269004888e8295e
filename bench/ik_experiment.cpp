// The Kenwright paper's IK experiment (§10), reproduced: an arm, a leg and the 16-link biped follow
// a moving 6-DOF target along a path for thousands of frames, each frame warm-started from the
// last; per frame the position and orientation error, the iterations and the time of each solver,
// dual quaternions against 4x4 matrices. Writes a CSV (scripts/plot_ik.py draws docs/ik*.png from
// it) and prints the summary table of docs/ik.md.
//
//   ik_experiment [--frames N] [--csv FILE]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <initializer_list>
#include <numbers>
#include <string>
#include <vector>

#include "dq/ik/baselines.hpp"
#include "dq/ik/solver.hpp"

namespace {

using namespace dq;

struct Scenario {
  std::string name;
  const KinematicModel* model;
  int effector;
  std::vector<double> start;       // the first pose
  std::vector<std::uint8_t> free;  // parameters that move (in the path and in the solve)
  bool feet_planted = false;       // the biped: both feet held where they start (priority 0)
};

/// The path: forward kinematics of a smooth motion of the free parameters (each a sinusoid of its
/// own frequency, within its limits), so that every target is reachable, and moves in all six
/// degrees of freedom.
std::vector<double> pose_at(const Scenario& s, int f, int n) {
  std::vector<double> q = s.start;
  const double t = 2 * std::numbers::pi * f / n;
  for (std::size_t i = 0; i < q.size(); ++i) {
    if (!s.free[i]) continue;
    const ParameterLimits l = s.model->limits()[i];
    const double amplitude = 0.3 * std::min({q[i] - l.lower, l.upper - q[i], 0.8});
    q[i] += amplitude * std::sin(static_cast<double>(1 + i % 3) * t + 0.7 * static_cast<double>(i));
  }
  return q;
}

DualQuaternion<double> frame_of(const KinematicModel& m, std::span<const double> q, int joint) {
  std::vector<DualQuaternion<double>> w(m.skeleton().size());
  model_transforms<DualQuaternion<double>, double>(m, q, w);
  return w[static_cast<std::size_t>(joint)];
}

std::vector<std::uint8_t> parameters_named(const KinematicModel& m, std::initializer_list<const char*> names) {
  std::vector<std::uint8_t> free(m.parameters(), 0);
  for (const char* n : names) free[static_cast<std::size_t>(m.find_parameter(n))] = 1;
  return free;
}

struct Summary {
  double max_position = 0, max_orientation = 0, sum_iterations = 0, sum_us = 0;
  std::vector<double> us;
  int converged = 0, frames = 0;
};

}  // namespace

int main(int argc, char** argv) {
  int frames = 2000;
  std::string csv_path = "ik_experiment.csv";
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--frames") && i + 1 < argc) frames = std::max(1, std::atoi(argv[++i]));
    else if (!std::strcmp(argv[i], "--csv") && i + 1 < argc) csv_path = argv[++i];
    else {
      std::fprintf(stderr, "usage: ik_experiment [--frames N] [--csv FILE]\n");
      return 2;
    }
  }
  const KinematicModel& arm = KinematicModel::arm7();
  const KinematicModel& biped = KinematicModel::biped();
  const Skeleton& bs = biped.skeleton();
  std::vector<Scenario> scenarios;
  scenarios.push_back({"arm", &arm, arm.skeleton().find("flange"), {0.1, 0.5, 0.1, -1.2, 0.1, 0.6, 0.1},
                       std::vector<std::uint8_t>(7, 1), false});
  {
    // The leg alone: the left hip, knee and ankle move (6 DOF), the body stays as it is.
    std::vector<double> q(biped.parameters(), 0.0);
    q[static_cast<std::size_t>(biped.find_parameter("left_knee"))] = 0.6;
    q[static_cast<std::size_t>(biped.find_parameter("left_hip_flexion"))] = -0.4;
    q[static_cast<std::size_t>(biped.find_parameter("left_ankle_flexion"))] = -0.2;
    scenarios.push_back({"leg", &biped, bs.find("left_foot"), q,
                         parameters_named(biped, {"left_hip_flexion", "left_hip_twist", "left_hip_abduction", "left_knee",
                                                  "left_ankle_flexion", "left_ankle_inversion"}),
                         false});
  }
  {
    // The whole biped: the right hand follows a target made by the spine and right arm, while both
    // feet stay planted (priority 0) and every one of the 36 DOFs may move.
    std::vector<double> q(biped.parameters(), 0.0);
    q[static_cast<std::size_t>(biped.find_parameter("right_elbow"))] = -0.8;
    q[static_cast<std::size_t>(biped.find_parameter("right_shoulder_flexion"))] = 0.6;
    scenarios.push_back({"biped", &biped, bs.find("right_hand"), q,
                         parameters_named(biped, {"lumbar_flexion", "lumbar_twist", "lumbar_bend", "thoracic_flexion",
                                                  "right_shoulder_flexion", "right_shoulder_twist", "right_shoulder_abduction",
                                                  "right_elbow", "right_wrist"}),
                         true});
  }

  std::ofstream csv(csv_path);
  // (No field holds a comma or a quote: plain CSV.)
  csv << "scenario,solver,frame,tx,ty,tz,x,y,z,position_error,orientation_error,iterations,microseconds\n";
  std::printf("| scenario | solver | frames converged | max position error | max orientation error | mean iterations | median µs/frame |\n");
  std::printf("| --- | --- | --- | --- | --- | --- | --- |\n");
  for (const Scenario& s : scenarios) {
    IkOptions options;
    options.max_restarts = 0;  // tracking: stay with the warm start
    IkOptions gs = options;
    gs.method = IkMethod::gauss_seidel;
    gs.max_iterations = 400;
    IkSolver lm_dq(*s.model, options), gs_dq(*s.model, gs);
    MatrixIkSolver lm_matrix(*s.model, options);
    struct Entry {
      const char* name;
      std::vector<double> q;
      Summary summary;
    };
    std::vector<Entry> entries{{"LM (dual quaternions)", s.start, {}}, {"LM (4x4 matrices)", s.start, {}},
                               {"Gauss-Seidel (dual quaternions)", s.start, {}}, {"CCD (position only)", s.start, {}}};
    std::vector<IkTask> tasks;
    if (s.feet_planted) {
      for (const char* foot : {"left_foot", "right_foot"}) {
        const int j = s.model->skeleton().find(foot);
        tasks.push_back(IkTask::frame(j, frame_of(*s.model, s.start, j)));
      }
    } else {  // the arm and the leg move their own DOFs only
      for (auto* solver : {&lm_dq, &gs_dq}) solver->set_free_parameters(s.free);
      lm_matrix.set_free_parameters(s.free);
    }
    tasks.push_back({});
    const int priority = s.feet_planted ? 1 : 0;
    for (int f = 0; f < frames; ++f) {
      const DualQuaternion<double> target = frame_of(*s.model, pose_at(s, f, frames), s.effector);
      tasks.back() = IkTask::frame(s.effector, target);
      tasks.back().priority = priority;
      for (std::size_t e = 0; e < entries.size(); ++e) {
        Entry& en = entries[e];
        const auto t0 = std::chrono::steady_clock::now();
        IkResult r;
        if (e == 0) r = lm_dq.solve(tasks, en.q);
        if (e == 1) r = lm_matrix.solve(tasks, en.q);
        if (e == 2) {
          if (s.feet_planted) continue;  // Gauss–Seidel has no priority levels
          r = gs_dq.solve(tasks, en.q);
        }
        if (e == 3) {
          if (s.model != &arm) continue;  // CCD moves every DOF of the chain and holds no other task
          r = ccd(*s.model, IkTask::reach(s.effector, target.translation()), en.q, {50, 1e-10});
        }
        const double us = std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count();
        const DualQuaternion<double> got = frame_of(*s.model, en.q, s.effector);
        const double pe = norm(got.translation() - target.translation()), oe = angular_distance(got.real, target.real);
        Summary& sm = en.summary;
        sm.max_position = std::max(sm.max_position, pe);
        sm.max_orientation = std::max(sm.max_orientation, oe);
        sm.sum_iterations += r.iterations;
        sm.us.push_back(us);
        sm.converged += r.status == IkStatus::converged;
        ++sm.frames;
        const Vec3<double> tp = target.translation(), gp = got.translation();
        char line[512];
        std::snprintf(line, sizeof line, "%s,%s,%d,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.6g,%.6g,%d,%.3f\n", s.name.c_str(), en.name,
                      f, tp.x, tp.y, tp.z, gp.x, gp.y, gp.z, pe, oe, r.iterations, us);
        csv << line;
      }
    }
    for (Entry& en : entries) {
      Summary& sm = en.summary;
      if (sm.frames == 0) continue;
      std::nth_element(sm.us.begin(), sm.us.begin() + static_cast<std::ptrdiff_t>(sm.us.size() / 2), sm.us.end());
      std::printf("| %s | %s | %d / %d | %.2g m | %.2g rad | %.2f | %.1f |\n", s.name.c_str(), en.name, sm.converged, sm.frames,
                  sm.max_position, sm.max_orientation, sm.sum_iterations / sm.frames, sm.us[sm.us.size() / 2]);
    }
  }
  std::fprintf(stderr, "wrote %s\n", csv_path.c_str());
  return 0;
}

// Inverse kinematics on a KinematicModel: damped least squares / Levenberg–Marquardt with
// adaptive damping over weighted tasks in priority levels, box joint limits (never violated in
// the returned pose), a secondary objective in the null space, random restarts out of local
// minima; a Newton variant with exact second derivatives from HyperDual numbers; and the same
// solver driven by 4x4 matrices instead of dual quaternions (the seeds' comparison).
//
// A solver is configured once (model, options; it allocates its workspace then) and reused:
// `solve` allocates nothing, and reports its status and final errors.
#pragma once

#include <cstdint>
#include <memory>
#include <span>

#include "dq/ik/kinematic_model.hpp"

namespace dq {

enum class TaskKind {
  position,       ///< a point of the effector to a target point (3 rows)
  orientation,    ///< the effector's rotation to a target rotation (3 rows)
  pose,           ///< both (6 rows)
  aim,            ///< a local axis of the effector towards a target point (3 rows)
  point_on_line,  ///< a point of the effector onto a line (3 rows, rank 2)
};

/// Priority levels a solve may have (IkTask::priority 0 to 3), and tasks per solve.
inline constexpr int kIkPriorityLevels = 4;
inline constexpr std::size_t kIkMaxTasks = 64;

/// One goal for one effector joint. Targets must be unit dual quaternions to 1e-6 (data read as
/// float is accepted) and are normalized by the solve; axes and directions may have any non-zero
/// length.
struct IkTask {
  TaskKind kind = TaskKind::pose;
  int joint = -1;                   ///< the effector's runtime joint index
  Vec3<double> point{};             ///< the effector point (or pose origin) in the joint's frame
  DualQuaternion<double> target{};  ///< pose/orientation: the target frame; position: its translation
  Vec3<double> axis{0, 0, 1};       ///< aim: the local axis; point_on_line: the line's direction (world)
  Vec3<double> location{};          ///< aim: the point to look at; point_on_line: a point of the line
  double weight = 1;                ///< relative weight within its priority level
  int priority = 0;                 ///< 0 first (to kIkPriorityLevels − 1); level k is solved in the null space of levels < k

  static IkTask reach(int joint, const Vec3<double>& target, const Vec3<double>& point = {}) {
    IkTask t;
    t.kind = TaskKind::position, t.joint = joint, t.point = point, t.target = DualQuaternion<double>::from_translation(target);
    return t;
  }
  static IkTask frame(int joint, const DualQuaternion<double>& target, const Vec3<double>& point = {}) {
    IkTask t;
    t.kind = TaskKind::pose, t.joint = joint, t.point = point, t.target = target;
    return t;
  }
  static IkTask rotation(int joint, const Quaternion<double>& target) {
    IkTask t;
    t.kind = TaskKind::orientation, t.joint = joint, t.target = DualQuaternion<double>::from_rotation(target);
    return t;
  }
  static IkTask aim_at(int joint, const Vec3<double>& local_axis, const Vec3<double>& target, const Vec3<double>& point = {}) {
    IkTask t;
    t.kind = TaskKind::aim, t.joint = joint, t.axis = local_axis, t.location = target, t.point = point;
    return t;
  }
  static IkTask onto_line(int joint, const Vec3<double>& line_point, const Vec3<double>& direction, const Vec3<double>& point = {}) {
    IkTask t;
    t.kind = TaskKind::point_on_line, t.joint = joint, t.location = line_point, t.axis = direction, t.point = point;
    return t;
  }
};

constexpr std::size_t task_rows(TaskKind k) noexcept { return k == TaskKind::pose ? 6 : 3; }

enum class IkMethod {
  levenberg_marquardt,  ///< damped least squares with adaptive damping (the default)
  newton,               ///< Newton on ½ Σ w |r|², gradient and Hessian exact from HyperDual
  gauss_seidel,         ///< Kenwright's projected Gauss–Seidel on the damped normal equations (one priority level)
};

struct IkOptions {
  IkMethod method = IkMethod::levenberg_marquardt;
  int max_iterations = 100;              ///< per start
  int max_restarts = 10;                 ///< random restarts (within limits) out of local minima
  double position_tolerance = 1e-10;     ///< metres (model units)
  double orientation_tolerance = 1e-10;  ///< radians
  double initial_damping = 1e-3;         ///< λ of the first step, plus 0.1 × Σ w |r|² there (adapted after every step)
  double rest_weight = 0;                ///< secondary objective: pull towards `rest` in the null space
  std::uint64_t seed = 1;                ///< restarts are pseudo-random from this (reproducible)
  std::size_t max_rows = 36;             ///< the most task rows a solve may have (workspace size)
};

enum class IkStatus {
  converged,        ///< every task within its tolerance
  unreachable,      ///< no pose within tolerance was found: q is the closest one found
  iteration_limit,  ///< still improving when the iterations ran out: q is the best so far
  invalid_input,    ///< see IkResult::message; q untouched
};

struct IkResult {
  IkStatus status = IkStatus::invalid_input;
  int iterations = 0;              ///< in total, over all starts
  int restarts = 0;
  double position_error = 0;       ///< largest over position-like tasks (metres); NaN for invalid_input
  double orientation_error = 0;    ///< largest over orientation-like tasks (radians); NaN for invalid_input
  const char* message = "";        ///< for invalid_input: what is wrong
};

/// The solver over transform type X: DualQuaternion<double> (the default) or Mat4<double>.
template <class X>
class BasicIkSolver {
 public:
  BasicIkSolver(const KinematicModel& model, const IkOptions& options = {});
  ~BasicIkSolver();
  BasicIkSolver(BasicIkSolver&&) noexcept;
  BasicIkSolver& operator=(BasicIkSolver&&) noexcept;

  /// Solves for q (in: the initial pose; out: the solution, always within the limits). `rest`
  /// is the secondary objective's pose (empty: the initial pose). Invalid input (q or rest of the
  /// wrong size, a NaN, a target further than 1e-6 from unit, an axis of zero or infinite length,
  /// an effector that is not a joint, a priority beyond kIkPriorityLevels, more than kIkMaxTasks
  /// tasks or more rows than options.max_rows) gives IkStatus::invalid_input and leaves q
  /// untouched; targets and axes within those bounds are normalized. Allocates nothing.
  IkResult solve(std::span<const IkTask> tasks, std::span<double> q, std::span<const double> rest = {});

  /// Restricts later solves to some parameters (a flag per parameter, non-zero: may move); the
  /// others keep their input values (a leg solved alone, the rest of the body as captured).
  /// Empty: every parameter may move. Precondition: empty or one flag per parameter.
  void set_free_parameters(std::span<const std::uint8_t> free);

  const KinematicModel& model() const noexcept { return *model_; }
  const IkOptions& options() const noexcept { return options_; }

 private:
  struct Workspace;
  const KinematicModel* model_;
  IkOptions options_;
  std::unique_ptr<Workspace> ws_;
};

using IkSolver = BasicIkSolver<DualQuaternion<double>>;
using MatrixIkSolver = BasicIkSolver<Mat4<double>>;

extern template class BasicIkSolver<DualQuaternion<double>>;
extern template class BasicIkSolver<Mat4<double>>;

}  // namespace dq

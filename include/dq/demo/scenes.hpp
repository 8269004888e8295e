// What the three demo programs draw, frame by frame, with dqkit::render: the slider puzzle, the
// four viewports of the Arends thesis, the biped of the Kenwright paper following a target. Each
// frame is a list of views (scene, camera, viewport) for Renderer::draw; the programs draw them
// headless or in a window, and the tests project the expected objects with the same cameras.
#pragma once

#include <chrono>
#include <optional>
#include <string>
#include <vector>

#include "dq/demo/puzzle.hpp"
#include "dq/ik/solver.hpp"
#include "dq/render/render.hpp"

namespace dq::demo {

struct View {
  render::Scene scene;
  render::Camera camera;
  render::Viewport viewport;
};

/// The colour of the pieces whose home is on face f (0..5: +x, −x, +y, −y, +z, −z).
render::Color face_color(int face);

// ---- the slider puzzle -----------------------------------------------------------------------

/// A move in progress: the piece, its slots, and the fraction done.
struct PuzzleAnimation {
  PuzzleMove move;
  double t = 0;
};

/// The orbit camera of the puzzle for an image of this aspect (the cube framed).
render::Camera puzzle_camera(double aspect, double yaw = 0.6, double pitch = 0.45);
/// The pose of a piece as drawn: its pose, or during `animation` (if it is the moving piece)
/// move_motion(from, to, t) · pose before the move (`puzzle` is the state before the move).
DualQuaternion<double> drawn_pose(const Puzzle& puzzle, int piece, const std::optional<PuzzleAnimation>& animation);
/// The up direction of a piece's number, in the piece's frame (the number lies on local +x): in
/// the solved cube, world +y on the side faces, and on the top and bottom faces the horizontal axis
/// that reads upright from the default camera above (−z) and below (+z).
Vec3<double> number_up(int piece);
/// The pieces as slabs coloured by home face with their numbers drawn on their outer side, the
/// cube's edges as thin lines.
View puzzle_view(const Puzzle& puzzle, const std::optional<PuzzleAnimation>& animation, const render::Camera& camera,
                 render::Viewport viewport);
/// The piece whose outer side is under the pixel (x, y) of a viewport, the nearest to the camera,
/// or −1: picking by projecting each visible piece's outer square with render::project.
int pick_piece(const Puzzle& puzzle, const render::Camera& camera, int width, int height, double x, double y);

/// A scripted run: the state after a scramble, and the moves to animate (the solver's, if asked).
struct PuzzleScript {
  Puzzle start;
  std::vector<int> moves;
};
/// The state and the animated moves at frame `frame` of `frames` (the moves spread evenly over the
/// frames, the last frame at the end state).
struct PuzzleFrameState {
  Puzzle puzzle;
  std::optional<PuzzleAnimation> animation;
};
PuzzleFrameState puzzle_frame(const PuzzleScript& script, int frame, int frames);

// ---- the four viewports (Arends, chapter 6 and appendix) --------------------------------------

enum class Method { matrix, quaternion_slerp, dual_quaternion, hyper_dual_quaternion };
inline constexpr int method_count = 4;
const char* method_name(Method m);
render::Color method_color(Method m);

/// The thesis' animation state after `frame` calls of its animate(): rotate_angle (degrees, +1
/// per frame, wrapping after 360), translate (±0.01 per frame between −1 and 1), the SLERP
/// parameter t (+0.0175 per frame) and beginposition (the next quarter after each SLERP).
struct ViewportsState {
  double rotate_angle = 0, translate = 0, t = 0;
  int begin_position = 0;
};
ViewportsState viewports_state(int frame);
/// The base and tip of the moved vector (0, 0.9, 0), by each method.
struct Arrow {
  Vec3<double> base, tip;
};
Arrow move_vector(Method m, const ViewportsState& s);
/// Measures the time of one evaluation of move_vector by each method (nanoseconds, the median of
/// a few batches).
std::array<double, method_count> time_methods(const ViewportsState& s);
/// The camera of every viewport: looking down −z at the xy square the thesis draws in.
render::Camera viewports_camera(double aspect);
/// Upper left matrix, lower left quaternion with SLERP, upper right dual quaternion, lower right
/// hyper-dual quaternion, as in the thesis' listing; each with its name, its time per frame (if
/// given) and a note on the thesis' SLERP failures or its gimbal-lock claim.
std::vector<View> viewports_views(const ViewportsState& s, const std::array<double, method_count>* nanoseconds, int width,
                                  int height);

// ---- the biped following a target (Kenwright §10) ----------------------------------------------

/// The moving 6-DOF target of the right hand at time `seconds`.
DualQuaternion<double> biped_target(double seconds);

/// IK with dual quaternions and with matrices side by side, warm-started frame to frame, the
/// pelvis fixed; their errors recorded.
class BipedDemo {
 public:
  BipedDemo();
  /// Solves both for the target at `seconds`.
  void step(double seconds);
  const std::vector<double>& pose(bool matrices) const { return matrices ? q_matrix_ : q_dual_; }
  int effector() const noexcept { return effector_; }
  const DualQuaternion<double>& target() const noexcept { return target_; }
  /// The effector's frame for each solver's pose.
  DualQuaternion<double> effector_frame(bool matrices) const;
  /// Position errors (metres) of each step, dual quaternions then matrices.
  const std::vector<double>& errors(bool matrices) const { return matrices ? errors_matrix_ : errors_dual_; }
  /// The time of each step's solve (microseconds), dual quaternions then matrices.
  const std::vector<double>& solve_times(bool matrices) const { return matrices ? times_matrix_ : times_dual_; }
  /// The two side-by-side views (dual quaternions left, matrices right): the skeleton computed
  /// (green) over the ideal one whose hand made the target (red), the target frame (red), each error plotted over the steps (log scale).
  std::vector<View> views(int width, int height) const;
  /// The camera of both views.
  static render::Camera camera(double aspect);

 private:
  IkSolver dual_;
  MatrixIkSolver matrix_;
  std::vector<double> ideal_, q_dual_, q_matrix_;  ///< the pose that made the target; the solutions
  std::vector<double> errors_dual_, errors_matrix_, times_dual_, times_matrix_;
  DualQuaternion<double> target_;
  int effector_ = -1;
};

}  // namespace dq::demo

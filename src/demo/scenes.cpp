#include "dq/demo/scenes.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "dq/core/hyperdual_quaternion.hpp"
#include "dq/render/text.hpp"
#include "dq/interp/rotation.hpp"

namespace dq::demo {
namespace {

Vec3<float> to_float(const Vec3<double>& p) { return {float(p.x), float(p.y), float(p.z)}; }

render::Mesh slab(const DualQuaternion<double>& pose, render::Color color) {
  // The tutorial's slab, 0.4 thick, 3.9 wide (a small gap between neighbours), one quad per side.
  const double h = piece_thickness / 2, w = 1.95;
  render::Mesh m;
  m.color = color;
  const Vec3<double> axes[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const double extent[3] = {h, w, w};
  for (int a = 0; a < 3; ++a)
    for (int s : {1, -1}) {
      const Vec3<double> n = axes[a] * double(s);
      const Vec3<double> u = axes[(a + 1) % 3] * extent[(a + 1) % 3], v = axes[(a + 2) % 3] * extent[(a + 2) % 3];
      const Vec3<double> c = n * extent[a];
      const auto base = static_cast<std::uint32_t>(m.positions.size());
      for (const Vec3<double>& p : {c - u - v, c + u - v, c + u + v, c - u + v}) {
        m.positions.push_back(to_float(pose.transform_point(p)));
        m.normals.push_back(to_float(pose.real.rotate(n)));
      }
      if (s > 0) {
        m.triangles.insert(m.triangles.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
      } else {
        m.triangles.insert(m.triangles.end(), {base, base + 2, base + 1, base, base + 3, base + 2});
      }
    }
  return m;
}

std::string format(const char* f, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}

}  // namespace

render::Color face_color(int face) {
  static constexpr render::Color colors[6] = {{0.85f, 0.25f, 0.2f, 1}, {0.95f, 0.6f, 0.15f, 1}, {0.95f, 0.9f, 0.3f, 1},
                                              {0.3f, 0.75f, 0.3f, 1},  {0.25f, 0.45f, 0.9f, 1}, {0.7f, 0.45f, 0.85f, 1}};
  return colors[std::clamp(face, 0, 5)];
}

// ---- the puzzle ---------------------------------------------------------------------------------

render::Camera puzzle_camera(double aspect, double yaw, double pitch) {
  render::Bounds b;
  b.add({-6.6, -6.6, -6.6});
  b.add({6.6, 6.6, 6.6});
  render::Camera c = render::Camera::framing(b, aspect, yaw, pitch);
  c.distance *= 0.72;  // the box's corners may leave the view; the pieces (within 6.4 of the centre) do not
  return c;
}

DualQuaternion<double> drawn_pose(const Puzzle& puzzle, int piece, const std::optional<PuzzleAnimation>& animation) {
  if (animation && animation->move.piece == piece)
    return move_motion(animation->move.from, animation->move.to, animation->t) * puzzle.pose(piece);
  return puzzle.pose(piece);
}

Vec3<double> number_up(int piece) {
  // The default camera is at yaw 0.6 (from +z towards +x): its view's up on the top face is −z.
  static const Puzzle solved;
  const Vec3<double> n = slot_normal(piece);
  const Vec3<double> world_up = n.y > 0.5 ? Vec3<double>{0, 0, -1} : n.y < -0.5 ? Vec3<double>{0, 0, 1} : Vec3<double>{0, 1, 0};
  return solved.pose(piece).real.conjugate().rotate(world_up);
}

View puzzle_view(const Puzzle& puzzle, const std::optional<PuzzleAnimation>& animation, const render::Camera& camera,
                 render::Viewport viewport) {
  View v{{}, camera, viewport};
  render::Lines numbers;
  numbers.color = {0.05f, 0.05f, 0.05f, 1};
  for (int piece = 0; piece < puzzle_pieces; ++piece) {
    const DualQuaternion<double> pose = drawn_pose(puzzle, piece, animation);
    v.scene.meshes.push_back(slab(pose, face_color(piece / 4)));
    // The number on the picture side (local +x), upright in the solved cube as seen from the
    // default camera (number_up).
    const std::string label = (piece < 10 ? "0" : "") + std::to_string(piece);
    const double height = 1.5, width = render::text_width(label, height) - height / 6 * 1.5;
    const Vec3<double> up = number_up(piece), right = cross(up, Vec3<double>{1, 0, 0});
    std::vector<Vec3<float>> local;
    render::add_text(local, label, Vec3<double>{piece_thickness / 2 + 0.01, 0, 0} - right * (width / 2) - up * (height / 2), right, up,
             height);
    for (const Vec3<float>& p : local) numbers.points.push_back(to_float(pose.transform_point({p.x, p.y, p.z})));
  }
  v.scene.lines.push_back(std::move(numbers));
  return v;
}

int pick_piece(const Puzzle& puzzle, const render::Camera& camera, int width, int height, double x, double y) {
  int best = -1;
  double best_depth = 2;
  for (int piece = 0; piece < puzzle_pieces; ++piece) {
    const DualQuaternion<double> pose = puzzle.pose(piece);
    const Vec3<double> centre = pose.transform_point({piece_thickness / 2, 0, 0});
    if (dot(pose.real.rotate({1, 0, 0}), camera.eye() - centre) <= 0) continue;  // facing away
    render::Projected q[4];
    const double w = 1.95;
    const Vec3<double> corners[4] = {{0, -w, -w}, {0, w, -w}, {0, w, w}, {0, -w, w}};
    for (int i = 0; i < 4; ++i)
      q[i] = render::project(camera, width, height, pose.transform_point(corners[i] + Vec3<double>{piece_thickness / 2, 0, 0}));
    // Inside the convex quad: the same side of every edge.
    int positive = 0, negative = 0;
    for (int i = 0; i < 4; ++i) {
      const auto& a = q[i];
      const auto& b = q[(i + 1) % 4];
      const double c = (b.x - a.x) * (y - a.y) - (b.y - a.y) * (x - a.x);
      (c >= 0 ? positive : negative) += 1;
    }
    const double depth = render::project(camera, width, height, centre).depth;
    if ((positive == 4 || negative == 4) && depth < best_depth) best = piece, best_depth = depth;
  }
  return best;
}

PuzzleFrameState puzzle_frame(const PuzzleScript& script, int frame, int frames) {
  PuzzleFrameState s{script.start, std::nullopt};
  const auto total = static_cast<double>(script.moves.size());
  if (script.moves.empty()) return s;
  const double u = frames > 1 ? total * frame / (frames - 1) : total;
  const auto done = static_cast<std::size_t>(std::floor(u));
  for (std::size_t i = 0; i < std::min(done, script.moves.size()); ++i) s.puzzle.move(script.moves[i]);
  if (done < script.moves.size() && u > double(done))
    s.animation = PuzzleAnimation{*s.puzzle.move_of(script.moves[done]), u - double(done)};
  return s;
}

// ---- the four viewports -------------------------------------------------------------------------

const char* method_name(Method m) {
  switch (m) {
    case Method::matrix: return "ROTATION MATRIX";
    case Method::quaternion_slerp: return "QUATERNION WITH SLERP";
    case Method::dual_quaternion: return "DUAL QUATERNION";
    case Method::hyper_dual_quaternion: return "HYPER-DUAL QUATERNION";
  }
  return "";
}

render::Color method_color(Method m) {  // the thesis' red, green, blue, yellow (darkened for white)
  switch (m) {
    case Method::matrix: return {0.9f, 0.1f, 0.1f, 1};
    case Method::quaternion_slerp: return {0.1f, 0.7f, 0.1f, 1};
    case Method::dual_quaternion: return {0.1f, 0.2f, 0.95f, 1};
    case Method::hyper_dual_quaternion: return {0.8f, 0.65f, 0.0f, 1};
  }
  return {};
}

ViewportsState viewports_state(int frame) {
  ViewportsState s;
  bool moving_up = true;
  for (int i = 0; i < frame; ++i) {  // the thesis' animate()
    s.rotate_angle += 1;
    if (s.rotate_angle > 360) s.rotate_angle = 0;
    s.t += 0.0175;
    if (s.t > 1) {
      s.t = 0;
      s.begin_position = (s.begin_position + 1) % 4;
    }
    s.translate += moving_up ? 0.01 : -0.01;
    if (s.translate > 1) moving_up = false;
    if (s.translate < -1) moving_up = true;
  }
  return s;
}

Arrow move_vector(Method m, const ViewportsState& s) {
  const Vec3<double> v{0, 0.9, 0}, z{0, 0, 1}, up{0, s.translate, 0};
  const double angle = s.rotate_angle * std::numbers::pi / 180;
  switch (m) {
    case Method::matrix: {  // glTranslatef(0, translate, 0); glRotatef(rotate_angle, 0, 0, 1)
      const Mat3<double> r = Quaternion<double>::from_axis_angle(z, angle).to_matrix();
      return {up, up + Vec3<double>{r(0, 1) * 0.9, r(1, 1) * 0.9, r(2, 1) * 0.9}};
    }
    case Method::quaternion_slerp: {
      static constexpr double begin[4][2] = {{0.9, 0}, {0, 0.9}, {-0.9, 0}, {0, -0.9}};
      const Vec3<double> b{begin[s.begin_position][0], begin[s.begin_position][1], 0};
      const auto q = slerp(Quaternion<double>::identity(), Quaternion<double>::from_axis_angle(z, std::numbers::pi / 2), s.t);
      return {{0, 0, 0}, q.rotate(b)};
    }
    case Method::dual_quaternion:
      return {up, DualQuaternion<double>::from_rotation_translation(Quaternion<double>::from_axis_angle(z, angle), up).transform_point(v)};
    case Method::hyper_dual_quaternion:
      return {up, HyperDualQuaternion<double>::from_rotation_translation(Quaternion<double>::from_axis_angle(z, angle), up)
                      .transform_point(v)};
  }
  return {};
}

std::array<double, method_count> time_methods(const ViewportsState& s) {
  std::array<double, method_count> ns{};
  constexpr int repeats = 2000;
  for (int m = 0; m < method_count; ++m) {
    std::array<double, 5> batches{};
    for (double& b : batches) {
      ViewportsState varied = s;
      volatile double sink = 0;
      const auto t0 = std::chrono::steady_clock::now();
      for (int i = 0; i < repeats; ++i) {
        varied.rotate_angle = s.rotate_angle + i * 1e-6;  // no hoisting out of the loop
        sink = sink + move_vector(static_cast<Method>(m), varied).tip.x;
      }
      b = std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - t0).count() / repeats;
    }
    std::sort(batches.begin(), batches.end());
    ns[static_cast<std::size_t>(m)] = batches[2];
  }
  return ns;
}

render::Camera viewports_camera(double aspect) {
  render::Camera c;
  c.target = {0, 0, 0};
  c.yaw = 0;
  c.pitch = 0;
  c.fov_y = 0.7;
  c.distance = 2.25 / std::tan(c.fov_y / 2) / std::min(1.0, aspect);
  return c;
}

std::vector<View> viewports_views(const ViewportsState& s, const std::array<double, method_count>* nanoseconds, int width,
                                  int height) {
  const int w = width / 2, h = height / 2;
  const render::Viewport places[4] = {{0, 0, w, h}, {0, h, w, height - h}, {w, 0, width - w, h}, {w, h, width - w, height - h}};
  std::vector<View> views;
  const Arrow reference = move_vector(Method::matrix, s);
  for (int i = 0; i < method_count; ++i) {
    const auto m = static_cast<Method>(i);
    const render::Viewport vp = places[i];
    const double aspect = double(vp.width) / vp.height;
    View v{{}, viewports_camera(aspect), vp};
    const Arrow a = move_vector(m, s);
    render::Lines arrow;
    arrow.color = method_color(m);
    arrow.points = {to_float(a.base), to_float(a.tip)};
    v.scene.lines.push_back(arrow);
    render::Points tip;
    tip.color = method_color(m);
    tip.size = 9;
    tip.positions = {to_float(a.tip)};
    render::Points base;
    base.color = {0.5f, 0.5f, 0.5f, 1};
    base.positions = {to_float(a.base)};
    v.scene.points = {base, tip};
    render::Lines text;
    text.color = {0.1f, 0.1f, 0.1f, 1};
    render::add_overlay_text(text, v.camera, aspect, method_name(m), -0.95, 0.88, 0.07);
    if (nanoseconds) render::add_overlay_text(text, v.camera, aspect, format("%.1f NS PER EVALUATION", (*nanoseconds)[static_cast<std::size_t>(i)]), -0.95, 0.76, 0.06);
    switch (m) {
      case Method::matrix:  // the thesis' gimbal-lock claim, explained
        render::add_overlay_text(text, v.camera, aspect, "GLROTATE 90 Z THEN 45 Y ON (0 1 0):", -0.95, -0.78, 0.05);
        render::add_overlay_text(text, v.camera, aspect, "IT LIES ON THE Y AXIS: NO GIMBAL LOCK", -0.95, -0.9, 0.05);
        break;
      case Method::quaternion_slerp: {  // the thesis' SLERP failures, fixed
        const auto q = Quaternion<double>::from_axis_angle({1, 0, 0}, std::numbers::pi / 2);
        render::add_overlay_text(text, v.camera, aspect, format("SLERP(Q Q 0.5) NORM %.6f", slerp(q, q, 0.5).norm()), -0.95, -0.78, 0.05);
        render::add_overlay_text(text, v.camera, aspect, format("SLERP(Q -Q 0.5) NORM %.6f", slerp(q, -q, 0.5).norm()), -0.95, -0.9, 0.05);
        break;
      }
      case Method::dual_quaternion:
      case Method::hyper_dual_quaternion:
        render::add_overlay_text(text, v.camera, aspect, format("TIP - MATRIX TIP %.1e", norm(a.tip - reference.tip)), -0.95, -0.9, 0.05);
        break;
    }
    v.scene.lines.push_back(text);
    views.push_back(std::move(v));
  }
  return views;
}

// ---- the biped ------------------------------------------------------------------------------------

namespace {

int joint_named(const Skeleton& s, std::string_view name) {
  const auto names = s.names();
  for (std::size_t j = 0; j < names.size(); ++j)
    if (names[j] == name) return static_cast<int>(j);
  return -1;
}

bool drives_right_arm(const KinematicModel& model, const Dof& d) {
  const std::string_view n = model.skeleton().names()[static_cast<std::size_t>(d.joint)];
  return n == "right_upper_arm" || n == "right_forearm" || n == "right_hand";
}

/// The ideal pose at `seconds`: the right arm's parameters swinging within their limits.
std::vector<double> ideal_pose(double seconds) {
  const KinematicModel& model = KinematicModel::biped();
  std::vector<double> q(model.parameters(), 0.0);
  const auto dofs = model.dofs();
  for (std::size_t d = 0; d < dofs.size(); ++d) {
    if (!drives_right_arm(model, dofs[d])) continue;
    for (std::size_t k = 0; k < parameter_count(dofs[d].type); ++k) {
      const std::size_t i = model.offset(d) + k;
      const ParameterLimits l = model.limits()[i];
      const double mid = 0.5 * (l.lower + l.upper), half = 0.5 * (l.upper - l.lower);
      q[i] = mid + 0.45 * half * std::sin(0.9 * seconds * (1 + 0.3 * double(i % 4)) + double(i));
    }
  }
  return q;
}

template <class X>
std::vector<X> world_of(const std::vector<double>& q) {
  const KinematicModel& model = KinematicModel::biped();
  std::vector<X> w(model.skeleton().size());
  model_transforms<X, double>(model, q, w);
  return w;
}

render::Lines skeleton_lines(const std::vector<DualQuaternion<double>>& world, render::Color color) {
  render::Lines l;
  l.color = color;
  l.on_top = true;
  const auto parents = KinematicModel::biped().skeleton().parents();
  for (std::size_t j = 0; j < world.size(); ++j)
    if (parents[j] >= 0) {
      l.points.push_back(to_float(world[static_cast<std::size_t>(parents[j])].translation()));
      l.points.push_back(to_float(world[j].translation()));
    }
  return l;
}

void add_axes(render::Lines& l, const DualQuaternion<double>& frame, double length) {
  for (const Vec3<double>& a : {Vec3<double>{1, 0, 0}, Vec3<double>{0, 1, 0}, Vec3<double>{0, 0, 1}}) {
    l.points.push_back(to_float(frame.translation()));
    l.points.push_back(to_float(frame.transform_point(a * length)));
  }
}

IkOptions realtime_options() {
  IkOptions o;
  o.max_iterations = 60;
  o.max_restarts = 0;  // warm-started every frame
  o.position_tolerance = 1e-10;
  o.orientation_tolerance = 1e-10;
  return o;
}

}  // namespace

DualQuaternion<double> biped_target(double seconds) {
  const int hand = joint_named(KinematicModel::biped().skeleton(), "right_hand");
  return world_of<DualQuaternion<double>>(ideal_pose(seconds))[static_cast<std::size_t>(hand)];
}

BipedDemo::BipedDemo()
    : dual_(KinematicModel::biped(), realtime_options()),
      matrix_(KinematicModel::biped(), realtime_options()),
      q_dual_(KinematicModel::biped().parameters(), 0.0),
      q_matrix_(q_dual_),
      effector_(joint_named(KinematicModel::biped().skeleton(), "right_hand")) {
  const KinematicModel& model = KinematicModel::biped();
  std::vector<std::uint8_t> free(model.parameters(), 0);
  const auto dofs = model.dofs();
  for (std::size_t d = 0; d < dofs.size(); ++d)
    if (drives_right_arm(model, dofs[d]) || model.skeleton().names()[static_cast<std::size_t>(dofs[d].joint)] == "chest")
      for (std::size_t k = 0; k < parameter_count(dofs[d].type); ++k) free[model.offset(d) + k] = 1;
  dual_.set_free_parameters(free);
  matrix_.set_free_parameters(free);
}

void BipedDemo::step(double seconds) {
  ideal_ = ideal_pose(seconds);
  target_ = world_of<DualQuaternion<double>>(ideal_)[static_cast<std::size_t>(effector_)];
  const IkTask task = IkTask::frame(effector_, target_);
  auto timed = [&](auto& solver, std::vector<double>& q, std::vector<double>& errors, std::vector<double>& times) {
    const auto t0 = std::chrono::steady_clock::now();
    errors.push_back(solver.solve({&task, 1}, q).position_error);
    times.push_back(std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count());
  };
  timed(dual_, q_dual_, errors_dual_, times_dual_);
  timed(matrix_, q_matrix_, errors_matrix_, times_matrix_);
}

DualQuaternion<double> BipedDemo::effector_frame(bool matrices) const {
  return world_of<DualQuaternion<double>>(pose(matrices))[static_cast<std::size_t>(effector_)];
}

render::Camera BipedDemo::camera(double aspect) {
  render::Bounds b;
  b.add({-1.0, 0.0, -0.6});
  b.add({0.6, 1.9, 0.6});
  return render::Camera::framing(b, aspect, -0.5, 0.2);
}

std::vector<View> BipedDemo::views(int width, int height) const {
  std::vector<View> out;
  const auto places = render::columns(width, height, 2);
  const std::string ideal_note = "RED IDEAL  GREEN COMPUTED";
  for (int side = 0; side < 2; ++side) {
    const bool matrices = side == 1;
    const render::Viewport vp = places[static_cast<std::size_t>(side)];
    const double aspect = double(vp.width) / vp.height;
    View v{{}, camera(aspect), vp};
    const render::Color red{0.9f, 0.1f, 0.1f, 1}, green{0.1f, 0.65f, 0.1f, 1};
    if (!ideal_.empty()) v.scene.lines.push_back(skeleton_lines(world_of<DualQuaternion<double>>(ideal_), red));
    v.scene.lines.push_back(skeleton_lines(world_of<DualQuaternion<double>>(pose(matrices)), green));
    render::Lines axes;
    axes.color = red;
    axes.on_top = true;
    add_axes(axes, target_, 0.12);
    render::Lines computed_axes;
    computed_axes.color = green;
    computed_axes.on_top = true;
    const DualQuaternion<double> effector = effector_frame(matrices);
    add_axes(computed_axes, effector, 0.08);
    v.scene.lines.push_back(axes);
    v.scene.lines.push_back(computed_axes);
    v.scene.points.push_back({{to_float(target_.translation())}, red, 16, true});
    v.scene.points.push_back({{to_float(effector.translation())}, green, 6, true});
    // The floor, for depth.
    render::Mesh floor;
    floor.color = {0.85f, 0.85f, 0.88f, 1};
    floor.positions = {{-1.2f, 0.07f, -0.8f}, {0.8f, 0.07f, -0.8f}, {0.8f, 0.07f, 0.8f}, {-1.2f, 0.07f, 0.8f}};
    floor.triangles = {0, 2, 1, 0, 3, 2};
    v.scene.meshes.push_back(floor);
    // Labels and the error plot (log10 of the position error, −16 to 0, the last 150 steps).
    render::Lines text;
    text.color = {0.1f, 0.1f, 0.1f, 1};
    text.on_top = true;
    render::add_overlay_text(text, v.camera, aspect, matrices ? "IK WITH MATRICES" : "IK WITH DUAL QUATERNIONS", -0.95, 0.9, 0.06);
    render::add_overlay_text(text, v.camera, aspect, ideal_note, -0.95, 0.8, 0.045);
    const auto& e = errors(matrices);
    if (!e.empty()) render::add_overlay_text(text, v.camera, aspect, format("POSITION ERROR %.1e M", e.back()), -0.95, 0.72, 0.045);
    render::Lines plot;
    plot.color = green;
    plot.on_top = true;
    const double x0 = -0.9, x1 = 0.9, y0 = -0.95, y1 = -0.6;
    for (const auto& [a, b] : {std::pair{Vec3<double>{x0, y0, 0}, Vec3<double>{x1, y0, 0}}, std::pair{Vec3<double>{x0, y0, 0}, Vec3<double>{x0, y1, 0}}}) {
      text.points.push_back(to_float(render::overlay_point(v.camera, aspect, a.x, a.y)));
      text.points.push_back(to_float(render::overlay_point(v.camera, aspect, b.x, b.y)));
    }
    render::add_overlay_text(text, v.camera, aspect, "LOG10 ERR", x0 + 0.02, y1 - 0.05, 0.035);
    for (const int tick : {0, -8, -16}) {  // the scale of the y axis: ticks and their values left of it
      const double y = y0 + (y1 - y0) * (tick + 16) / 16.0;
      text.points.push_back(to_float(render::overlay_point(v.camera, aspect, x0 - 0.012, y)));
      text.points.push_back(to_float(render::overlay_point(v.camera, aspect, x0, y)));
      render::add_overlay_text(text, v.camera, aspect, std::to_string(tick), -0.99, y - 0.014, 0.028);
    }
    const std::size_t n = std::min<std::size_t>(e.size(), 150), first = e.size() - n;
    auto plot_point = [&](std::size_t i) {
      const double l = std::clamp(std::log10(std::max(e[first + i], 1e-16)), -16.0, 0.0);
      return to_float(render::overlay_point(v.camera, aspect, x0 + (x1 - x0) * double(i) / 149, y0 + (y1 - y0) * (l + 16) / 16));
    };
    for (std::size_t i = 1; i < n; ++i) {
      plot.points.push_back(plot_point(i - 1));
      plot.points.push_back(plot_point(i));
    }
    v.scene.lines.push_back(text);
    v.scene.lines.push_back(plot);
    out.push_back(std::move(v));
  }
  return out;
}

}  // namespace dq::demo

// dqkit fk: each joint's transform per frame (world or parent-relative), streamed as CSV or JSON.
#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <unordered_map>

#include "commands.hpp"
#include "common.hpp"
#include "dq/anim/forward_kinematics.hpp"
#include "dq/convert/euler.hpp"

namespace dq::cli {

namespace {

struct FkArgs {
  InputOptions input;
  std::optional<std::string> frames;  ///< "0,1,100", "0:100:2", mixed; none: frame 0
  bool all = false;
  std::function<std::string(const std::string&)> format;
  std::string output;  ///< empty or "-": standard output
  bool force = false;
  std::string space = "world";
  std::string rotation = "quaternion";
  std::string euler_order = "ZXY";
  bool degrees = false;
  bool euler_order_given = false;
  std::vector<std::string> joints;  ///< empty: every joint
  double scale = 1;
  bool time = false, parents = false;
};

const std::vector<std::string> kOrders{"XYZ", "XZY", "YXZ", "YZX", "ZXY", "ZYX", "XYX", "XZX", "YXY", "YZY", "ZXZ", "ZYZ"};

EulerOrder order_named(const std::string& s) {
  for (EulerOrder o : all_euler_orders)
    if (to_string(o) == s) return o;
  throw Failure("--euler-order: '" + s + "' is not an Euler order");  // unreachable: CLI11 checks
}

std::vector<std::size_t> selected_joints(const Skeleton& s, const std::vector<std::string>& names) {
  std::vector<std::size_t> out;
  if (names.empty()) {
    for (std::size_t j = 0; j < s.size(); ++j) out.push_back(j);
    return out;
  }
  std::unordered_map<std::string_view, std::size_t> index;
  for (std::size_t j = 0; j < s.size(); ++j) index.emplace(s.names()[j], j);
  for (const std::string& n : names) {
    const auto it = index.find(n);
    if (it == index.end()) throw Failure("--joint: the file has no joint named '" + n + "' (dqkit info lists them)");
    if (std::find(out.begin(), out.end(), it->second) != out.end()) throw Failure("--joint: '" + n + "' is given twice");
    out.push_back(it->second);
  }
  return out;
}

int run_fk(const FkArgs& args) {
  const std::string format = args.format(args.output);  // refusals before the work
  if (args.degrees && args.rotation != "euler") throw Failure("--degrees applies to Euler angles: add --rotation euler");
  if (args.euler_order_given && args.rotation != "euler") throw Failure("--euler-order applies to Euler angles: add --rotation euler");
  const Motion m = load(args.input);
  const Skeleton& s = m.skeleton;
  const Animation& a = m.animation;
  const std::size_t frame_count = a.frame_count ? a.frame_count : 1;  // no animation: the rest pose as frame 0
  std::vector<std::size_t> frames;
  if (args.all) {
    for (std::size_t f = 0; f < frame_count; ++f) frames.push_back(f);
  } else if (!args.frames) {
    frames.push_back(0);
  } else {
    std::string error;
    frames = parse_frame_list(*args.frames, frame_count, error);
    if (!error.empty()) throw Failure(error);
  }
  const std::vector<std::size_t> joints = selected_joints(s, args.joints);
  Output out(args.output, args.force, {args.input.file});

  const bool csv = format == "csv", world = args.space == "world";
  const EulerOrder order = order_named(args.euler_order);
  const auto axes = euler_axes(order);
  const double angle_unit = args.degrees ? 180 / std::numbers::pi : 1;
  const std::vector<DualQuaternion<double>> rest(s.rest_pose().begin(), s.rest_pose().end());
  std::vector<DualQuaternion<double>> model(s.size());
  std::array<double, 9> r{};  // the rotation's numbers in the chosen form
  auto rotation_numbers = [&](const Quaternion<double>& q) -> std::size_t {
    if (args.rotation == "matrix") {
      const Mat3<double> mat = q.to_matrix();
      for (int row = 0; row < 3; ++row)
        for (int col = 0; col < 3; ++col) r[static_cast<std::size_t>(3 * row + col)] = mat(row, col);
      return 9;
    }
    if (args.rotation == "euler") {
      const EulerAngles<double> e = to_euler(q, order, EulerFrame::intrinsic).angles;
      r = {e.a * angle_unit, e.b * angle_unit, e.c * angle_unit};
      return 3;
    }
    const Quaternion<double> c = q.canonical();
    r = {c.w, c.x, c.y, c.z};
    return 4;
  };

  std::string t;
  if (csv) {
    t = args.time ? "frame,time,joint" : "frame,joint";
    if (args.parents) t += ",index,parent";
    t += ",x,y,z";
    if (args.rotation == "matrix") {
      t += ",r00,r01,r02,r10,r11,r12,r20,r21,r22";
    } else if (args.rotation == "euler") {
      for (int k = 0; k < 3; ++k) t += std::string(",") + "xyz"[axes[static_cast<std::size_t>(k)]] + std::to_string(k + 1);
    } else {
      t += ",qw,qx,qy,qz";
    }
    t += "\r\n";
  } else {
    t = "{\"file\":";
    append_json_string(t, args.input.file);
    t += ",\"space\":\"" + args.space + "\",\"rotation\":\"" + args.rotation + "\"";
    if (args.rotation == "euler")
      t += ",\"euler_order\":\"" + args.euler_order + "\",\"euler_frame\":\"intrinsic\",\"angle_unit\":\"" +
           (args.degrees ? "degrees" : "radians") + "\"";
    t += ",\"scale\":";
    append_number(t, args.scale);
    t += ",\"frame_time\":";
    append_number(t, a.frame_time);
    t += ",\"frames\":[";
  }
  Progress progress("dqkit fk: frame", frames.size());
  for (std::size_t i = 0; i < frames.size(); ++i) {
    progress.update(i);
    const std::size_t f = frames[i];
    const std::span<const DualQuaternion<double>> local = a.frame_count ? a.frame(f) : std::span<const DualQuaternion<double>>(rest);
    if (world) local_to_model<DualQuaternion<double>>(s, local, model);
    const std::span<const DualQuaternion<double>> shown = world ? std::span<const DualQuaternion<double>>(model) : local;
    const double time = static_cast<double>(f) * a.frame_time;
    if (!csv) {
      t += i ? ",\n{\"frame\":" : "\n{\"frame\":";
      t += std::to_string(f) + ",\"time\":";
      append_number(t, time);
      t += ",\"joints\":[";
    }
    for (std::size_t k = 0; k < joints.size(); ++k) {
      const std::size_t j = joints[k];
      const Vec3<double> p = shown[j].translation() * args.scale;
      const std::size_t n = rotation_numbers(shown[j].real);
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z) ||
          !std::all_of(r.begin(), r.begin() + static_cast<std::ptrdiff_t>(n), [](double v) { return std::isfinite(v); }))
        throw Failure(args.input.file + ": frame " + std::to_string(f) + ", joint '" + s.names()[j] + "': the transform is not finite (its lengths" +
                      (args.scale != 1 ? " times --scale" : "") + " overflow a double); nothing is written to a file");
      if (csv) {
        t += std::to_string(f);
        if (args.time) (t += ','), append_number(t, time);
        t += ',';
        append_csv_field(t, s.names()[j]);
        if (args.parents) t += "," + std::to_string(j) + "," + std::to_string(s.parents()[j]);
        for (double v : {p.x, p.y, p.z}) (t += ','), append_number(t, v);
        for (std::size_t c = 0; c < n; ++c) (t += ','), append_number(t, r[c]);
        t += "\r\n";
      } else {
        t += k ? ",{\"joint\":" : "{\"joint\":";
        append_json_string(t, s.names()[j]);
        t += ",\"index\":" + std::to_string(j) + ",\"parent\":" + std::to_string(s.parents()[j]) + ",\"position\":[";
        append_number(t, p.x);
        (t += ','), append_number(t, p.y);
        (t += ','), append_number(t, p.z);
        t += args.rotation == "matrix" ? "],\"matrix\":[" : args.rotation == "euler" ? "],\"euler\":[" : "],\"rotation\":[";
        for (std::size_t c = 0; c < n; ++c) {
          if (c) t += ',';
          if (n == 9 && c % 3 == 0) t += '[';
          append_number(t, r[c]);
          if (n == 9 && c % 3 == 2) t += ']';
        }
        t += "]}";
      }
      if (t.size() >= (1u << 16)) out.write(std::exchange(t, {}));
    }
    if (!csv) t += "]}";
  }
  if (!csv) t += "\n]}\n";
  out.write(t);
  out.finish();
  return 0;
}

}  // namespace

Runner define_fk(CLI::App& c) {
  auto args = std::make_shared<FkArgs>();
  add_input_options(c, args->input);
  auto* frames = c.add_option("--frames", args->frames,
                              "Frames, from 0: numbers and Python slices start:stop:step (stop exclusive, negative from the end), "
                              "comma-separated and mixable, e.g. 0,10:20,::5 (default: 0)");
  c.add_flag("--all", args->all, "Every frame")->excludes(frames);
  args->format = add_format_option(c, {"csv", "json"}, "Output format: csv (RFC 4180) or json");
  c.add_option("-o,--output", args->output, "Write to this file instead of standard output (- for standard output)")->check(file_name());
  c.add_flag("--force", args->force, "Replace the output file if it exists (a regular file only)");
  c.add_option("--space", args->space, "world (model space) or local (relative to the parent)")->check(CLI::IsMember({"world", "local"}));
  c.add_option("--rotation", args->rotation, "quaternion (w x y z, w >= 0), matrix (3x3, row by row) or euler")
      ->check(CLI::IsMember({"quaternion", "matrix", "euler"}));
  CLI::Option* order = c.add_option("--euler-order", args->euler_order, "Intrinsic Euler sequence for --rotation euler (default ZXY)")
                           ->check(CLI::IsMember(kOrders));
  c.add_flag("--degrees", args->degrees, "Euler angles in degrees (default radians)");
  c.add_option("--joint", args->joints, "Only this joint (repeat for several; default every joint)")->allow_extra_args(false);
  c.add_option("--scale", args->scale, "Multiply positions by this (unit conversion, e.g. 0.01 for cm to m)")->check(finite_in(0, 1e12));
  c.add_flag("--time", args->time, "CSV: add a time column (seconds)");
  c.add_flag("--parents", args->parents, "CSV: add the joint's index and its parent's index (-1 for a root)");
  return [args, order] {
    args->euler_order_given = order->count() > 0;
    return run_fk(*args);
  };
}

}  // namespace dq::cli

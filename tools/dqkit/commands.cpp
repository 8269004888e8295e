#include "commands.hpp"

#include <charconv>
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>

#include "dq/anim/forward_kinematics.hpp"
#include "dq/io/file.hpp"
#include "dq/io/motion.hpp"
#ifdef DQKIT_HAVE_IMPORT
#include "dq/io/scene.hpp"
#endif

namespace dq::cli {

namespace {

int fail(const std::string& message) {
  std::fprintf(stderr, "dqkit: %s\n", message.c_str());
  return 1;
}

void print_warnings(const std::vector<std::string>& warnings) {
  for (const std::string& w : warnings) std::fprintf(stderr, "dqkit: warning: %s\n", w.c_str());
}

std::optional<EulerOrder> parse_order(const std::string& s) {
  for (EulerOrder o : all_euler_orders)
    if (to_string(o) == s) return o;
  return std::nullopt;
}

/// Writes to stdout, or safely to a file.
int emit(const std::string& text, const std::string& output, bool force) {
  if (output.empty()) {
    std::fwrite(text.data(), 1, text.size(), stdout);
    return std::fflush(stdout) == 0 ? 0 : fail("cannot write to standard output");
  }
  const Status s = write_file_atomically(output, text, force ? Overwrite::allow : Overwrite::refuse);
  return s ? 0 : fail(s.error().message);
}

std::string number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

}  // namespace

std::vector<std::size_t> parse_frame_list(const std::string& text, std::size_t count, std::string& error) {
  std::vector<std::size_t> out;
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t comma = std::min(text.find(',', start), text.size());
    std::string item = text.substr(start, comma - start);
    while (!item.empty() && item.front() == ' ') item.erase(item.begin());
    while (!item.empty() && item.back() == ' ') item.pop_back();
    std::size_t v = 0;
    const auto [end, ec] = std::from_chars(item.data(), item.data() + item.size(), v);
    if (item.empty() || ec != std::errc() || end != item.data() + item.size()) {
      error = "--frames: '" + item + "' is not a frame number";
      return {};
    }
    if (v >= count) {
      error = "--frames: frame " + item + " out of range (the file has " + std::to_string(count) + " frames, numbered from 0)";
      return {};
    }
    out.push_back(v);
    start = comma + 1;
  }
  return out;
}

namespace {
/// Loads a motion file with the common options and prints its warnings.
Expected<Motion> load(const std::string& file, std::size_t animation, double import_timeout, double rate = 30) {
#ifdef DQKIT_HAVE_IMPORT
  MotionOptions options;
  options.animation = animation;
  options.import_timeout = import_timeout;
  options.sample_rate = rate;
  Expected<Motion> m = import_motion(file, options);
#else
  (void)animation, (void)import_timeout, (void)rate;  // for imported formats, which this build does not read
  Expected<Motion> m = load_motion(file);
#endif
  if (m) print_warnings(m->warnings);
  return m;
}
}  // namespace

int info(const InfoArgs& args) {
  const Expected<Motion> m = load(args.file, args.animation, args.import_timeout);
  if (!m) return fail(m.error().message);
  const Skeleton& s = m->skeleton;
  std::size_t end_sites = 0;
  for (std::size_t j = 0; j < s.size(); ++j) end_sites += s.is_end_site(j);
  std::ostringstream out;
  out << "file: " << args.file << " (" << m->format << ")\n";
  out << "joints: " << s.size() << " (" << end_sites << " end sites)\n";
  if (m->bvh) out << "channels: " << m->bvh->channel_count() << "\n";
  const Animation& a = m->animation;
  out << "animations: " << m->animation_count << "\n";
  out << "frames: " << a.frame_count << ", frame time " << a.frame_time << " s (" << (a.frame_time > 0 ? 1 / a.frame_time : 0)
      << " Hz), duration " << a.duration() << " s\n";
  if (m->scene) {
    std::size_t skinned = 0, vertices = 0;
    for (const ImportedMesh& mesh : m->scene->meshes) {
      skinned += !mesh.influences.empty();
      vertices += mesh.positions.size();
    }
    out << "meshes: " << m->scene->meshes.size() << " (" << skinned << " skinned, " << vertices << " vertices)\n";
    for (std::size_t i = 0; i < m->scene->animations.size(); ++i)
      out << "animation " << i << ": '" << m->scene->animations[i].name << "', " << m->scene->animations[i].animation.frame_count
          << " frames resampled\n";
  }
  out << "hierarchy:\n";
  std::vector<int> depth(s.size(), 0);
  for (std::size_t j = 0; j < s.size(); ++j) {
    const int p = s.parents()[j];
    depth[j] = p < 0 ? 0 : depth[static_cast<std::size_t>(p)] + 1;
    out << std::string(2 + 2 * static_cast<std::size_t>(depth[j]), ' ') << s.names()[j];
    if (m->bvh) {
      const BvhJoint& b = m->bvh->joints[static_cast<std::size_t>(s.raw_indices()[j])];
      if (b.end_site) {
        out << " (End Site)";
      } else {
        out << " [";
        for (std::size_t k = 0; k < b.channels.size(); ++k) out << (k ? " " : "") << to_string(b.channels[k]);
        out << "]";
      }
    }
    out << "\n";
  }
  const std::string text = out.str();
  std::fwrite(text.data(), 1, text.size(), stdout);
  return 0;
}

int fk(const FkArgs& args) {
  const Expected<Motion> m = load(args.file, args.animation, args.import_timeout);
  if (!m) return fail(m.error().message);
  const Skeleton& s = m->skeleton;
  const Animation& a = m->animation;
  // A file without animation has one frame: the rest pose.
  std::vector<DualQuaternion<double>> rest(s.rest_pose().begin(), s.rest_pose().end());
  const std::size_t frame_count = a.frame_count ? a.frame_count : 1;
  std::vector<std::size_t> frames;
  if (args.all) {
    for (std::size_t f = 0; f < frame_count; ++f) frames.push_back(f);
  } else if (args.frames.empty()) {
    frames.push_back(0);
  } else {
    std::string error;
    frames = parse_frame_list(args.frames, frame_count, error);
    if (!error.empty()) return fail(error);
  }
  std::vector<DualQuaternion<double>> model(s.size());
  std::string text;
  nlohmann::json json;
  if (args.format == "csv") {
    text = "frame,joint,x,y,z,qw,qx,qy,qz\n";
  } else {
    json["file"] = args.file;
    json["frame_time"] = a.frame_time;
    json["frames"] = nlohmann::json::array();
  }
  for (std::size_t f : frames) {
    const std::span<const DualQuaternion<double>> local = a.frame_count ? a.frame(f) : std::span<const DualQuaternion<double>>(rest);
    local_to_model<DualQuaternion<double>>(s, local, model);
    nlohmann::json joints = nlohmann::json::array();
    for (std::size_t j = 0; j < s.size(); ++j) {
      const Vec3<double> p = model[j].translation();
      const Quaternion<double> q = model[j].real.canonical();
      if (args.format == "csv") {
        text += std::to_string(f) + "," + s.names()[j] + "," + number(p.x) + "," + number(p.y) + "," + number(p.z) + "," + number(q.w) +
                "," + number(q.x) + "," + number(q.y) + "," + number(q.z) + "\n";
      } else {
        joints.push_back({{"joint", s.names()[j]}, {"position", {p.x, p.y, p.z}}, {"rotation", {q.w, q.x, q.y, q.z}}});
      }
    }
    if (args.format == "json") json["frames"].push_back({{"frame", f}, {"time", static_cast<double>(f) * a.frame_time}, {"joints", joints}});
  }
  if (args.format == "json") text = json.dump(1) + "\n";
  return emit(text, args.output, args.force);
}

int convert(const ConvertArgs& args) {
  std::string ext = std::filesystem::path(args.output).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (ext != ".bvh") return fail(args.output + ": only BVH output is supported (the file name must end in .bvh)");
  std::error_code ec;
  if (std::filesystem::exists(args.output, ec) && std::filesystem::equivalent(args.input, args.output, ec))
    return fail(args.output + ": is the input file; write to another file");
  const Expected<Motion> m = load(args.input, args.animation, args.import_timeout, args.rate);
  if (!m) return fail(m.error().message);
  std::optional<EulerOrder> order;
  if (!args.rotation_order.empty()) order = parse_order(args.rotation_order);
  BvhFile out = m->bvh ? (order ? with_rotation_order(*m->bvh, *order) : *m->bvh)
                       : to_bvh(m->skeleton, m->animation, order.value_or(EulerOrder::ZXY));
  return emit(write_bvh(out), args.output, args.force);
}

}  // namespace dq::cli

// dqkit info: what a motion file holds, as text or JSON.
#include <memory>
#include <sstream>

#include "commands.hpp"
#include "common.hpp"

namespace dq::cli {

namespace {

struct InfoArgs {
  InputOptions input;
  std::function<std::string(const std::string&)> format;
  std::string output;
  bool force = false;
};

constexpr std::size_t kMaxIndent = 32;  // deeper levels say their depth: the text stays linear

std::string channels_of(const BvhJoint& b) {
  std::string s;
  for (std::size_t k = 0; k < b.channels.size(); ++k) (s += k ? " " : "") += to_string(b.channels[k]);
  return s;
}

int run_info(const InfoArgs& args) {
  const std::string format = args.format(args.output);  // refusals before the work
  const Motion m = load(args.input);
  Output out(args.output, args.force, {args.input.file});
  const Skeleton& s = m.skeleton;
  const Animation& a = m.animation;
  std::size_t end_sites = 0;
  for (std::size_t j = 0; j < s.size(); ++j) end_sites += s.is_end_site(j);
  std::size_t skinned = 0, vertices = 0;
  if (m.scene)
    for (const ImportedMesh& mesh : m.scene->meshes) {
      skinned += !mesh.influences.empty();
      vertices += mesh.positions.size();
    }
  const double rate = a.frame_time > 0 ? 1 / a.frame_time : 0;
  std::vector<std::size_t> depth(s.size(), 0);
  for (std::size_t j = 0; j < s.size(); ++j)
    if (const int p = s.parents()[j]; p >= 0) depth[j] = depth[static_cast<std::size_t>(p)] + 1;
  auto bvh_joint = [&](std::size_t j) -> const BvhJoint* {
    return m.bvh ? &m.bvh->joints[static_cast<std::size_t>(s.raw_indices()[j])] : nullptr;
  };
  std::string t;
  if (format == "json") {
    t += "{\"file\":";
    append_json_string(t, args.input.file);
    t += ",\"format\":";
    append_json_string(t, m.format);
    t += ",\"joints\":" + std::to_string(s.size()) + ",\"end_sites\":" + std::to_string(end_sites);
    if (m.bvh) t += ",\"channels\":" + std::to_string(m.bvh->channel_count());
    t += ",\"animations\":" + std::to_string(m.animation_count) + ",\"frames\":" + std::to_string(a.frame_count) + ",\"frame_time\":";
    append_number(t, a.frame_time);
    t += ",\"rate\":";
    append_json_number_or_null(t, rate);
    t += ",\"duration\":";
    append_json_number_or_null(t, a.duration());
    if (m.scene) {
      t += ",\"meshes\":" + std::to_string(m.scene->meshes.size()) + ",\"skinned_meshes\":" + std::to_string(skinned) +
           ",\"vertices\":" + std::to_string(vertices) + ",\"animation_list\":[";
      for (std::size_t i = 0; i < m.scene->animations.size(); ++i) {
        t += i ? ",{\"name\":" : "{\"name\":";
        append_json_string(t, m.scene->animations[i].name);
        t += ",\"frames\":" + std::to_string(m.scene->animations[i].animation.frame_count) + "}";
      }
      t += "]";
    }
    t += ",\"warnings\":[";
    for (std::size_t i = 0; i < m.warnings.size(); ++i) {
      if (i) t += ',';
      append_json_string(t, m.warnings[i]);
    }
    t += "],\"hierarchy\":[\n";
    for (std::size_t j = 0; j < s.size(); ++j) {
      t += j ? ",\n{\"index\":" : "{\"index\":";
      t += std::to_string(j) + ",\"name\":";
      append_json_string(t, s.names()[j]);
      t += ",\"parent\":" + std::to_string(s.parents()[j]) + ",\"depth\":" + std::to_string(depth[j]) +
           ",\"end_site\":" + (s.is_end_site(j) ? "true" : "false");
      if (const BvhJoint* b = bvh_joint(j); b && !b->end_site) {
        t += ",\"channels\":[";
        for (std::size_t k = 0; k < b->channels.size(); ++k) (t += k ? ",\"" : "\"") += std::string(to_string(b->channels[k])) + "\"";
        t += "]";
      }
      t += "}";
      if (t.size() > (1u << 16)) out.write(std::exchange(t, {}));
    }
    t += "\n]}\n";
  } else {
    std::ostringstream o;
    o << "file: " << args.input.file << " (" << m.format << ")\n";
    o << "joints: " << s.size() << " (" << count_text(end_sites, "end site", "end sites") << ")\n";
    if (m.bvh) o << "channels: " << m.bvh->channel_count() << "\n";
    o << "animations: " << m.animation_count << "\n";
    if (a.frame_count == 0)
      o << (m.animation_count ? "frames: 0 (an empty animation: the rest pose)\n" : "frames: 0 (no animation: the rest pose)\n");
    else
      o << "frames: " << a.frame_count << ", frame time " << a.frame_time << " s (" << rate << " Hz), duration " << a.duration() << " s\n";
    if (m.scene) {
      o << "meshes: " << m.scene->meshes.size() << " (" << skinned << " skinned, " << count_text(vertices, "vertex", "vertices") << ")\n";
      for (std::size_t i = 0; i < m.scene->animations.size(); ++i)
        o << "animation " << i << ": '" << printable(m.scene->animations[i].name) << "', "
          << count_text(m.scene->animations[i].animation.frame_count, "frame", "frames") << " resampled\n";
    }
    o << "hierarchy:\n";
    t = o.str();
    for (std::size_t j = 0; j < s.size(); ++j) {
      t.append(2 + 2 * std::min(depth[j], kMaxIndent), ' ');
      if (depth[j] > kMaxIndent) t += "(depth " + std::to_string(depth[j]) + ") ";
      t += printable(s.names()[j]);
      if (const BvhJoint* b = bvh_joint(j)) t += b->end_site ? " (End Site)" : " [" + channels_of(*b) + "]";
      t += '\n';
      if (t.size() > (1u << 16)) out.write(std::exchange(t, {}));
    }
  }
  out.write(t);
  out.finish();
  return 0;
}

}  // namespace

Runner define_info(CLI::App& c) {
  auto args = std::make_shared<InfoArgs>();
  add_input_options(c, args->input);
  args->format = add_format_option(c, {"text", "json"}, "Output format: text or json");
  c.add_option("-o,--output", args->output, "Write to this file instead of standard output (- for standard output)")->check(file_name());
  c.add_flag("--force", args->force, "Replace the output file if it exists (a regular file only)");
  return [args] { return run_info(*args); };
}

}  // namespace dq::cli

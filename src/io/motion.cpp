#include "dq/io/motion.hpp"

#include <algorithm>
#include <cctype>

namespace dq {

Expected<Motion> load_motion(const std::filesystem::path& path, const MotionOptions& options) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  Motion m;
  if (ext == ".bvh") {
    Expected<BvhFile> bvh = read_bvh_file(path);
    if (!bvh) return bvh.error();
    Expected<Skeleton> skeleton = bvh_skeleton(*bvh);
    if (!skeleton) return Error{path.string() + ": " + skeleton.error().message};
    m.format = "bvh";
    m.skeleton = std::move(*skeleton);
    m.animation = bvh_animation(*bvh, m.skeleton);
    m.animation_count = 1;
    m.warnings = bvh->warnings;
    m.bvh = std::move(*bvh);
    return m;
  }
  ImportOptions io;
  io.sample_rate = options.sample_rate;
  io.timeout_seconds = options.import_timeout;
  Expected<ImportedScene> scene = import_scene(path, io);
  if (!scene) return scene.error();
  m.format = ext.empty() ? "unknown" : ext.substr(1);
  m.skeleton = scene->skeleton;
  m.animation_count = scene->animations.size();
  if (options.animation >= m.animation_count && m.animation_count > 0)
    return Error{path.string() + ": animation " + std::to_string(options.animation) + " requested, the file has " +
                 std::to_string(m.animation_count)};
  if (m.animation_count > 0) m.animation = scene->animations[options.animation].animation;
  m.warnings = scene->warnings;
  m.scene = std::move(*scene);
  return m;
}

}  // namespace dq

#include <filesystem>

#include "dq/io/file.hpp"
#include "dq/io/scene.hpp"

namespace dq {

Expected<Motion> import_motion(const std::filesystem::path& path, const MotionOptions& options) {
  // A device, FIFO or socket is refused before the BVH sniffing opens it.
  if (Status s = refuse_special_file(path); !s) return s.error();
  if (is_bvh_file(path) || has_bvh_extension(path)) return load_motion(path, options);
  if (!(options.import_timeout > 0)) return Error{path.string() + ": MotionOptions::import_timeout must be positive"};
  ImportOptions io;
  io.sample_rate = options.sample_rate > 0 ? options.sample_rate : 30;
  io.timeout_seconds = options.import_timeout;
  io.result_limit_mb = options.memory_limit_mb;
  io.lights_and_cameras = options.lights_and_cameras;
  Expected<ImportedScene> scene = import_scene(path, io);
  if (!scene) return scene.error();
  Motion m;
  const std::string ext = lowercase_extension(path);
  m.format = ext.empty() ? "unknown" : ext.substr(1);
  m.skeleton = scene->skeleton;
  m.animation_count = scene->animations.size();
  if (options.animation >= m.animation_count && options.animation > 0)  // 0 of none: the rest pose
    return Error{path.string() + ": animation " + std::to_string(options.animation) + " requested, the file has " +
                 std::to_string(m.animation_count)};
  if (m.animation_count > 0) m.animation = scene->animations[options.animation].animation;
  m.warnings = scene->warnings;
  m.scene = std::move(*scene);
  return m;
}

}  // namespace dq

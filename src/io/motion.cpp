#include "dq/io/motion.hpp"

#include <algorithm>
#include <cctype>

namespace dq {

bool is_bvh_path(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext == ".bvh";
}

Expected<Motion> load_motion(const std::filesystem::path& path) {
  if (!is_bvh_path(path))
    return Error{path.string() + ": not a BVH file (other formats are read by dq::import_motion, in dqkit::import, built with Assimp)"};
  Expected<BvhFile> bvh = read_bvh_file(path);
  if (!bvh) return bvh.error();
  Expected<Skeleton> skeleton = bvh_skeleton(*bvh);
  if (!skeleton) return Error{path.string() + ": " + skeleton.error().message};
  Motion m;
  m.format = "bvh";
  m.skeleton = std::move(*skeleton);
  m.animation = bvh_animation(*bvh, m.skeleton);
  m.animation_count = 1;
  m.warnings = bvh->warnings;
  m.bvh = std::move(*bvh);
  return m;
}

}  // namespace dq

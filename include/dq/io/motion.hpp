// "A skeleton and its motion from a file". load_motion (dqkit::io) reads BVH with dqkit's own exact
// reader and needs no Assimp; import_motion (dqkit::import, dq/io/scene.hpp) reads BVH the same
// way and every other format through the Assimp importer.
#pragma once

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "dq/io/bvh.hpp"
#include "dq/io/imported_scene.hpp"
#include "dq/util/expected.hpp"

namespace dq {

struct Motion {
  std::string format;            ///< "bvh" or the importer's file extension
  Skeleton skeleton;
  Animation animation;           ///< empty (0 frames) for a file without animation
  std::optional<BvhFile> bvh;    ///< the file itself, for BVH input (channels, exact values)
  std::optional<ImportedScene> scene;  ///< the imported scene, for other formats
  std::size_t animation_count = 0;
  std::vector<std::string> warnings;
};

/// Options of import_motion (dq/io/scene.hpp); a BVH file has one animation and needs none.
struct MotionOptions {
  std::size_t animation = 0;  ///< which animation of a multi-animation file
  double sample_rate = 30;    ///< resampling rate for imported animations
  double import_timeout = 120;  ///< seconds before an isolated import is abandoned
};

/// Whether load_motion reads this file: its extension is .bvh (any case).
bool is_bvh_path(const std::filesystem::path& path);

/// Reads a BVH file into a skeleton and its animation. Any other file is an error that names
/// import_motion, which reads the other formats.
Expected<Motion> load_motion(const std::filesystem::path& path);

}  // namespace dq

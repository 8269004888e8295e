// One entry point for "a skeleton and its motion from a file": BVH through dqkit's own exact
// reader, every other format through the Assimp importer.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "dq/io/bvh.hpp"
#include "dq/io/scene.hpp"

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

struct MotionOptions {
  std::size_t animation = 0;  ///< which animation of a multi-animation file
  double sample_rate = 30;    ///< resampling rate for imported animations
  double import_timeout = 120;  ///< seconds before an (isolated) import is abandoned
};

Expected<Motion> load_motion(const std::filesystem::path& path, const MotionOptions& options = {});

}  // namespace dq

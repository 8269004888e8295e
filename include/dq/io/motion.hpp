// "A skeleton and its motion from a file". load_motion (dqkit::io) reads BVH with dqkit's own exact
// reader and needs no Assimp; import_motion (dqkit::import, dq/io/scene.hpp) reads BVH the same
// way and every other format through the Assimp importer.
#pragma once

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
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

/// Options of load_motion and import_motion (dq/io/scene.hpp).
struct MotionOptions {
  std::size_t animation = 0;  ///< which animation of a multi-animation file (a BVH file has one)
  /// Frames per second of the result, 0 < rate ≤ 1000; 0: the file's own (BVH), 30 (imported
  /// clips, which Assimp gives as keys). A BVH file is resampled by screw interpolation; the last
  /// frame is always the clip's end (resampled_frame_count).
  double sample_rate = 0;
  double import_timeout = 120;  ///< seconds before an isolated import is abandoned
  /// The most the animation (frames × joints × 64 bytes) may take; beyond it an error, before
  /// anything is allocated. A BVH text of at most 1 GiB (BvhLimits) comes on top.
  std::size_t memory_limit_mb = 4096;
};

/// Frames that cover `seconds` at `rate` with the last one on the end: ⌈seconds × rate⌉ + 1
/// (a clip of 1.03 s at 30 Hz has 32 frames; the last one is at 1.03 s, not 1.0 s).
std::size_t resampled_frame_count(double seconds, double rate);

/// Whether the file's content is BVH (after an optional UTF-8 byte-order mark and whitespace,
/// the word HIERARCHY), whatever its name. Never blocks (FIFOs and devices are not BVH).
bool is_bvh_file(const std::filesystem::path& path);
/// The same test on the start of a text.
bool looks_like_bvh(std::string_view text);

/// Reads a BVH file (recognized by content) into a skeleton and its animation. Any other file is
/// an error that names import_motion, which reads the other formats.
Expected<Motion> load_motion(const std::filesystem::path& path, const MotionOptions& options = {});
/// The same from BVH text in memory (standard input); `source` names it in errors.
Expected<Motion> read_motion(std::string_view bvh_text, std::string_view source, const MotionOptions& options = {});

}  // namespace dq

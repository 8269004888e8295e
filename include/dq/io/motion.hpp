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
  /// clips, which Assimp gives as keys). A BVH file is resampled by screw interpolation at
  /// f / rate; the last frame holds the clip's end (resampled_frame_count).
  double sample_rate = 0;
  double import_timeout = 120;  ///< seconds before an isolated import is abandoned
  /// The most the animation (frames × joints × 64 bytes) may take; beyond it an error, before
  /// anything is allocated. A BVH text of at most 1 GiB (BvhLimits) comes on top.
  std::size_t memory_limit_mb = 4096;
  bool lights_and_cameras = false;  ///< imported files: ImportOptions::lights_and_cameras
};

/// Frames that cover `seconds` at `rate`: ⌈seconds × rate⌉ + 1 (within 1e-9 of a frame; 2 at least
/// for any positive length), at f / rate, so that a source
/// whose frames lie on the grid keeps them to rounding (120 Hz to 30 Hz: every 4th). The last
/// frame lies at or up to one frame past the end and holds the clip's last pose (a clip of 1.03 s
/// at 30 Hz has 32 frames, the last at 31/30 s with the pose of 1.03 s): nothing of the clip is
/// lost, and the resampled duration is at most one frame longer. Saturates at the largest std::size_t where the
/// count would not fit (a memory budget then refuses it).
std::size_t resampled_frame_count(double seconds, double rate);

/// Whether the file's content is BVH (after an optional UTF-8 byte-order mark and whitespace,
/// the word HIERARCHY), whatever its name. Never blocks (FIFOs and devices are not BVH).
bool is_bvh_file(const std::filesystem::path& path);
/// The same test on the start of a text.
bool looks_like_bvh(std::string_view text);
/// Whether the file's name ends in .bvh (any case): load_motion and import_motion read such a file
/// as BVH whatever it holds, so that a damaged one gets the BVH reader's error ("file:line: ...").
bool has_bvh_extension(const std::filesystem::path& path);

/// Reads a BVH file (recognized by content, or by its name: has_bvh_extension) into a skeleton and
/// its animation. Any other file is an error that names import_motion, which reads the other
/// formats; so is MotionOptions::animation other than 0 (a BVH file has one animation).
Expected<Motion> load_motion(const std::filesystem::path& path, const MotionOptions& options = {});
/// The same from BVH text in memory (standard input); `source` names it in errors.
Expected<Motion> read_motion(std::string_view bvh_text, std::string_view source, const MotionOptions& options = {});

}  // namespace dq

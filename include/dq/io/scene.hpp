// Skeletons, skins and animations from glTF 2.0, FBX, Collada, DirectX X, IQM, BVH and the other
// formats of the Open Asset Import Library (Debian libassimp-dev): library dqkit::import.
//
// Isolation: by default Assimp runs in a helper process, `dqkit-import-worker`, started with
// posix_spawn (never fork(), so callers may be multithreaded, e.g. Python). The worker dies with
// the calling thread's process, runs under address-space, CPU-time and wall-clock limits, and
// whatever it sends back is checked against a size budget before the caller allocates for it.
// The worker is found, in this order: ImportOptions::worker_path; the environment variable
// DQKIT_IMPORT_WORKER; ../libexec/dqkit/ relative to the running program or to the shared library
// that holds dqkit::import (so an installed tree can be moved); the configured install location.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>

#include "dq/io/imported_scene.hpp"
#include "dq/io/motion.hpp"
#include "dq/util/expected.hpp"

namespace dq {

struct ImportOptions {
  double sample_rate = 30;  ///< frames per second for resampled animations (0 < rate ≤ 1000; resampled_frame_count)
  bool meshes = true;       ///< import mesh geometry and skins (a broken mesh is left out with a warning)
  bool lights_and_cameras = false;  ///< keep light and camera nodes (leaves without meshes) as joints
  /// Run Assimp in a helper process. Assimp 5.2 crashes, hangs or exhausts memory on some
  /// malformed files (found by dqkit's fuzzing, docs/reliability.md); isolated, such a file gives
  /// an Error ("the importer crashed on this file") instead of taking the program down.
  bool isolate = true;
  double timeout_seconds = 120;         ///< isolated import only: wall-clock limit
  double cpu_limit_seconds = 120;       ///< isolated import only: CPU-time limit of the worker (whole seconds, rounded up)
  std::size_t memory_limit_mb = 8192;   ///< isolated import only: address-space limit of the worker (0: none)
  std::size_t result_limit_mb = 2048;   ///< isolated import only: the most the caller allocates for the worker's result
  std::filesystem::path worker_path{};  ///< isolated import only: the worker executable (empty: look it up, see above)
};

/// Imports a file. Errors say which file and what the importer reported; nothing throws, and
/// with `isolate` (the default) no input file can crash or hang the caller.
Expected<ImportedScene> import_scene(const std::filesystem::path& path, const ImportOptions& options = {});
/// The same from memory (for fuzzing); `hint` is the file extension ("gltf", "fbx", ...).
Expected<ImportedScene> import_scene_from_memory(std::span<const std::uint8_t> data, const std::string& hint,
                                                 const ImportOptions& options = {});

/// load_motion for every format: BVH (recognized by content, is_bvh_file, or by a name ending in
/// .bvh, has_bvh_extension) through dqkit's own exact reader (load_motion), every other format
/// through import_scene (isolated).
Expected<Motion> import_motion(const std::filesystem::path& path, const MotionOptions& options = {});

}  // namespace dq

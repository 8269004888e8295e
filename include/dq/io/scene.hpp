// Skeletons, skins and animations from glTF 2.0, FBX, Collada, DirectX X, IQM, BVH and the other
// formats of the Open Asset Import Library (Debian libassimp-dev), converted at this boundary to
// dqkit's conventions: column vectors, right-handed, radians, unit dual quaternions.
//
// Scale: rigid transforms cannot hold scale. A uniform scale on a node is pushed into the
// translations of its descendants (the joint positions stay right) and recorded in
// `joint_scale`; a non-uniform scale is approximated by its geometric mean, with a warning.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "dq/anim/animation.hpp"
#include "dq/anim/skeleton.hpp"
#include "dq/util/expected.hpp"

namespace dq {

struct SkinInfluence {
  std::uint32_t joint = 0;  ///< runtime joint index in ImportedScene::skeleton
  float weight = 0;
  friend bool operator==(const SkinInfluence&, const SkinInfluence&) = default;
};

struct ImportedMesh {
  std::string name;
  std::vector<Vec3<float>> positions;
  std::vector<Vec3<float>> normals;                ///< empty if the file has none
  std::vector<std::uint32_t> indices;              ///< triangles
  std::vector<std::uint32_t> influence_offsets;    ///< vertex v's influences: [offsets[v], offsets[v+1])
  std::vector<SkinInfluence> influences;           ///< empty for a rigid (unskinned) mesh
  std::vector<std::uint32_t> bone_joints;          ///< joints that deform this mesh
  std::vector<Mat4<double>> inverse_bind;          ///< per bone_joints entry: mesh space to joint space at bind time
  int node_joint = -1;                             ///< the joint of the node that holds the mesh
};

struct ImportedAnimation {
  std::string name;
  Animation animation;  ///< every joint's local transform, resampled at the import rate
};

struct ImportedScene {
  Skeleton skeleton;                    ///< every node of the scene graph, parents first
  std::vector<double> joint_scale;      ///< accumulated uniform scale of each joint (1 for most files)
  std::vector<ImportedMesh> meshes;
  std::vector<ImportedAnimation> animations;
  std::vector<std::string> warnings;    ///< "file: ..." notes on what was approximated
};

struct ImportOptions {
  double sample_rate = 30;  ///< frames per second for resampled animations (0 < rate ≤ 1000)
  bool meshes = true;       ///< import mesh geometry and skins
  /// Run Assimp in a child process. Assimp 5.2 crashes, hangs or exhausts memory on some malformed
  /// files (found by dqkit's fuzzing, docs/reliability.md); isolated, such a file gives an Error
  /// ("the importer crashed on this file") instead of taking the program down.
  bool isolate = true;
  double timeout_seconds = 120;       ///< isolated import only: give up after this long
  std::size_t memory_limit_mb = 8192;  ///< isolated import only: address-space limit of the child
};

/// Imports a file. Errors say which file and what the importer reported; nothing throws, and
/// with `isolate` (the default) no input file can crash or hang the caller.
Expected<ImportedScene> import_scene(const std::filesystem::path& path, const ImportOptions& options = {});
/// The same from memory (for fuzzing); `hint` is the file extension ("gltf", "fbx", ...).
Expected<ImportedScene> import_scene_from_memory(std::span<const std::uint8_t> data, const std::string& hint,
                                                 const ImportOptions& options = {});

}  // namespace dq

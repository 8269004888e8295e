// Skinning a whole imported scene (library dqkit::skin): every mesh of an ImportedScene as a Skin,
// posed from the skeleton at any time of an animation, skinned into one vertex buffer (all
// meshes' vertices in import order, triangles re-indexed into it), and written as CSV, OBJ, PLY
// or glTF 2.0.
//
// World space: a skinned vertex is Σ wᵢ Gᵢ Bᵢ⁻¹ v with Gᵢ the bone's full world transform (the
// glTF 2.0 rule; the mesh node's own transform does not apply to a skinned mesh). The importer
// gives rigid joint transforms and the uniform scale it pushed into translations
// (ImportedScene::joint_scale), so Gᵢ = Wᵢ S(sᵢ), and the skin's bone scale is sᵢ. A mesh without
// bones is rigid: its vertices follow its node's full world transform.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "dq/io/imported_scene.hpp"
#include "dq/skin/skin.hpp"
#include "dq/skin/skinning.hpp"
#include "dq/util/expected.hpp"

namespace dq {

/// One skinned frame of a scene: component arrays over all vertices, and the triangles.
struct SkinnedFrame {
  std::vector<float> px, py, pz;
  std::vector<float> nx, ny, nz;  ///< empty when some mesh has no normals
  std::vector<float> tx, ty, tz;  ///< empty when some mesh has no tangents (unit, skinned as directions)
  std::vector<std::uint32_t> triangles;
  std::size_t size() const noexcept { return px.size(); }
  Vec3<float> position(std::size_t v) const { return {px[v], py[v], pz[v]}; }
};

class SceneSkin {
 public:
  /// Builds one Skin per mesh (errors name the mesh). Allocates everything a frame needs.
  static Expected<SceneSkin> build(const ImportedScene& scene, const SkinOptions& options = {});

  std::size_t vertex_count() const noexcept { return vertex_count_; }
  std::size_t joint_count() const noexcept { return joint_count_; }
  bool has_normals() const noexcept { return normals_; }
  bool has_tangents() const noexcept { return tangents_; }
  /// Vertices whose weights were renormalized (WeightPolicy::normalize), over all meshes.
  std::size_t renormalized_vertices() const noexcept;
  struct Part {
    Skin skin;
    std::vector<std::uint32_t> bone_joints;  ///< skeleton joint of each bone of `skin`
    std::size_t first_vertex = 0;            ///< where the mesh starts in the frame
    std::string name;
  };
  std::span<const Part> parts() const noexcept { return parts_; }

  /// A frame sized for this scene (triangles filled in); skin() then only writes into it.
  SkinnedFrame make_frame() const;
  /// Skins every mesh with the skeleton's model (world) transforms `joint_world`, one per joint:
  /// one call of `threads` for all the meshes, so that the threads share small meshes too.
  /// Preconditions: sizes match and the frame comes from make_frame(). No allocation but the
  /// pool's list of outputs, the first time it skins this many meshes (SkinningThreads::run).
  Status skin(std::span<const DualQuaternion<double>> joint_world, SkinningMethod method, SkinningThreads& threads,
              SkinnedFrame& frame);

 private:
  std::vector<Part> parts_;
  std::vector<SkinPalette> palettes_;
  std::vector<std::vector<DualQuaternion<double>>> bone_world_;
  std::vector<SkinningJob> jobs_;  // one per part, refilled by each skin()
  std::vector<std::uint32_t> triangles_;
  std::size_t vertex_count_ = 0, joint_count_ = 0;
  bool normals_ = false, tangents_ = false;
};

/// The skeleton's world transforms at `time` seconds of animation `animation` (clamped to its
/// duration; the rest pose when the scene has no animation). Errors: animation out of range.
/// Allocates only to size `joint_world` (so not at all when called again for the same scene).
Status pose_at(const ImportedScene& scene, std::size_t animation, double time, std::vector<DualQuaternion<double>>& joint_world);

enum class MeshFormat { csv, obj, ply, gltf };
/// "csv", "obj", "ply", "gltf"; an error names the accepted ones.
Expected<MeshFormat> parse_mesh_format(const std::string& name);
/// The frame in a format: CSV `vertex,x,y,z` (vertex ids from 0, %.9g), OBJ (v, vn, f), PLY
/// (ASCII, vertices with normals when present, triangles), glTF 2.0 (one mesh, embedded buffer,
/// written with tinygltf). Vertex order is the frame's in every format.
Expected<std::string> format_frame(const SkinnedFrame& frame, MeshFormat format);

}  // namespace dq

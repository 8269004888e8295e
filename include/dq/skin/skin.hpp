// Skins: the data contract between an importer and the skinning kernels (library dqkit::skin).
//
// A RawSkin is what a file gives (vertices, normals, tangents, influences of any count, inverse
// bind matrices); build_skin validates it with reasons and makes the immutable runtime Skin, in
// which everything the kernels need is normalized and laid out once:
//  - weights normalized to sum 1 (once, here; never per frame);
//  - each vertex's influences in a canonical order: weight descending, ties by bone index. The
//    first one is the vertex's pivot for the antipodality of dual-quaternion skinning, so the
//    result does not depend on the order a file lists influences in (docs/skinning.md);
//  - influences stored slot-major and padded to the skin's largest count K with weight 0, so a
//    kernel runs the same K iterations for every vertex (what a SIMD kernel over vertices needs);
//  - the bind transform of every bone split into a rigid part (a unit dual quaternion) and a
//    symmetric scale/shear matrix (Kavan et al. 2008, two-phase skinning), see SkinBone.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "dq/core/dual_quaternion.hpp"
#include "dq/core/matrix.hpp"
#include "dq/util/component_arrays.hpp"
#include "dq/util/expected.hpp"

namespace dq {

struct RawSkinInfluence {
  std::uint32_t bone = 0;  ///< index into RawSkin::inverse_bind
  float weight = 0;
};

/// A skin as a file gives it. Positions, normals and tangents are in the mesh's bind space.
struct RawSkin {
  std::vector<Vec3<float>> positions;
  std::vector<Vec3<float>> normals;      ///< empty, or one per vertex
  std::vector<Vec3<float>> tangents;     ///< empty, or one per vertex (the handedness sign is not skinned)
  std::vector<std::uint32_t> triangles;  ///< vertex indices, three per triangle (needed for centres of rotation)
  std::vector<std::uint32_t> influence_offsets;  ///< vertex v: influences [offsets[v], offsets[v+1])
  std::vector<RawSkinInfluence> influences;
  /// Per bone: bind space to the bone's space at bind time (glTF inverseBindMatrices, Assimp's
  /// mOffsetMatrix). May hold scale and shear.
  std::vector<Mat4<double>> inverse_bind;
  /// Per bone: the uniform scale of the bone's world transform that the rigid pose given to
  /// skinning does not carry (dq::ImportedScene::joint_scale). Empty: all 1.
  std::vector<double> bone_scale;
};

enum class WeightPolicy {
  normalize,  ///< weights that do not sum to 1 are divided by their sum (and counted in Skin::renormalized_vertices)
  reject,     ///< a vertex whose weights sum differs from 1 by more than SkinOptions::weight_tolerance is an error
};

struct SkinOptions {
  WeightPolicy weights = WeightPolicy::normalize;
  double weight_tolerance = 1e-3;    ///< |sum − 1| accepted as 1 (then still normalized exactly)
  bool centers_of_rotation = true;   ///< precompute the centres for CoR skinning (needs triangles)
  double cor_sigma = 0.1;            ///< width of the weight similarity kernel (Le and Hodgins 2016 use 0.1)
};

/// One bone's bind transform B = S(bone_scale) · inverse_bind, split as B = [U | b] · [P | 0] with U
/// a rotation and P symmetric positive definite (polar decomposition). `rigid` is [U | b] as a
/// unit dual quaternion; `scale_shear` is P (the identity for rigid binds). Skinning a vertex with
/// a rigid pose W: the full transform is W · B (LBS uses it whole); DQS blends the rigid parts
/// W · rigid and applies the blended P first (Kavan's two-phase method).
struct SkinBone {
  DualQuaternion<double> rigid;
  Mat3<double> scale_shear = Mat3<double>::identity();
};

/// The runtime skin: immutable, validated, structure-of-arrays.
class Skin {
 public:
  std::size_t vertex_count() const noexcept { return vertex_count_; }
  std::size_t bone_count() const noexcept { return bones_.size(); }
  /// Influence slots per vertex (the largest count in the file; shorter vertices are padded with weight 0).
  std::size_t slots() const noexcept { return slots_; }
  bool has_normals() const noexcept { return normals_at_ != 0; }
  bool has_tangents() const noexcept { return tangents_at_ != 0; }
  bool has_centers() const noexcept { return centers_at_ != 0; }
  /// Whether any bone's bind has scale or shear (then DQS and CoR run the linear phase first).
  bool has_scale_shear() const noexcept { return has_scale_shear_; }
  std::size_t renormalized_vertices() const noexcept { return renormalized_; }

  std::span<const SkinBone> bones() const noexcept { return bones_; }
  std::span<const std::uint32_t> triangles() const noexcept { return triangles_; }
  /// Component arrays of the bind-space vertices (x, y, z); empty where the skin has none.
  std::span<const float> px() const noexcept { return coordinates_[0]; }
  std::span<const float> py() const noexcept { return coordinates_[1]; }
  std::span<const float> pz() const noexcept { return coordinates_[2]; }
  std::span<const float> nx() const noexcept { return coordinate(normals_at_, 0); }
  std::span<const float> ny() const noexcept { return coordinate(normals_at_, 1); }
  std::span<const float> nz() const noexcept { return coordinate(normals_at_, 2); }
  std::span<const float> tx() const noexcept { return coordinate(tangents_at_, 0); }
  std::span<const float> ty() const noexcept { return coordinate(tangents_at_, 1); }
  std::span<const float> tz() const noexcept { return coordinate(tangents_at_, 2); }
  /// The centre of rotation of each vertex (bind space; Le and Hodgins 2016, eq. 4): the average
  /// of the triangle centroids weighted by area and by the similarity of the triangle's weights
  /// (the mean of its corners') to the vertex's. A vertex with no similar triangle (one
  /// influence, or no triangle sharing two of its bones) has its own position as centre, which
  /// makes CoR equal LBS there (and exact for one influence).
  std::span<const float> cx() const noexcept { return coordinate(centers_at_, 0); }
  std::span<const float> cy() const noexcept { return coordinate(centers_at_, 1); }
  std::span<const float> cz() const noexcept { return coordinate(centers_at_, 2); }
  /// The bone and the weight of influence slot k (k < slots()) of every vertex.
  std::span<const std::uint32_t> slot_bones(std::size_t k) const noexcept { return bone_[k]; }
  std::span<const float> slot_weights(std::size_t k) const noexcept { return weight_[k]; }
  /// Values from one slot's array to the next's, the same in both tables (for kernels that step
  /// from slot to slot).
  std::size_t slot_stride() const noexcept { return bone_.distance(); }
  Vec3<float> position(std::size_t v) const { return {px()[v], py()[v], pz()[v]}; }
  Vec3<float> center(std::size_t v) const { return {cx()[v], cy()[v], cz()[v]}; }

 private:
  friend Expected<Skin> build_skin(const RawSkin& raw, const SkinOptions& options);
  friend struct SkinCenters;
  std::size_t vertex_count_ = 0, slots_ = 0, renormalized_ = 0;
  bool has_scale_shear_ = false;
  std::vector<SkinBone> bones_;
  std::vector<std::uint32_t> triangles_;
  std::span<const float> coordinate(std::size_t at, std::size_t c) const noexcept {
    return at == 0 ? std::span<const float>{} : coordinates_[at + c];
  }
  // Every array a kernel streams through starts a cache line, and no two of them share their
  // cache sets (ComponentArrays, docs/skinning.md): the vertices' coordinates in one allocation
  // (positions, then normals, tangents and centres where present: their first arrays' indices,
  // 0 for none), the slots' bones and weights in one each.
  ComponentArrays<float, std::dynamic_extent> coordinates_;
  std::size_t normals_at_ = 0, tangents_at_ = 0, centers_at_ = 0;
  ComponentArrays<std::uint32_t, std::dynamic_extent> bone_;
  ComponentArrays<float, std::dynamic_extent> weight_;
};

/// Validates and builds. Errors name the vertex or bone and say what is wrong: sizes that do
/// not match, a bone index out of range, a non-finite or negative weight or coordinate, a vertex
/// without weight, weights that do not sum to 1 (WeightPolicy::reject), a singular or
/// non-affine inverse bind matrix, a non-positive bone scale, a triangle index out of range.
Expected<Skin> build_skin(const RawSkin& raw, const SkinOptions& options = {});

}  // namespace dq

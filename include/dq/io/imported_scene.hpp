// What an import produces: a skeleton, skinned meshes and animations in dqkit's conventions
// (column vectors, right-handed, radians, unit dual quaternions). Plain data; reading files into
// it is dqkit::import (dq/io/scene.hpp).
//
// Scale: rigid transforms cannot hold scale. A uniform scale on a node is pushed into the
// translations of its descendants (the joint positions stay right) and recorded in
// `joint_scale`; a non-uniform scale is approximated by its geometric mean, with a warning.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "dq/anim/animation_data.hpp"
#include "dq/anim/skeleton.hpp"
#include "dq/core/matrix.hpp"

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
  /// Empty, or one per vertex: the file's tangents (Assimp's aiMesh::mTangents, read where the mesh
  /// also has normals). The handedness sign (which way the bitangent points) is not kept: skinning
  /// moves the tangent as a direction, and the bitangent follows as ± n × t.
  std::vector<Vec3<float>> tangents;
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

}  // namespace dq

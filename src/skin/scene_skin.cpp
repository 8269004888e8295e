#include "dq/skin/scene_skin.hpp"

#include <algorithm>

#include "dq/anim/animation.hpp"
#include "dq/anim/forward_kinematics.hpp"
#include "dq/util/assert.hpp"

namespace dq {

Expected<SceneSkin> SceneSkin::build(const ImportedScene& scene, const SkinOptions& options) {
  SceneSkin out;
  out.joint_count_ = scene.skeleton.size();
  out.normals_ = out.tangents_ = !scene.meshes.empty();
  for (const ImportedMesh& mesh : scene.meshes) {
    RawSkin raw;
    raw.positions = mesh.positions;
    raw.normals = mesh.normals;
    raw.tangents = mesh.tangents;
    raw.triangles = mesh.indices;
    std::vector<std::uint32_t> bone_joints;
    if (mesh.influences.empty()) {
      // A rigid mesh: one bone, its node, bound with the identity.
      if (mesh.node_joint < 0) return Error{"mesh '" + mesh.name + "' has no bones and no node"};
      bone_joints.push_back(static_cast<std::uint32_t>(mesh.node_joint));
      raw.inverse_bind.push_back(Mat4<double>::identity());
      raw.influence_offsets.resize(mesh.positions.size() + 1);
      for (std::size_t v = 0; v <= mesh.positions.size(); ++v) raw.influence_offsets[v] = static_cast<std::uint32_t>(v);
      raw.influences.assign(mesh.positions.size(), RawSkinInfluence{0, 1.0f});
    } else {
      bone_joints = mesh.bone_joints;
      raw.inverse_bind = mesh.inverse_bind;
      raw.influence_offsets = mesh.influence_offsets;
      for (const SkinInfluence& i : mesh.influences) {
        const auto it = std::find(bone_joints.begin(), bone_joints.end(), i.joint);
        if (it == bone_joints.end()) return Error{"mesh '" + mesh.name + "': an influence names joint " + std::to_string(i.joint) + ", which is not one of its bones"};
        raw.influences.push_back({static_cast<std::uint32_t>(it - bone_joints.begin()), i.weight});
      }
    }
    for (std::uint32_t j : bone_joints) {
      if (j >= scene.skeleton.size()) return Error{"mesh '" + mesh.name + "': bone joint " + std::to_string(j) + " is not in the skeleton"};
      raw.bone_scale.push_back(j < scene.joint_scale.size() ? scene.joint_scale[j] : 1.0);
    }
    Expected<Skin> skin = build_skin(raw, options);
    if (!skin) return Error{"mesh '" + mesh.name + "': " + skin.error().message};
    out.normals_ = out.normals_ && skin->has_normals();
    out.tangents_ = out.tangents_ && skin->has_tangents();
    for (std::uint32_t t : mesh.indices) out.triangles_.push_back(static_cast<std::uint32_t>(out.vertex_count_ + t));
    out.palettes_.emplace_back(bone_joints.size());
    out.bone_world_.emplace_back(bone_joints.size());
    out.jobs_.emplace_back();
    out.parts_.push_back({std::move(*skin), std::move(bone_joints), out.vertex_count_, mesh.name});
    out.vertex_count_ += mesh.positions.size();
  }
  return out;
}

std::size_t SceneSkin::renormalized_vertices() const noexcept {
  std::size_t n = 0;
  for (const Part& p : parts_) n += p.skin.renormalized_vertices();
  return n;
}

SkinnedFrame SceneSkin::make_frame() const {
  SkinnedFrame f;
  for (auto* a : {&f.px, &f.py, &f.pz}) a->assign(vertex_count_, 0.0f);
  if (normals_)
    for (auto* a : {&f.nx, &f.ny, &f.nz}) a->assign(vertex_count_, 0.0f);
  if (tangents_)
    for (auto* a : {&f.tx, &f.ty, &f.tz}) a->assign(vertex_count_, 0.0f);
  f.triangles = triangles_;
  return f;
}

Status SceneSkin::skin(std::span<const DualQuaternion<double>> joint_world, SkinningMethod method, SkinningThreads& threads,
                       SkinnedFrame& frame) {
  DQ_PRECONDITION(joint_world.size() == joint_count_ && frame.size() == vertex_count_ &&
                      (frame.nx.size() == vertex_count_) == normals_ && (frame.tx.size() == vertex_count_) == tangents_,
                  "SceneSkin::skin needs one transform per joint and a frame from make_frame()",
                  Error{"SceneSkin::skin: precondition violated (see the message above)"});
  for (std::size_t i = 0; i < parts_.size(); ++i) {
    const Part& part = parts_[i];
    for (std::size_t b = 0; b < part.bone_joints.size(); ++b) bone_world_[i][b] = joint_world[part.bone_joints[b]];
    update_palette(part.skin, bone_world_[i], palettes_[i]);
    // The job indexes the skin's vertices from 0: hand it the part's window of the frame.
    const std::size_t n = part.skin.vertex_count();
    auto window = [&](std::vector<float>& a) { return a.empty() ? std::span<float>{} : std::span<float>(a).subspan(part.first_vertex, n); };
    jobs_[i] = {&part.skin, &palettes_[i], method,
                {window(frame.px), window(frame.py), window(frame.pz), window(frame.nx), window(frame.ny), window(frame.nz),
                 window(frame.tx), window(frame.ty), window(frame.tz)},
                0, n};
    if (Status s = jobs_[i].validate(); !s) return Error{"mesh '" + part.name + "': " + s.error().message};
  }
  return threads.run(jobs_);  // the windows of one frame do not overlap
}

Status pose_at(const ImportedScene& scene, std::size_t animation, double time, std::vector<DualQuaternion<double>>& joint_world) {
  const std::size_t joints = scene.skeleton.size();
  joint_world.resize(joints);
  if (scene.animations.empty()) {
    local_to_model<DualQuaternion<double>>(scene.skeleton, scene.skeleton.rest_pose(), joint_world);
    return {};
  }
  if (animation >= scene.animations.size())
    return Error{"animation " + std::to_string(animation) + " does not exist (the file has " + std::to_string(scene.animations.size()) + ")"};
  // Sampled into the output, then forward kinematics in place: no allocation once it is sized.
  const Animation& anim = scene.animations[animation].animation;
  if (anim.joint_count < joints) std::copy(scene.skeleton.rest_pose().begin(), scene.skeleton.rest_pose().end(), joint_world.begin());
  sample<double>(anim, time, Interpolation::screw, WrapMode::clamp, joint_world);
  local_to_model<DualQuaternion<double>>(scene.skeleton.parents(), joint_world, joint_world);
  return {};
}

}  // namespace dq

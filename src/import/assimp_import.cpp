#include <assimp/Importer.hpp>
#include <assimp/config.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <algorithm>
#include <cmath>
#include <unordered_map>
#include <unordered_set>

#include "dq/io/file.hpp"
#include "dq/io/utf8.hpp"
#include "import_internal.hpp"

namespace dq {

namespace {

struct Rigid {
  Quaternion<double> rotation;
  Vec3<double> translation;
  double scale = 1;
  bool non_uniform = false;
  bool degenerate = false;  ///< not a rotation times a positive scale: zero, singular, sheared or beyond 1e±12
};

/// Whether the upper 3x3 block is R · diag(s) with R a rotation and every s in [1e-12, 1e12]
/// (a mirror, a shear or a zero column would otherwise become an arbitrary rotation).
bool is_rotation_and_scale(const aiMatrix4x4& m) {
  const Vec3<double> c[3] = {Vec3<ai_real>{m.a1, m.b1, m.c1}.cast<double>(),  // columns
                            Vec3<ai_real>{m.a2, m.b2, m.c2}.cast<double>(), Vec3<ai_real>{m.a3, m.b3, m.c3}.cast<double>()};
  double len[3];
  for (int i = 0; i < 3; ++i) {
    len[i] = std::sqrt(c[i][0] * c[i][0] + c[i][1] * c[i][1] + c[i][2] * c[i][2]);
    if (!(len[i] >= 1e-12 && len[i] <= 1e12)) return false;
  }
  for (int i = 0; i < 3; ++i)
    for (int k = i + 1; k < 3; ++k)
      if (std::abs(c[i][0] * c[k][0] + c[i][1] * c[k][1] + c[i][2] * c[k][2]) > 1e-4 * len[i] * len[k]) return false;  // shear
  const double det = c[0][0] * (c[1][1] * c[2][2] - c[1][2] * c[2][1]) - c[1][0] * (c[0][1] * c[2][2] - c[0][2] * c[2][1]) +
                     c[2][0] * (c[0][1] * c[1][2] - c[0][2] * c[1][1]);
  return det > 0;  // a mirror is not a rotation
}

Rigid decompose(const aiMatrix4x4& m) {
  aiVector3D s, t;
  aiQuaternion r;
  m.Decompose(s, r, t);
  Rigid out;
  out.degenerate = !is_rotation_and_scale(m);
  out.rotation = Quaternion<ai_real>(r.w, r.x, r.y, r.z).cast<double>().normalized();
  out.translation = Vec3<ai_real>{t.x, t.y, t.z}.cast<double>();
  const double sx = std::abs(static_cast<double>(s.x)), sy = std::abs(static_cast<double>(s.y)), sz = std::abs(static_cast<double>(s.z));
  out.scale = std::cbrt(sx * sy * sz);
  out.non_uniform = std::abs(sx - sy) > 1e-4 * out.scale || std::abs(sx - sz) > 1e-4 * out.scale;
  if (!(out.scale > 0) || !std::isfinite(out.scale)) out.scale = 1;
  return out;
}

Mat4<double> to_mat4(const aiMatrix4x4& m) {
  return Mat4<double>::from_rows(m.a1, m.a2, m.a3, m.a4, m.b1, m.b2, m.b3, m.b4, m.c1, m.c2, m.c3, m.c4, m.d1, m.d2, m.d3, m.d4);
}

bool finite(const Rigid& r) {
  for (double v : {r.rotation.w, r.rotation.x, r.rotation.y, r.rotation.z, r.translation.x, r.translation.y, r.translation.z})
    if (!std::isfinite(v)) return false;
  return true;
}

/// Linear interpolation of vector keys / slerp of rotation keys at time t (ticks).
template <class Key, class Value, class Lerp>
Value sample_keys(const Key* keys, unsigned count, double t, Value fallback, Lerp lerp) {
  if (count == 0) return fallback;
  if (t <= keys[0].mTime) return keys[0].mValue;
  for (unsigned i = 1; i < count; ++i)
    if (t < keys[i].mTime) {
      const double span = keys[i].mTime - keys[i - 1].mTime;
      const double u = span > 0 ? (t - keys[i - 1].mTime) / span : 0;
      return lerp(keys[i - 1].mValue, keys[i].mValue, u);
    }
  return keys[count - 1].mValue;
}

class SceneBuilder {
 public:
  SceneBuilder(const aiScene& scene, const ImportOptions& options, std::string source) : scene_(scene), options_(options), source_(std::move(source)) {}

  Expected<ImportedScene> build() {
    if (!scene_.mRootNode) return Error{source_ + ": the file has no scene graph"};
    collect(scene_.mRootNode, -1);
    for (std::size_t i = 0; i < nodes_.size(); ++i) {
      const Rigid& r = rest_[i];
      if (!finite(r)) return Error{source_ + ": node '" + raw_.joints[i].name + "' has a non-finite transform"};
      if (r.degenerate)
        return Error{source_ + ": node '" + raw_.joints[i].name +
                     "' has a transform that is not a rotation and a scale (zero, mirrored, sheared or scaled beyond 1e±12)"};
    }
    Expected<Skeleton> skeleton = build_skeleton(raw_);
    if (!skeleton) return Error{source_ + ": " + skeleton.error().message};
    out_.skeleton = std::move(*skeleton);
    runtime_of_.assign(nodes_.size(), 0);
    for (std::size_t j = 0; j < out_.skeleton.size(); ++j) runtime_of_[static_cast<std::size_t>(out_.skeleton.raw_indices()[j])] = static_cast<std::uint32_t>(j);
    out_.joint_scale.resize(out_.skeleton.size());
    for (std::size_t i = 0; i < nodes_.size(); ++i) out_.joint_scale[runtime_of_[i]] = accumulated_scale_[i];
    if (options_.meshes) import_meshes();
    for (unsigned a = 0; a < scene_.mNumAnimations; ++a)
      if (auto e = import_animation(*scene_.mAnimations[a]); !e) return e.error();
    return std::move(out_);
  }

 private:
  void collect(const aiNode* node, int parent) {
    // Lights and cameras are scene nodes, not joints: left out (with a warning) when they are
    // leaves without meshes, unless asked for.
    std::unordered_map<std::string, const char*> not_joints;
    if (!options_.lights_and_cameras) {
      for (unsigned i = 0; i < scene_.mNumLights; ++i) not_joints.emplace(scene_.mLights[i]->mName.C_Str(), "light");
      for (unsigned i = 0; i < scene_.mNumCameras; ++i) not_joints.emplace(scene_.mCameras[i]->mName.C_Str(), "camera");
      for (unsigned m = 0; m < scene_.mNumMeshes; ++m)  // a node that a skin uses stays a joint
        for (unsigned b = 0; b < scene_.mMeshes[m]->mNumBones; ++b) not_joints.erase(scene_.mMeshes[m]->mBones[b]->mName.C_Str());
    }
    // Iterative depth-first walk (hostile files can nest deeply).
    std::vector<std::pair<const aiNode*, int>> stack{{node, parent}};
    while (!stack.empty()) {
      const auto [n, p] = stack.back();
      stack.pop_back();
      if (p >= 0 && n->mNumChildren == 0 && n->mNumMeshes == 0)
        if (const auto it = not_joints.find(n->mName.C_Str()); it != not_joints.end()) {
          warn(std::string(it->second) + " '" + it->first + "' is not a joint; left out (the option lights_and_cameras, dqkit's --lights-and-cameras, keeps it)");
          skipped_.insert(it->first);
          continue;
        }
      const int index = static_cast<int>(nodes_.size());
      nodes_.push_back(n);
      Rigid r = decompose(n->mTransformation);
      const double parent_scale = p < 0 ? 1.0 : accumulated_scale_[static_cast<std::size_t>(p)];
      if (r.non_uniform) warn("node '" + std::string(n->mName.C_Str()) + "' has a non-uniform scale; its geometric mean is used");
      r.translation = r.translation * parent_scale;  // push the ancestors' scale into the translation
      accumulated_scale_.push_back(parent_scale * r.scale);
      rest_.push_back(r);
      // Names as a user can trust them: UTF-8, present, unique; every change is a warning.
      const std::string given = n->mName.C_Str();
      std::string name = given.empty() ? "node" + std::to_string(index) : to_valid_utf8(given);
      if (taken_.count(name)) name += "#" + std::to_string(index);
      taken_.insert(name);
      if (given.empty()) {
        warn("a node without a name is called '" + name + "'");
      } else if (name != given) {
        warn("node '" + name + "' renamed (its name was taken or not UTF-8)");
      }
      by_name_.emplace(given.empty() ? name : given, static_cast<std::size_t>(index));  // bones and channels use the file's names
      raw_.add(name, p, DualQuaternion<double>::from_rotation_translation(r.rotation, r.translation));
      for (unsigned c = n->mNumChildren; c-- > 0;) stack.emplace_back(n->mChildren[c], index);
    }
  }

  int joint_of(const aiString& name) const {
    const auto it = by_name_.find(name.C_Str());
    return it == by_name_.end() ? -1 : static_cast<int>(runtime_of_[it->second]);
  }

  /// Each mesh on its own: a broken one is left out with a warning, the rest of the file loads.
  void import_meshes() {
    // Which node holds which mesh.
    std::unordered_map<unsigned, int> holder;
    for (std::size_t i = 0; i < nodes_.size(); ++i)
      for (unsigned k = 0; k < nodes_[i]->mNumMeshes; ++k) holder.emplace(nodes_[i]->mMeshes[k], static_cast<int>(runtime_of_[i]));
    for (unsigned m = 0; m < scene_.mNumMeshes; ++m) {
      Expected<ImportedMesh> mesh = import_mesh(*scene_.mMeshes[m], holder.count(m) ? holder[m] : -1);
      if (mesh) {
        out_.meshes.push_back(std::move(*mesh));
      } else {
        warn(mesh.error().message + "; the mesh is left out");
      }
    }
  }

  Expected<ImportedMesh> import_mesh(const aiMesh& mesh, int node_joint) {
    {
      ImportedMesh out;
      out.name = mesh.mName.C_Str();
      out.node_joint = node_joint;
      out.positions.reserve(mesh.mNumVertices);
      for (unsigned v = 0; v < mesh.mNumVertices; ++v) out.positions.push_back({mesh.mVertices[v].x, mesh.mVertices[v].y, mesh.mVertices[v].z});
      if (mesh.mNormals)
        for (unsigned v = 0; v < mesh.mNumVertices; ++v) out.normals.push_back({mesh.mNormals[v].x, mesh.mNormals[v].y, mesh.mNormals[v].z});
      if (mesh.mNormals && mesh.mTangents)
        for (unsigned v = 0; v < mesh.mNumVertices; ++v) out.tangents.push_back({mesh.mTangents[v].x, mesh.mTangents[v].y, mesh.mTangents[v].z});
      for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
        const aiFace& face = mesh.mFaces[f];
        if (face.mNumIndices != 3) continue;  // points and lines are not surfaces
        for (unsigned k = 0; k < 3; ++k) {
          if (face.mIndices[k] >= mesh.mNumVertices) return Error{"mesh '" + out.name + "' has an index out of range"};
          out.indices.push_back(face.mIndices[k]);
        }
      }
      std::vector<std::vector<SkinInfluence>> per_vertex(mesh.mNumVertices);
      for (unsigned b = 0; b < mesh.mNumBones; ++b) {
        const aiBone& bone = *mesh.mBones[b];
        const int joint = joint_of(bone.mName);
        if (joint < 0) return Error{"mesh '" + out.name + "' has a bone '" + bone.mName.C_Str() + "' with no node"};
        out.bone_joints.push_back(static_cast<std::uint32_t>(joint));
        out.inverse_bind.push_back(to_mat4(bone.mOffsetMatrix));
        for (unsigned w = 0; w < bone.mNumWeights; ++w) {
          const aiVertexWeight& vw = bone.mWeights[w];
          if (vw.mVertexId >= mesh.mNumVertices || !std::isfinite(vw.mWeight))
            return Error{"mesh '" + out.name + "' bone '" + bone.mName.C_Str() + "' has an invalid weight"};
          if (vw.mWeight > 0) per_vertex[vw.mVertexId].push_back({static_cast<std::uint32_t>(joint), vw.mWeight});
        }
      }
      out.influence_offsets.push_back(0);
      for (auto& v : per_vertex) {
        out.influences.insert(out.influences.end(), v.begin(), v.end());
        out.influence_offsets.push_back(static_cast<std::uint32_t>(out.influences.size()));
      }
      if (mesh.mNumBones == 0) {
        out.influences.clear();
        out.influence_offsets.clear();
      }
      return out;
    }
  }

  Status import_animation(const aiAnimation& a) {
    const double ticks = a.mTicksPerSecond > 0 ? a.mTicksPerSecond : 25.0;  // Assimp's documented default
    // The clip ends at its last key, also where that lies beyond mDuration (as in FBX files whose
    // duration is one frame short).
    double end = a.mDuration;
    for (unsigned c = 0; c < a.mNumChannels; ++c) {
      const aiNodeAnim& ch = *a.mChannels[c];
      if (ch.mNumPositionKeys) end = std::max(end, ch.mPositionKeys[ch.mNumPositionKeys - 1].mTime);
      if (ch.mNumRotationKeys) end = std::max(end, ch.mRotationKeys[ch.mNumRotationKeys - 1].mTime);
    }
    const double seconds = end / ticks;
    if (!std::isfinite(seconds) || seconds < 0) return Error{source_ + ": animation '" + std::string(a.mName.C_Str()) + "' has an invalid duration"};
    const double rate = std::clamp(options_.sample_rate, 1e-3, 1000.0);
    const std::size_t frames = resampled_frame_count(seconds, rate);  // the last frame on the last key
    const double bytes = static_cast<double>(frames) * static_cast<double>(out_.skeleton.size()) * sizeof(DualQuaternion<double>);
    resampled_bytes_ += bytes;
    if (resampled_bytes_ > static_cast<double>(options_.result_limit_mb) * 1048576.0)
      return Error{source_ + ": animation '" + std::string(a.mName.C_Str()) + "' is too long to resample: " + std::to_string(frames) +
                   " frames at " + std::to_string(rate) + " Hz need more than the " + std::to_string(options_.result_limit_mb) + " MB allowed"};
    ImportedAnimation out;
    out.name = a.mName.C_Str();
    if (a.mNumMorphMeshChannels > 0 || a.mNumMeshChannels > 0)
      warn("animation '" + out.name + "' changes mesh shapes (" + std::to_string(a.mNumMorphMeshChannels + a.mNumMeshChannels) +
           " morph or mesh channels); dqkit imports joint motion only, so the meshes keep their base shape");
    Animation& anim = out.animation;
    anim.frame_time = 1.0 / rate;
    anim.frame_count = frames;
    anim.joint_count = out_.skeleton.size();
    anim.locals.resize(frames * anim.joint_count);
    for (std::size_t f = 0; f < frames; ++f)
      for (std::size_t j = 0; j < anim.joint_count; ++j) anim.locals[f * anim.joint_count + j] = out_.skeleton.rest_pose()[j];
    for (unsigned c = 0; c < a.mNumChannels; ++c) {
      const aiNodeAnim& ch = *a.mChannels[c];
      const int joint = joint_of(ch.mNodeName);
      if (joint < 0) {
        if (!skipped_.count(ch.mNodeName.C_Str()))
          warn("animation '" + out.name + "' drives '" + ch.mNodeName.C_Str() + "', which is not in the scene; ignored");
        continue;
      }
      const std::size_t raw = static_cast<std::size_t>(out_.skeleton.raw_indices()[static_cast<std::size_t>(joint)]);
      const int parent = out_.skeleton.parents()[static_cast<std::size_t>(joint)];
      const double parent_scale = parent < 0 ? 1.0 : out_.joint_scale[static_cast<std::size_t>(parent)];
      const Rigid& rest = rest_[raw];
      for (unsigned k = 0; k < ch.mNumScalingKeys; ++k) {
        const aiVector3D& sk = ch.mScalingKeys[k].mValue;
        const double mean = std::cbrt(std::abs(double(sk.x) * double(sk.y) * double(sk.z)));
        if (std::abs(mean - rest.scale) > 1e-4 * rest.scale) {
          warn("animation '" + out.name + "' scales '" + ch.mNodeName.C_Str() + "'; scale keys are ignored");
          break;
        }
      }
      for (std::size_t f = 0; f < frames; ++f) {
        const double t = std::min(static_cast<double>(f) / rate, seconds) * ticks;
        const aiVector3D p = sample_keys(ch.mPositionKeys, ch.mNumPositionKeys, t,
                                         aiVector3D(static_cast<float>(rest.translation.x / parent_scale), static_cast<float>(rest.translation.y / parent_scale),
                                                    static_cast<float>(rest.translation.z / parent_scale)),
                                         [](const aiVector3D& x, const aiVector3D& y, double u) { return x + (y - x) * static_cast<float>(u); });
        const aiQuaternion r = sample_keys(ch.mRotationKeys, ch.mNumRotationKeys, t,
                                           aiQuaternion(static_cast<float>(rest.rotation.w), static_cast<float>(rest.rotation.x),
                                                        static_cast<float>(rest.rotation.y), static_cast<float>(rest.rotation.z)),
                                           [](const aiQuaternion& x, const aiQuaternion& y, double u) {
                                             aiQuaternion q;
                                             aiQuaternion::Interpolate(q, x, y, static_cast<float>(u));
                                             return q;
                                           });
        const Quaternion<double> q = Quaternion<ai_real>(r.w, r.x, r.y, r.z).cast<double>().normalized();
        const Vec3<double> tr{double(p.x) * parent_scale, double(p.y) * parent_scale, double(p.z) * parent_scale};
        if (!std::isfinite(tr.x + tr.y + tr.z + q.w + q.x + q.y + q.z))
          return Error{source_ + ": animation '" + out.name + "' has non-finite keys for '" + ch.mNodeName.C_Str() + "'"};
        anim.locals[f * anim.joint_count + static_cast<std::size_t>(joint)] = DualQuaternion<double>::from_rotation_translation(q, tr);
      }
    }
    out_.animations.push_back(std::move(out));
    return {};
  }

  void warn(std::string what) {
    if (out_.warnings.size() < 100) out_.warnings.push_back(source_ + ": " + std::move(what));
  }

  const aiScene& scene_;
  ImportOptions options_;
  std::string source_;
  std::vector<const aiNode*> nodes_;
  std::vector<Rigid> rest_;
  std::vector<double> accumulated_scale_;
  std::unordered_map<std::string, std::size_t> by_name_;  // the file's name → the first node of that name
  std::unordered_set<std::string> taken_;                   // the joint names given
  std::vector<std::uint32_t> runtime_of_;
  double resampled_bytes_ = 0;
  std::unordered_set<std::string> skipped_;  // lights and cameras left out
  RawSkeleton raw_;
  ImportedScene out_;
};

constexpr unsigned kFlags = aiProcess_Triangulate | aiProcess_JoinIdenticalVertices | aiProcess_LimitBoneWeights |
                            aiProcess_ValidateDataStructure;

}  // namespace

namespace detail {

ImportRequest make_request(bool from_memory, std::string path_or_hint, std::vector<std::uint8_t> data, const ImportOptions& options) {
  return {.from_memory = from_memory,
          .path_or_hint = std::move(path_or_hint),
          .data = std::move(data),
          .sample_rate = options.sample_rate,
          .meshes = options.meshes,
          .lights_and_cameras = options.lights_and_cameras,
          .result_limit_mb = options.result_limit_mb};
}

namespace {
/// Assimp's FBX reader adds "$AssimpFbx$" pivot nodes unless told to fold them into the joints.
void configure(Assimp::Importer& importer) { importer.SetPropertyBool(AI_CONFIG_IMPORT_FBX_PRESERVE_PIVOTS, false); }
/// Assimp's reason for a failed read; it reports running out of memory as the bare "std::bad_alloc".
Error read_failure(const std::string& source, const Assimp::Importer& importer) {
  const std::string why = importer.GetErrorString();
  if (why == "std::bad_alloc")
    return Error{source + ": the importer ran out of memory on this file (std::bad_alloc): a damaged file, or one that needs "
                          "more than the importer's memory limit (ImportOptions::memory_limit_mb)"};
  return Error{source + ": " + why};
}
}  // namespace

Expected<ImportedScene> import_file_in_process(const std::filesystem::path& path, const ImportOptions& options) {
  Assimp::Importer importer;
  configure(importer);
  const aiScene* scene = importer.ReadFile(path.string(), options.meshes ? kFlags : aiProcess_ValidateDataStructure);
  if (!scene) return read_failure(path.string(), importer);
  return SceneBuilder(*scene, options, path.string()).build();
}

Expected<ImportedScene> import_memory_in_process(std::span<const std::uint8_t> data, const std::string& hint, const ImportOptions& options) {
  Assimp::Importer importer;
  configure(importer);
  const aiScene* scene = importer.ReadFileFromMemory(data.data(), data.size(), options.meshes ? kFlags : aiProcess_ValidateDataStructure, hint.c_str());
  if (!scene) return read_failure("<memory." + hint + ">", importer);
  return SceneBuilder(*scene, options, "<memory." + hint + ">").build();
}

}  // namespace detail

Expected<ImportedScene> import_scene(const std::filesystem::path& path, const ImportOptions& options) {
  std::error_code ec;
  const auto status = std::filesystem::status(path, ec);
  if (!std::filesystem::exists(status)) return Error{path.string() + ": no such file"};
  if (std::filesystem::is_directory(status)) return Error{path.string() + ": is a directory"};
  // A FIFO would hold the importer until its wall-clock limit; a device could be endless.
  if (Status s = refuse_special_file(path); !s) return s.error();
  if (!options.isolate) return detail::import_file_in_process(path, options);
  if (!(options.timeout_seconds > 0)) return Error{path.string() + ": ImportOptions::timeout_seconds must be positive"};
  return detail::run_isolated(detail::make_request(false, path.string(), {}, options), path.string(), options);
}

Expected<ImportedScene> import_scene_from_memory(std::span<const std::uint8_t> data, const std::string& hint, const ImportOptions& options) {
  if (!options.isolate) return detail::import_memory_in_process(data, hint, options);
  return detail::run_isolated(detail::make_request(true, hint, std::vector<std::uint8_t>(data.begin(), data.end()), options),
                              "<memory." + hint + ">", options);
}

}  // namespace dq

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <functional>
#include <mutex>
#include <type_traits>
#include <unordered_map>

#include "dq/io/scene.hpp"

namespace dq {

namespace {

struct Rigid {
  Quaternion<double> rotation;
  Vec3<double> translation;
  double scale = 1;
  bool non_uniform = false;
};

Rigid decompose(const aiMatrix4x4& m) {
  aiVector3D s, t;
  aiQuaternion r;
  m.Decompose(s, r, t);
  Rigid out;
  out.rotation = Quaternion<double>(r.w, r.x, r.y, r.z).normalized();
  out.translation = {t.x, t.y, t.z};
  const double sx = std::abs(s.x), sy = std::abs(s.y), sz = std::abs(s.z);
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
    }
    Expected<Skeleton> skeleton = build_skeleton(raw_);
    if (!skeleton) return Error{source_ + ": " + skeleton.error().message};
    out_.skeleton = std::move(*skeleton);
    runtime_of_.assign(nodes_.size(), 0);
    for (std::size_t j = 0; j < out_.skeleton.size(); ++j) runtime_of_[static_cast<std::size_t>(out_.skeleton.raw_indices()[j])] = static_cast<std::uint32_t>(j);
    out_.joint_scale.resize(out_.skeleton.size());
    for (std::size_t i = 0; i < nodes_.size(); ++i) out_.joint_scale[runtime_of_[i]] = accumulated_scale_[i];
    if (options_.meshes)
      if (auto e = import_meshes(); !e) return e.error();
    for (unsigned a = 0; a < scene_.mNumAnimations; ++a)
      if (auto e = import_animation(*scene_.mAnimations[a]); !e) return e.error();
    return std::move(out_);
  }

 private:
  void collect(const aiNode* node, int parent) {
    // Iterative depth-first walk (hostile files can nest deeply).
    std::vector<std::pair<const aiNode*, int>> stack{{node, parent}};
    while (!stack.empty()) {
      const auto [n, p] = stack.back();
      stack.pop_back();
      const int index = static_cast<int>(nodes_.size());
      nodes_.push_back(n);
      Rigid r = decompose(n->mTransformation);
      const double parent_scale = p < 0 ? 1.0 : accumulated_scale_[static_cast<std::size_t>(p)];
      if (r.non_uniform) warn("node '" + std::string(n->mName.C_Str()) + "' has a non-uniform scale; its geometric mean is used");
      r.translation = r.translation * parent_scale;  // push the ancestors' scale into the translation
      accumulated_scale_.push_back(parent_scale * r.scale);
      rest_.push_back(r);
      std::string name = n->mName.length ? n->mName.C_Str() : "node" + std::to_string(index);
      if (by_name_.count(name)) name += "#" + std::to_string(index);  // keep names unique
      by_name_.emplace(name, static_cast<std::size_t>(index));
      raw_.add(name, p, DualQuaternion<double>::from_rotation_translation(r.rotation, r.translation));
      for (unsigned c = n->mNumChildren; c-- > 0;) stack.emplace_back(n->mChildren[c], index);
    }
  }

  int joint_of(const aiString& name) const {
    const auto it = by_name_.find(name.C_Str());
    return it == by_name_.end() ? -1 : static_cast<int>(runtime_of_[it->second]);
  }

  Status import_meshes() {
    // Which node holds which mesh.
    std::unordered_map<unsigned, int> holder;
    for (std::size_t i = 0; i < nodes_.size(); ++i)
      for (unsigned k = 0; k < nodes_[i]->mNumMeshes; ++k) holder.emplace(nodes_[i]->mMeshes[k], static_cast<int>(runtime_of_[i]));
    for (unsigned m = 0; m < scene_.mNumMeshes; ++m) {
      const aiMesh& mesh = *scene_.mMeshes[m];
      ImportedMesh out;
      out.name = mesh.mName.C_Str();
      out.node_joint = holder.count(m) ? holder[m] : -1;
      out.positions.reserve(mesh.mNumVertices);
      for (unsigned v = 0; v < mesh.mNumVertices; ++v) out.positions.push_back({mesh.mVertices[v].x, mesh.mVertices[v].y, mesh.mVertices[v].z});
      if (mesh.mNormals)
        for (unsigned v = 0; v < mesh.mNumVertices; ++v) out.normals.push_back({mesh.mNormals[v].x, mesh.mNormals[v].y, mesh.mNormals[v].z});
      for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
        const aiFace& face = mesh.mFaces[f];
        if (face.mNumIndices != 3) continue;  // points and lines are not surfaces
        for (unsigned k = 0; k < 3; ++k) {
          if (face.mIndices[k] >= mesh.mNumVertices) return Error{source_ + ": mesh '" + out.name + "' has an index out of range"};
          out.indices.push_back(face.mIndices[k]);
        }
      }
      std::vector<std::vector<SkinInfluence>> per_vertex(mesh.mNumVertices);
      for (unsigned b = 0; b < mesh.mNumBones; ++b) {
        const aiBone& bone = *mesh.mBones[b];
        const int joint = joint_of(bone.mName);
        if (joint < 0) return Error{source_ + ": mesh '" + out.name + "' has a bone '" + bone.mName.C_Str() + "' with no node"};
        out.bone_joints.push_back(static_cast<std::uint32_t>(joint));
        out.inverse_bind.push_back(to_mat4(bone.mOffsetMatrix));
        for (unsigned w = 0; w < bone.mNumWeights; ++w) {
          const aiVertexWeight& vw = bone.mWeights[w];
          if (vw.mVertexId >= mesh.mNumVertices || !std::isfinite(vw.mWeight))
            return Error{source_ + ": mesh '" + out.name + "' bone '" + bone.mName.C_Str() + "' has an invalid weight"};
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
      out_.meshes.push_back(std::move(out));
    }
    return {};
  }

  Status import_animation(const aiAnimation& a) {
    const double ticks = a.mTicksPerSecond > 0 ? a.mTicksPerSecond : 25.0;  // Assimp's documented default
    const double seconds = a.mDuration / ticks;
    if (!std::isfinite(seconds) || seconds < 0) return Error{source_ + ": animation '" + std::string(a.mName.C_Str()) + "' has an invalid duration"};
    const double rate = std::clamp(options_.sample_rate, 1e-3, 1000.0);
    const std::size_t frames = static_cast<std::size_t>(std::floor(seconds * rate + 1e-9)) + 1;
    if (frames > (1u << 22)) return Error{source_ + ": animation '" + std::string(a.mName.C_Str()) + "' is too long to resample"};
    ImportedAnimation out;
    out.name = a.mName.C_Str();
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
        const double t = static_cast<double>(f) / rate * ticks;
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
        const Quaternion<double> q = Quaternion<double>(r.w, r.x, r.y, r.z).normalized();
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
  std::unordered_map<std::string, std::size_t> by_name_;
  std::vector<std::uint32_t> runtime_of_;
  RawSkeleton raw_;
  ImportedScene out_;
};

constexpr unsigned kFlags = aiProcess_Triangulate | aiProcess_JoinIdenticalVertices | aiProcess_LimitBoneWeights |
                            aiProcess_ValidateDataStructure;

// ---- isolation: the scene crosses a pipe from the child process ----------------------------------

class Writer {
 public:
  template <class T>
  void pod(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    out_.append(reinterpret_cast<const char*>(&v), sizeof v);
  }
  template <class T>
  void vec(const std::vector<T>& v) {
    pod<std::uint64_t>(v.size());
    if (!v.empty()) out_.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
  }
  void str(const std::string& s) {
    pod<std::uint64_t>(s.size());
    out_ += s;
  }
  std::string take() { return std::move(out_); }

 private:
  std::string out_;
};

class Reader {
 public:
  explicit Reader(std::string_view data) : data_(data) {}
  template <class T>
  bool pod(T& v) {
    if (data_.size() < sizeof v) return false;
    std::memcpy(&v, data_.data(), sizeof v);
    data_.remove_prefix(sizeof v);
    return true;
  }
  template <class T>
  bool vec(std::vector<T>& v) {
    std::uint64_t n = 0;
    if (!pod(n) || n > data_.size() / std::max<std::size_t>(sizeof(T), 1)) return false;
    v.resize(n);
    if (n) std::memcpy(v.data(), data_.data(), n * sizeof(T));
    data_.remove_prefix(n * sizeof(T));
    return true;
  }
  bool str(std::string& s) {
    std::uint64_t n = 0;
    if (!pod(n) || n > data_.size()) return false;
    s.assign(data_.substr(0, n));
    data_.remove_prefix(n);
    return true;
  }
  bool done() const { return data_.empty(); }

 private:
  std::string_view data_;
};

std::string serialize(const ImportedScene& s) {
  Writer w;
  w.pod<std::uint64_t>(s.skeleton.size());
  for (std::size_t j = 0; j < s.skeleton.size(); ++j) {
    w.str(s.skeleton.names()[j]);
    w.pod(s.skeleton.parents()[j]);
    w.pod(s.skeleton.rest_pose()[j]);
    w.pod(s.skeleton.end_sites()[j]);
  }
  w.vec(s.joint_scale);
  w.pod<std::uint64_t>(s.meshes.size());
  for (const ImportedMesh& m : s.meshes) {
    w.str(m.name);
    w.vec(m.positions);
    w.vec(m.normals);
    w.vec(m.indices);
    w.vec(m.influence_offsets);
    w.vec(m.influences);
    w.vec(m.bone_joints);
    w.vec(m.inverse_bind);
    w.pod(m.node_joint);
  }
  w.pod<std::uint64_t>(s.animations.size());
  for (const ImportedAnimation& a : s.animations) {
    w.str(a.name);
    w.pod(a.animation.frame_time);
    w.pod<std::uint64_t>(a.animation.frame_count);
    w.pod<std::uint64_t>(a.animation.joint_count);
    w.vec(a.animation.locals);
  }
  w.pod<std::uint64_t>(s.warnings.size());
  for (const std::string& x : s.warnings) w.str(x);
  return w.take();
}

Expected<ImportedScene> deserialize(std::string_view data, const std::string& source) {
  Reader r(data);
  ImportedScene s;
  const Error broken{source + ": the isolated importer returned a damaged result"};
  std::uint64_t n = 0;
  if (!r.pod(n) || n > data.size()) return broken;
  RawSkeleton raw;
  for (std::uint64_t j = 0; j < n; ++j) {
    RawSkeleton::Joint joint;
    std::uint8_t end = 0;
    if (!r.str(joint.name) || !r.pod(joint.parent) || !r.pod(joint.rest) || !r.pod(end)) return broken;
    joint.is_end_site = end != 0;
    raw.joints.push_back(std::move(joint));
  }
  Expected<Skeleton> skeleton = build_skeleton(raw);
  if (!skeleton) return Error{source + ": " + skeleton.error().message};
  s.skeleton = std::move(*skeleton);
  if (!r.vec(s.joint_scale) || !r.pod(n) || n > data.size()) return broken;
  s.meshes.resize(n);
  for (ImportedMesh& m : s.meshes)
    if (!r.str(m.name) || !r.vec(m.positions) || !r.vec(m.normals) || !r.vec(m.indices) || !r.vec(m.influence_offsets) ||
        !r.vec(m.influences) || !r.vec(m.bone_joints) || !r.vec(m.inverse_bind) || !r.pod(m.node_joint))
      return broken;
  if (!r.pod(n) || n > data.size()) return broken;
  s.animations.resize(n);
  for (ImportedAnimation& a : s.animations) {
    std::uint64_t frames = 0, joints = 0;
    if (!r.str(a.name) || !r.pod(a.animation.frame_time) || !r.pod(frames) || !r.pod(joints) || !r.vec(a.animation.locals)) return broken;
    a.animation.frame_count = frames;
    a.animation.joint_count = joints;
    if (a.animation.locals.size() != frames * joints) return broken;
  }
  if (!r.pod(n) || n > data.size()) return broken;
  s.warnings.resize(n);
  for (std::string& x : s.warnings)
    if (!r.str(x)) return broken;
  if (!r.done()) return broken;
  return s;
}

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
constexpr bool kSanitized = true;  // sanitizers reserve large address ranges: no RLIMIT_AS
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer)
constexpr bool kSanitized = true;
#else
constexpr bool kSanitized = false;
#endif
#else
constexpr bool kSanitized = false;
#endif

/// Runs `work` in a child process and returns its result; a crash, a hang past the timeout, or
/// an exhausted memory limit in the child becomes an Error naming the file.
Expected<ImportedScene> run_isolated(const std::function<Expected<ImportedScene>()>& work, const std::string& source,
                                     const ImportOptions& options) {
  // One fork at a time in this process: two importing threads forking at once would each leak
  // its pipe into the other's child, and a child copied while a sibling thread held a lock of
  // ours could block on it.
  static std::mutex fork_mutex;
  std::unique_lock lock(fork_mutex);
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0) return Error{source + ": cannot create a pipe: " + std::strerror(errno)};
  const pid_t pid = ::fork();
  if (pid < 0) {
    ::close(fds[0]);
    ::close(fds[1]);
    return Error{source + ": cannot start the importer process: " + std::strerror(errno)};
  }
  if (pid == 0) {  // child: import, send the result, leave without running the parent's exit code
    ::close(fds[0]);
    if (const int null = ::open("/dev/null", O_WRONLY); null >= 0) ::dup2(null, 2);  // glibc's abort messages
    // Keep only stdin/out/err and the result pipe (as fd 3): no descriptor of the parent's, such as
    // another import's pipe, stays open in this child.
    if (fds[1] != 3) {
      ::dup2(fds[1], 3);
      fds[1] = 3;
    }
    ::close_range(4, ~0U, 0);
    if (!kSanitized && options.memory_limit_mb > 0) {
      const rlim_t bytes = static_cast<rlim_t>(options.memory_limit_mb) << 20;
      const rlimit limit{bytes, bytes};
      ::setrlimit(RLIMIT_AS, &limit);
    }
    std::string payload;
    try {
      const Expected<ImportedScene> result = work();
      payload = result ? "S" + serialize(*result) : "E" + result.error().message;
    } catch (const std::exception& e) {
      payload = "E" + source + ": the importer failed: " + e.what();
    }
    for (std::size_t done = 0; done < payload.size();) {
      const ssize_t k = ::write(fds[1], payload.data() + done, payload.size() - done);
      if (k < 0 && errno == EINTR) continue;
      if (k <= 0) ::_exit(3);
      done += static_cast<std::size_t>(k);
    }
    ::_exit(0);
  }
  ::close(fds[1]);
  lock.unlock();
  std::string payload;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(options.timeout_seconds);
  bool timed_out = false;
  while (true) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now()).count();
    if (left <= 0) {
      timed_out = true;
      break;
    }
    pollfd p{fds[0], POLLIN, 0};
    const int ready = ::poll(&p, 1, static_cast<int>(std::min<long long>(left, 1000)));
    if (ready < 0 && errno == EINTR) continue;
    if (ready <= 0) continue;
    char buf[65536];
    const ssize_t k = ::read(fds[0], buf, sizeof buf);
    if (k < 0 && errno == EINTR) continue;
    if (k <= 0) break;  // EOF: the child is done (or died)
    payload.append(buf, static_cast<std::size_t>(k));
  }
  ::close(fds[0]);
  if (timed_out) ::kill(pid, SIGKILL);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (timed_out) return Error{source + ": the importer did not finish within " + std::to_string(options.timeout_seconds) + " s"};
  if (WIFSIGNALED(status))
    return Error{source + ": the importer (Assimp) crashed on this file (" + std::string(::strsignal(WTERMSIG(status))) + ")"};
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0 || payload.empty())
    return Error{source + ": the importer failed on this file (out of memory?)"};
  if (payload[0] == 'E') return Error{payload.substr(1)};
  return deserialize(std::string_view(payload).substr(1), source);
}

Expected<ImportedScene> import_file_in_process(const std::filesystem::path& path, const ImportOptions& options) {
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFile(path.string(), options.meshes ? kFlags : aiProcess_ValidateDataStructure);
  if (!scene) return Error{path.string() + ": " + importer.GetErrorString()};
  return SceneBuilder(*scene, options, path.string()).build();
}

Expected<ImportedScene> import_memory_in_process(std::span<const std::uint8_t> data, const std::string& hint, const ImportOptions& options) {
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFileFromMemory(data.data(), data.size(), options.meshes ? kFlags : aiProcess_ValidateDataStructure, hint.c_str());
  if (!scene) return Error{"<memory." + hint + ">: " + importer.GetErrorString()};
  return SceneBuilder(*scene, options, "<memory." + hint + ">").build();
}

}  // namespace

Expected<ImportedScene> import_scene(const std::filesystem::path& path, const ImportOptions& options) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return Error{path.string() + ": no such file"};
  if (!options.isolate) return import_file_in_process(path, options);
  return run_isolated([&] { return import_file_in_process(path, options); }, path.string(), options);
}

Expected<ImportedScene> import_scene_from_memory(std::span<const std::uint8_t> data, const std::string& hint, const ImportOptions& options) {
  if (!options.isolate) return import_memory_in_process(data, hint, options);
  return run_isolated([&] { return import_memory_in_process(data, hint, options); }, "<memory." + hint + ">", options);
}

}  // namespace dq

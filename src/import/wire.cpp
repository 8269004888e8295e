// The byte format between the caller and the import worker (src/import/import_internal.hpp).
#include <algorithm>
#include <cstring>
#include <limits>
#include <type_traits>

#include "import_internal.hpp"

namespace dq::detail {

namespace {

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
  void str(std::string_view s) {
    pod<std::uint64_t>(s.size());
    out_ += s;
  }
  std::string take() { return std::move(out_); }

 private:
  std::string out_;
};

/// Reads what a Writer wrote. Before anything is allocated, a count is checked against the bytes
/// left (each item takes at least `wire` bytes) and against the allocation budget (each item
/// takes `memory` bytes once stored), so no input makes the reader allocate more than its budget.
class Reader {
 public:
  Reader(std::string_view data, std::size_t budget) : data_(data), budget_(budget) {}
  template <class T>
  bool pod(T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    if (data_.size() < sizeof v) return false;
    std::memcpy(&v, data_.data(), sizeof v);
    data_.remove_prefix(sizeof v);
    return true;
  }
  bool count(std::uint64_t& n, std::size_t wire, std::size_t memory) {
    if (!pod(n) || n > data_.size() / wire) return false;
    if (n > budget_ / memory) {
      over_budget_ = true;
      return false;
    }
    budget_ -= static_cast<std::size_t>(n) * memory;
    return true;
  }
  template <class T>
  bool vec(std::vector<T>& v) {
    std::uint64_t n = 0;
    if (!count(n, sizeof(T), sizeof(T))) return false;
    v.resize(static_cast<std::size_t>(n));
    if (n) std::memcpy(v.data(), data_.data(), v.size() * sizeof(T));
    data_.remove_prefix(v.size() * sizeof(T));
    return true;
  }
  bool str(std::string& s) {
    std::uint64_t n = 0;
    if (!count(n, 1, 1)) return false;
    s.assign(data_.substr(0, static_cast<std::size_t>(n)));
    data_.remove_prefix(s.size());
    return true;
  }
  bool done() const { return data_.empty(); }
  bool over_budget() const { return over_budget_; }

 private:
  std::string_view data_;
  std::size_t budget_;
  bool over_budget_ = false;
};

// Smallest encodings, for the counts' first check.
constexpr std::size_t kJointWire = 8 + sizeof(int) + sizeof(DualQuaternion<double>) + 1;
constexpr std::size_t kMeshWire = 8 + 8 * 8 + sizeof(int);
constexpr std::size_t kAnimationWire = 8 + sizeof(double) + 8 + 8 + 8;

void write_scene(Writer& w, const ImportedScene& s) {
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
    w.vec(m.tangents);
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
}

/// What the in-process importer guarantees, checked again on what came through the socket.
bool consistent(const ImportedScene& s) {
  const std::size_t joints = s.skeleton.size();
  if (s.joint_scale.size() != joints) return false;
  for (const ImportedMesh& m : s.meshes) {
    if (m.node_joint >= static_cast<int>(joints) || m.node_joint < -1) return false;
    if (!m.normals.empty() && m.normals.size() != m.positions.size()) return false;
    if (!m.tangents.empty() && m.tangents.size() != m.positions.size()) return false;
    for (std::uint32_t i : m.indices)
      if (i >= m.positions.size()) return false;
    for (std::uint32_t j : m.bone_joints)
      if (j >= joints) return false;
    if (m.inverse_bind.size() != m.bone_joints.size()) return false;
    for (const SkinInfluence& i : m.influences)
      if (i.joint >= joints) return false;
    if (!m.influence_offsets.empty()) {
      if (m.influence_offsets.size() != m.positions.size() + 1 || m.influence_offsets.front() != 0 ||
          m.influence_offsets.back() != m.influences.size() || !std::is_sorted(m.influence_offsets.begin(), m.influence_offsets.end()))
        return false;
    } else if (!m.influences.empty()) {
      return false;
    }
  }
  for (const ImportedAnimation& a : s.animations)
    if (a.animation.joint_count != joints) return false;
  return true;
}

}  // namespace

std::string encode_request(const ImportRequest& r) {
  Writer w;
  w.pod<std::uint8_t>(r.from_memory);
  w.pod(r.sample_rate);
  w.pod<std::uint8_t>(r.meshes);
  w.pod<std::uint8_t>(r.lights_and_cameras);
  w.pod<std::uint64_t>(r.result_limit_mb);
  w.str(r.path_or_hint);
  w.vec(r.data);
  return w.take();
}

std::optional<ImportRequest> decode_request(std::string_view bytes) {
  Reader r(bytes, std::numeric_limits<std::size_t>::max());
  ImportRequest out;
  std::uint8_t from_memory = 0, meshes = 0, lights_and_cameras = 0;
  std::uint64_t result_limit_mb = 0;
  if (!r.pod(from_memory) || !r.pod(out.sample_rate) || !r.pod(meshes) || !r.pod(lights_and_cameras) || !r.pod(result_limit_mb) ||
      !r.str(out.path_or_hint) || !r.vec(out.data) || !r.done())
    return std::nullopt;
  out.from_memory = from_memory != 0;
  out.meshes = meshes != 0;
  out.lights_and_cameras = lights_and_cameras != 0;
  out.result_limit_mb = static_cast<std::size_t>(result_limit_mb);
  return out;
}

std::string encode_response(const Expected<ImportedScene>& result) {
  Writer body;
  if (result) {
    body.pod('S');
    write_scene(body, *result);
  } else {
    body.pod('E');
    body.str(result.error().message);
  }
  std::string payload = body.take();
  Writer framed;
  framed.pod<std::uint64_t>(payload.size());
  return framed.take() + payload;
}

Expected<ImportedScene> decode_response(std::string_view payload, const std::string& source, std::size_t budget_bytes) {
  Reader r(payload, budget_bytes);
  auto broken = [&] {
    if (r.over_budget())
      return Error{source + ": the importer's result needs more than the " + std::to_string(budget_bytes >> 20) +
                   " MB allowed (ImportOptions::result_limit_mb)"};
    return Error{source + ": the isolated importer returned a damaged result"};
  };
  char kind = 0;
  if (!r.pod(kind)) return broken();
  if (kind == 'E') {
    std::string message;
    if (!r.str(message) || !r.done()) return broken();
    return Error{std::move(message)};
  }
  if (kind != 'S') return broken();
  std::uint64_t n = 0;
  // A joint is stored twice for a while: in the RawSkeleton and in the Skeleton built from it.
  if (!r.count(n, kJointWire, 2 * sizeof(RawSkeleton::Joint))) return broken();
  RawSkeleton raw;
  raw.joints.resize(static_cast<std::size_t>(n));
  for (RawSkeleton::Joint& joint : raw.joints) {
    std::uint8_t end = 0;
    if (!r.str(joint.name) || !r.pod(joint.parent) || !r.pod(joint.rest) || !r.pod(end)) return broken();
    joint.is_end_site = end != 0;
  }
  Expected<Skeleton> skeleton = build_skeleton(raw);
  if (!skeleton) return Error{source + ": " + skeleton.error().message};
  ImportedScene s;
  s.skeleton = std::move(*skeleton);
  if (!r.vec(s.joint_scale) || !r.count(n, kMeshWire, sizeof(ImportedMesh))) return broken();
  s.meshes.resize(static_cast<std::size_t>(n));
  for (ImportedMesh& m : s.meshes)
    if (!r.str(m.name) || !r.vec(m.positions) || !r.vec(m.normals) || !r.vec(m.tangents) || !r.vec(m.indices) || !r.vec(m.influence_offsets) ||
        !r.vec(m.influences) || !r.vec(m.bone_joints) || !r.vec(m.inverse_bind) || !r.pod(m.node_joint))
      return broken();
  if (!r.count(n, kAnimationWire, sizeof(ImportedAnimation))) return broken();
  s.animations.resize(static_cast<std::size_t>(n));
  for (ImportedAnimation& a : s.animations) {
    std::uint64_t frames = 0, joints = 0, cells = 0;
    if (!r.str(a.name) || !r.pod(a.animation.frame_time) || !r.pod(frames) || !r.pod(joints) || !r.vec(a.animation.locals)) return broken();
    if (__builtin_mul_overflow(frames, joints, &cells) || cells != a.animation.locals.size()) return broken();
    a.animation.frame_count = static_cast<std::size_t>(frames);
    a.animation.joint_count = static_cast<std::size_t>(joints);
  }
  if (!r.count(n, 8, sizeof(std::string))) return broken();
  s.warnings.resize(static_cast<std::size_t>(n));
  for (std::string& x : s.warnings)
    if (!r.str(x)) return broken();
  if (!r.done() || !consistent(s)) return broken();
  return s;
}

}  // namespace dq::detail

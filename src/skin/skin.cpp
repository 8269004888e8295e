#include "dq/skin/skin.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

#include "dq/convert/matrix.hpp"

namespace dq {

namespace {

bool finite(const Vec3<float>& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

Mat3<double> block(const Mat4<double>& m) {
  Mat3<double> r;
  for (int c = 0; c < 3; ++c)
    for (int row = 0; row < 3; ++row) r(row, c) = m(row, c);
  return r;
}

double determinant(const Mat3<double>& a) {
  return a(0, 0) * (a(1, 1) * a(2, 2) - a(1, 2) * a(2, 1)) - a(0, 1) * (a(1, 0) * a(2, 2) - a(1, 2) * a(2, 0)) +
         a(0, 2) * (a(1, 0) * a(2, 1) - a(1, 1) * a(2, 0));
}

/// B = S(scale) · inverse_bind split into a rigid part and a symmetric scale/shear (polar).
Expected<SkinBone> split_bind(const Mat4<double>& inverse_bind, double scale, std::size_t bone) {
  const std::string where = "bone " + std::to_string(bone) + ": ";
  for (double v : inverse_bind.m)
    if (!std::isfinite(v)) return Error{where + "the inverse bind matrix is not finite"};
  if (inverse_bind(3, 0) != 0 || inverse_bind(3, 1) != 0 || inverse_bind(3, 2) != 0 || inverse_bind(3, 3) != 1)
    return Error{where + "the inverse bind matrix is not affine (last row is not 0 0 0 1)"};
  if (!(scale > 0) || !std::isfinite(scale)) return Error{where + "the bone scale is not a positive number"};
  const Mat3<double> a = block(inverse_bind) * scale;
  const double det = determinant(a);
  const double size = std::cbrt(std::abs(det));
  if (!(size > 0) || !std::isfinite(size)) return Error{where + "the inverse bind matrix is singular"};
  if (det < 0) return Error{where + "the inverse bind matrix mirrors (negative determinant); skinning needs rotations"};
  const Mat3<double> u = orthonormalize_polar(a, 60);
  if (!(orthonormality_error(u) < 1e-9)) return Error{where + "the inverse bind matrix has no polar decomposition (too ill-conditioned)"};
  Mat3<double> p = transpose(u) * a;
  // P is symmetric up to rounding; make it exactly so, and exactly the identity when it is one
  // to rounding (a rigid bind: then the kernels skip the linear phase).
  bool identity = true;
  for (int r = 0; r < 3; ++r)
    for (int c = r; c < 3; ++c) {
      const double s = 0.5 * (p(r, c) + p(c, r));
      p(r, c) = p(c, r) = s;
      if (std::abs(s - (r == c ? 1.0 : 0.0)) > 1e-6) identity = false;
    }
  SkinBone out;
  out.rigid = DualQuaternion<double>::from_rotation_translation(Quaternion<double>::from_matrix(u),
                                                                {scale * inverse_bind(0, 3), scale * inverse_bind(1, 3), scale * inverse_bind(2, 3)});
  out.scale_shear = identity ? Mat3<double>::identity() : p;
  return out;
}

}  // namespace

struct SkinCenters {
  static void compute(Skin& s, double sigma);
};

Expected<Skin> build_skin(const RawSkin& raw, const SkinOptions& options) {
  const std::size_t n = raw.positions.size();
  const std::size_t bones = raw.inverse_bind.size();
  if (!raw.normals.empty() && raw.normals.size() != n) return Error{"skin: " + std::to_string(raw.normals.size()) + " normals for " + std::to_string(n) + " vertices"};
  if (!raw.tangents.empty() && raw.tangents.size() != n) return Error{"skin: " + std::to_string(raw.tangents.size()) + " tangents for " + std::to_string(n) + " vertices"};
  if (raw.influence_offsets.size() != n + 1) return Error{"skin: influence offsets must have one entry per vertex plus one"};
  if (raw.influence_offsets.front() != 0 || raw.influence_offsets.back() != raw.influences.size())
    return Error{"skin: influence offsets must start at 0 and end at the number of influences"};
  if (!raw.bone_scale.empty() && raw.bone_scale.size() != bones) return Error{"skin: bone_scale must be empty or have one entry per bone"};
  if (raw.triangles.size() % 3 != 0) return Error{"skin: the triangle index count is not a multiple of 3"};
  if (bones == 0) return Error{"skin: no bones"};
  for (std::size_t i = 0; i < raw.triangles.size(); ++i)
    if (raw.triangles[i] >= n) return Error{"skin: triangle " + std::to_string(i / 3) + " has a vertex index out of range"};

  Skin s;
  s.vertex_count_ = n;
  for (std::size_t b = 0; b < bones; ++b) {
    Expected<SkinBone> bone = split_bind(raw.inverse_bind[b], raw.bone_scale.empty() ? 1.0 : raw.bone_scale[b], b);
    if (!bone) return bone.error();
    s.has_scale_shear_ = s.has_scale_shear_ || !(bone->scale_shear == Mat3<double>::identity());
    s.bones_.push_back(*bone);
  }

  // Influences: validated, normalized, in canonical order (weight descending, then bone), padded.
  std::vector<RawSkinInfluence> sorted;
  std::size_t slots = 1;
  for (std::size_t v = 0; v < n; ++v) {
    if (raw.influence_offsets[v + 1] < raw.influence_offsets[v]) return Error{"skin: influence offsets decrease at vertex " + std::to_string(v)};
    slots = std::max<std::size_t>(slots, raw.influence_offsets[v + 1] - raw.influence_offsets[v]);
  }
  s.slots_ = slots;
  // Values of the same size, so that both tables' arrays lie equally far apart (Skin::slot_stride).
  static_assert(sizeof(std::uint32_t) == sizeof(float));
  s.bone_ = ComponentArrays<std::uint32_t, std::dynamic_extent>(n, slots);
  s.weight_ = ComponentArrays<float, std::dynamic_extent>(n, slots);
  for (std::size_t v = 0; v < n; ++v) {
    const std::string where = "skin: vertex " + std::to_string(v) + ": ";
    if (!finite(raw.positions[v])) return Error{where + "the position is not finite"};
    if (!raw.normals.empty() && !finite(raw.normals[v])) return Error{where + "the normal is not finite"};
    if (!raw.tangents.empty() && !finite(raw.tangents[v])) return Error{where + "the tangent is not finite"};
    sorted.assign(raw.influences.begin() + raw.influence_offsets[v], raw.influences.begin() + raw.influence_offsets[v + 1]);
    double sum = 0;
    for (const RawSkinInfluence& i : sorted) {
      if (i.bone >= bones) return Error{where + "bone index " + std::to_string(i.bone) + " is out of range (" + std::to_string(bones) + " bones)"};
      if (!std::isfinite(i.weight) || i.weight < 0) return Error{where + "weight " + std::to_string(i.weight) + " is not a finite non-negative number"};
      sum += static_cast<double>(i.weight);
    }
    if (!(sum > 0)) return Error{where + "has no weight"};
    if (std::abs(sum - 1) > options.weight_tolerance) {
      if (options.weights == WeightPolicy::reject) return Error{where + "the weights sum to " + std::to_string(sum) + ", not 1"};
      ++s.renormalized_;
    }
    std::sort(sorted.begin(), sorted.end(), [](const RawSkinInfluence& a, const RawSkinInfluence& b) {
      return a.weight != b.weight ? a.weight > b.weight : a.bone < b.bone;
    });
    for (std::size_t k = 0; k < slots; ++k) {
      // Padding repeats the pivot's bone with weight 0 (no contribution, a valid palette index).
      s.bone_[k][v] = k < sorted.size() ? sorted[k].bone : sorted[0].bone;
      s.weight_[k][v] = k < sorted.size() ? static_cast<float>(static_cast<double>(sorted[k].weight) / sum) : 0.0f;
    }
  }
  // The coordinate arrays: positions, then normals, tangents and centres where the skin has them.
  std::size_t arrays = 3;
  for (const bool present : {!raw.normals.empty(), !raw.tangents.empty(), options.centers_of_rotation}) arrays += present ? 3 : 0;
  s.coordinates_ = ComponentArrays<float, std::dynamic_extent>(n, arrays);
  std::size_t next = 0;  // the next unused array
  auto split = [&](const std::vector<Vec3<float>>& in) -> std::size_t {
    if (in.empty()) return 0;
    for (std::size_t v = 0; v < n; ++v) s.coordinates_[next][v] = in[v].x, s.coordinates_[next + 1][v] = in[v].y, s.coordinates_[next + 2][v] = in[v].z;
    return std::exchange(next, next + 3);
  };
  split(raw.positions);
  s.normals_at_ = split(raw.normals);
  s.tangents_at_ = split(raw.tangents);
  s.triangles_ = raw.triangles;
  if (options.centers_of_rotation) {
    s.centers_at_ = next;
    SkinCenters::compute(s, options.cor_sigma);
  }
  return s;
}

void SkinCenters::compute(Skin& s, double sigma) {
  const std::size_t n = s.vertex_count_, slots = s.slots_;
  using Sparse = std::vector<std::pair<std::uint32_t, double>>;  // (bone, weight), sorted by bone
  auto weights_of = [&](std::size_t v) {
    Sparse w;
    for (std::size_t k = 0; k < slots; ++k)
      if (s.weight_[k][v] > 0) w.emplace_back(s.bone_[k][v], s.weight_[k][v]);
    std::sort(w.begin(), w.end());
    return w;
  };
  std::vector<Sparse> vertex(n);
  for (std::size_t v = 0; v < n; ++v) vertex[v] = weights_of(v);

  // Triangles: mean weights, area, centroid; indexed by every pair of bones they carry.
  const std::size_t triangles = s.triangles_.size() / 3;
  std::vector<Sparse> tri_w(triangles);
  std::vector<double> area(triangles);
  std::vector<Vec3<double>> centroid(triangles);
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::vector<std::uint32_t>> by_pair;
  for (std::size_t t = 0; t < triangles; ++t) {
    std::map<std::uint32_t, double> sum;
    Vec3<double> p[3];
    for (int c = 0; c < 3; ++c) {
      const std::size_t v = s.triangles_[3 * t + static_cast<std::size_t>(c)];
      p[c] = s.position(v).cast<double>();
      for (const auto& [b, w] : vertex[v]) sum[b] += w / 3;
    }
    tri_w[t].assign(sum.begin(), sum.end());
    area[t] = 0.5 * norm(cross(p[1] - p[0], p[2] - p[0]));
    centroid[t] = (p[0] + p[1] + p[2]) / 3.0;
    for (std::size_t i = 0; i < tri_w[t].size(); ++i)
      for (std::size_t j = i + 1; j < tri_w[t].size(); ++j) by_pair[{tri_w[t][i].first, tri_w[t][j].first}].push_back(static_cast<std::uint32_t>(t));
  }
  // Similarity (Le and Hodgins 2016, eq. 3) over the bone pairs both weight vectors carry.
  const double inv_sigma2 = 1.0 / (sigma * sigma);
  auto similarity = [&](const Sparse& a, const Sparse& b) {
    double sum = 0;
    for (std::size_t i = 0; i < a.size(); ++i)
      for (std::size_t j = i + 1; j < a.size(); ++j) {
        double bi = 0, bj = 0;
        for (const auto& [bone, w] : b) {
          if (bone == a[i].first) bi = w;
          if (bone == a[j].first) bj = w;
        }
        if (bi == 0 || bj == 0) continue;
        const double d = a[i].second * bj - a[j].second * bi;
        sum += a[i].second * a[j].second * bi * bj * std::exp(-d * d * inv_sigma2);
      }
    return sum;
  };
  const std::span<float> cx = s.coordinates_[s.centers_at_], cy = s.coordinates_[s.centers_at_ + 1], cz = s.coordinates_[s.centers_at_ + 2];
  std::vector<std::size_t> seen(triangles, static_cast<std::size_t>(-1));
  for (std::size_t v = 0; v < n; ++v) {
    Vec3<double> acc{0, 0, 0};
    double total = 0;
    const Sparse& w = vertex[v];
    for (std::size_t i = 0; i < w.size(); ++i)
      for (std::size_t j = i + 1; j < w.size(); ++j) {
        const auto it = by_pair.find({w[i].first, w[j].first});
        if (it == by_pair.end()) continue;
        for (std::uint32_t t : it->second) {
          if (seen[t] == v) continue;
          seen[t] = v;
          const double k = similarity(w, tri_w[t]) * area[t];
          acc += centroid[t] * k;
          total += k;
        }
      }
    const Vec3<double> c = total > 0 ? acc / total : s.position(v).cast<double>();
    cx[v] = static_cast<float>(c.x), cy[v] = static_cast<float>(c.y), cz[v] = static_cast<float>(c.z);
  }
}

}  // namespace dq

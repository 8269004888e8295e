#include "dq/skin/skinning.hpp"

#include <algorithm>
#include <cmath>

#include "dq/convert/matrix.hpp"
#include "dq/util/assert.hpp"

namespace dq {

SkinPalette::SkinPalette(std::size_t bones) {
  for (auto& a : m) a.assign(bones, 0.0f);
  for (auto& a : q) a.assign(bones, 0.0f);
}

void update_palette(const Skin& skin, std::span<const DualQuaternion<double>> bone_world, SkinPalette& palette) {
  DQ_PRECONDITION(bone_world.size() == skin.bone_count() && palette.size() == skin.bone_count(),
                  "update_palette needs one world transform and one palette entry per bone of the skin");
  for (std::size_t b = 0; b < skin.bone_count(); ++b) {
    const SkinBone& bone = skin.bones()[b];
    const DualQuaternion<double> d = bone_world[b] * bone.rigid;
    const Mat34<double> rigid = to_mat34(d);
    const Mat3<double> full = rotation_block(rigid) * bone.scale_shear;
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) palette.m[r * 4 + c][b] = static_cast<float>(full(r, c));
      palette.m[r * 4 + 3][b] = static_cast<float>(rigid(r, 3));
    }
    const double c[8] = {d.real.w, d.real.x, d.real.y, d.real.z, d.dual.w, d.dual.x, d.dual.y, d.dual.z};
    for (int k = 0; k < 8; ++k) palette.q[k][b] = static_cast<float>(c[k]);
  }
}

Status SkinningJob::validate() const {
  if (!skin || !palette) return Error{"skinning job: no skin or no palette"};
  if (palette->size() != skin->bone_count()) return Error{"skinning job: the palette has " + std::to_string(palette->size()) + " bones, the skin " + std::to_string(skin->bone_count())};
  if (first > skin->vertex_count() || count > skin->vertex_count() - first) return Error{"skinning job: the vertex range exceeds the skin"};
  const std::size_t end = first + count;
  for (auto s : {out.px, out.py, out.pz})
    if (s.size() < end) return Error{"skinning job: a position array is shorter than the vertex range"};
  for (auto s : {out.nx, out.ny, out.nz})
    if (!s.empty() && (s.size() < end || !skin->has_normals())) return Error{"skinning job: normals requested but the skin has none or an array is too short"};
  for (auto s : {out.tx, out.ty, out.tz})
    if (!s.empty() && (s.size() < end || !skin->has_tangents())) return Error{"skinning job: tangents requested but the skin has none or an array is too short"};
  if (method == SkinningMethod::cor && !skin->has_centers()) return Error{"skinning job: CoR needs a skin built with centres of rotation"};
  return {};
}

namespace {

struct V3 {
  float x, y, z;
};
inline V3 cross3(V3 a, V3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
inline V3 add(V3 a, V3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline V3 scale(V3 a, float s) { return {a.x * s, a.y * s, a.z * s}; }
inline V3 unit(V3 a) {
  const float n = std::sqrt(a.x * a.x + a.y * a.y + a.z * a.z);
  return n > 0 ? scale(a, 1.0f / n) : a;
}
/// The linear part of a 3x4 matrix (row-major a[r*4+c]) times v.
inline V3 linear(const float* a, V3 v) {
  return {a[0] * v.x + a[1] * v.y + a[2] * v.z, a[4] * v.x + a[5] * v.y + a[6] * v.z, a[8] * v.x + a[9] * v.y + a[10] * v.z};
}
inline V3 affine(const float* a, V3 v) { return add(linear(a, v), V3{a[3], a[7], a[11]}); }
/// The cofactor matrix's linear action (det · A⁻ᵀ): how a normal transforms, up to length.
inline V3 cofactor(const float* a, V3 n) {
  const V3 c0{a[0], a[4], a[8]}, c1{a[1], a[5], a[9]}, c2{a[2], a[6], a[10]};
  const V3 r0 = cross3(c1, c2), r1 = cross3(c2, c0), r2 = cross3(c0, c1);
  return {r0.x * n.x + r1.x * n.y + r2.x * n.z, r0.y * n.x + r1.y * n.y + r2.y * n.z, r0.z * n.x + r1.z * n.y + r2.z * n.z};
}
/// Rotation of v by the unit quaternion (w, u): v + 2w (u × v) + 2 u × (u × v).
inline V3 rotate(float w, V3 u, V3 v) {
  const V3 t = scale(cross3(u, v), 2.0f);
  return add(add(v, scale(t, w)), cross3(u, t));
}

template <SkinningMethod M>
void skin_range(const Skin& skin, const SkinPalette& pal, const SkinnedVertices& out, std::size_t b, std::size_t e) {
  const std::size_t n = skin.vertex_count(), slots = skin.slots();
  const std::uint32_t* bone = skin.slot_bones().data();
  const float* weight = skin.slot_weights().data();
  const bool normals = !out.nx.empty(), tangents = !out.tx.empty();
  // The linear phase (Kavan's two-phase method) is needed by DQS and CoR only when a bind scales.
  const bool scaled = M != SkinningMethod::lbs && skin.has_scale_shear();
  for (std::size_t v = b; v < e; ++v) {
    const V3 p{skin.px()[v], skin.py()[v], skin.pz()[v]};
    float mat[12] = {};   // blended 3x4 matrix (LBS, CoR)
    float dq[8] = {};     // blended dual quaternion (DQS; CoR uses its real part)
    float lin[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};  // blended scale/shear (two-phase)
    if constexpr (M != SkinningMethod::lbs) {
      const std::uint32_t j0 = bone[v];  // slot 0: the pivot (largest weight, then lowest bone)
      const float r0w = pal.q[0][j0], r0x = pal.q[1][j0], r0y = pal.q[2][j0], r0z = pal.q[3][j0];
      for (std::size_t k = 0; k < slots; ++k) {
        const std::uint32_t j = bone[k * n + v];
        const float w = weight[k * n + v];
        const float d = pal.q[0][j] * r0w + pal.q[1][j] * r0x + pal.q[2][j] * r0y + pal.q[3][j] * r0z;
        const float s = std::copysign(w, d);  // antipodality: the hemisphere of the pivot
        const int parts = M == SkinningMethod::dqs ? 8 : 4;
        for (int c = 0; c < parts; ++c) dq[c] += s * pal.q[c][j];
      }
    }
    if constexpr (M != SkinningMethod::dqs) {
      for (std::size_t k = 0; k < slots; ++k) {
        const std::uint32_t j = bone[k * n + v];
        const float w = weight[k * n + v];
        for (int c = 0; c < 12; ++c) mat[c] += w * pal.m[c][j];
      }
    }
    if (scaled) {
      for (float& x : lin) x = 0;
      for (std::size_t k = 0; k < slots; ++k) {
        const std::uint32_t j = bone[k * n + v];
        const float w = weight[k * n + v];
        const Mat3<double>& ps = skin.bones()[j].scale_shear;
        for (int r = 0; r < 3; ++r)
          for (int c = 0; c < 3; ++c) lin[r * 4 + c] += w * static_cast<float>(ps(r, c));
      }
    }
    auto write = [&](V3 x, std::span<float> ox, std::span<float> oy, std::span<float> oz) { ox[v] = x.x, oy[v] = x.y, oz[v] = x.z; };
    if constexpr (M == SkinningMethod::lbs) {
      write(affine(mat, p), out.px, out.py, out.pz);
      if (normals) write(unit(cofactor(mat, {skin.nx()[v], skin.ny()[v], skin.nz()[v]})), out.nx, out.ny, out.nz);
      if (tangents) write(unit(linear(mat, {skin.tx()[v], skin.ty()[v], skin.tz()[v]})), out.tx, out.ty, out.tz);
    } else {
      const float inv = 1.0f / std::sqrt(dq[0] * dq[0] + dq[1] * dq[1] + dq[2] * dq[2] + dq[3] * dq[3]);
      const float w = dq[0] * inv;
      const V3 u{dq[1] * inv, dq[2] * inv, dq[3] * inv};
      if constexpr (M == SkinningMethod::dqs) {
        // Translation of the normalized blend: 2 (w d⃗ − d_w u + u × d⃗), d the dual part / |real|.
        const float dw = dq[4] * inv;
        const V3 d{dq[5] * inv, dq[6] * inv, dq[7] * inv};
        const V3 t = scale(add(add(scale(d, w), scale(u, -dw)), cross3(u, d)), 2.0f);
        write(add(rotate(w, u, scaled ? linear(lin, p) : p), t), out.px, out.py, out.pz);
      } else {
        // CoR: rotate about the centre c by the blended rotation, move c by the blended matrix.
        const V3 c{skin.cx()[v], skin.cy()[v], skin.cz()[v]};
        const V3 rel{p.x - c.x, p.y - c.y, p.z - c.z};
        write(add(rotate(w, u, scaled ? linear(lin, rel) : rel), affine(mat, c)), out.px, out.py, out.pz);
      }
      if (normals) {
        const V3 nv{skin.nx()[v], skin.ny()[v], skin.nz()[v]};
        write(rotate(w, u, scaled ? unit(cofactor(lin, nv)) : nv), out.nx, out.ny, out.nz);
      }
      if (tangents) {
        const V3 tv{skin.tx()[v], skin.ty()[v], skin.tz()[v]};
        write(rotate(w, u, scaled ? unit(linear(lin, tv)) : tv), out.tx, out.ty, out.tz);
      }
    }
  }
}

}  // namespace

void SkinningJob::run() const {
  DQ_PRECONDITION(validate().ok(), "SkinningJob::run on a job that does not validate");
  switch (method) {
    case SkinningMethod::lbs: return skin_range<SkinningMethod::lbs>(*skin, *palette, out, first, first + count);
    case SkinningMethod::dqs: return skin_range<SkinningMethod::dqs>(*skin, *palette, out, first, first + count);
    case SkinningMethod::cor: return skin_range<SkinningMethod::cor>(*skin, *palette, out, first, first + count);
  }
}

SkinningThreads::SkinningThreads(unsigned threads) {
  for (unsigned i = 1; i < std::max(1u, threads); ++i) workers_.emplace_back([this, i] { work(i); });
}

SkinningThreads::~SkinningThreads() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  start_.notify_all();
  for (auto& t : workers_) t.join();
}

namespace {
/// Part i of n of the job's range, cut at multiples of 16 vertices (whole SIMD vectors).
SkinningJob part_of(const SkinningJob& job, unsigned i, unsigned parts) {
  const std::size_t chunk = ((job.count + parts - 1) / parts + 15) / 16 * 16;
  SkinningJob p = job;
  p.first = job.first + std::min(job.count, i * chunk);
  p.count = std::min(job.count, (i + 1) * chunk) - (p.first - job.first);
  return p;
}
}  // namespace

Status SkinningThreads::run(const SkinningJob& job) {
  if (Status s = job.validate(); !s) return s;
  if (workers_.empty()) {
    job.run();
    return {};
  }
  {
    std::lock_guard lock(mutex_);
    job_ = job;
    pending_ = static_cast<unsigned>(workers_.size());
    ++generation_;
  }
  start_.notify_all();
  part_of(job, 0, size()).run();
  std::unique_lock lock(mutex_);
  done_.wait(lock, [this] { return pending_ == 0; });
  return {};
}

void SkinningThreads::work(unsigned index) {
  std::size_t seen = 0;
  for (;;) {
    SkinningJob job;
    {
      std::unique_lock lock(mutex_);
      start_.wait(lock, [&] { return stop_ || generation_ != seen; });
      if (stop_) return;
      seen = generation_;
      job = job_;
    }
    part_of(job, index, size()).run();
    {
      std::lock_guard lock(mutex_);
      --pending_;
    }
    done_.notify_one();
  }
}

}  // namespace dq

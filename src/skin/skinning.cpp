#include "dq/skin/skinning.hpp"

#include <algorithm>
#include <cmath>

#include "dq/convert/matrix.hpp"
#include "dq/util/assert.hpp"

namespace dq {

SkinPalette::SkinPalette(std::size_t bones) : matrices(12 * bones), dual_quaternions(8 * bones), scale_shear(12 * bones) {}

void update_palette(const Skin& skin, std::span<const DualQuaternion<double>> bone_world, SkinPalette& palette) {
  DQ_PRECONDITION(bone_world.size() == skin.bone_count() && palette.size() == skin.bone_count(),
                  "update_palette needs one world transform and one palette entry per bone of the skin");
  for (std::size_t b = 0; b < skin.bone_count(); ++b) {
    const SkinBone& bone = skin.bones()[b];
    const DualQuaternion<double> d = bone_world[b] * bone.rigid;
    const Mat34<double> rigid = to_mat34(d);
    const Mat3<double> full = rotation_block(rigid) * bone.scale_shear;
    float* m = palette.matrices.data() + 12 * b;
    float* p = palette.scale_shear.data() + 12 * b;
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) {
        m[r * 4 + c] = static_cast<float>(full(r, c));
        p[r * 4 + c] = static_cast<float>(bone.scale_shear(r, c));
      }
      m[r * 4 + 3] = static_cast<float>(rigid(r, 3));
      p[r * 4 + 3] = 0.0f;
    }
    const double c[8] = {d.real.w, d.real.x, d.real.y, d.real.z, d.dual.w, d.dual.x, d.dual.y, d.dual.z};
    for (std::size_t k = 0; k < 8; ++k) palette.dual_quaternions[8 * b + k] = static_cast<float>(c[k]);
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
/// K > 0: the skin has exactly K slots (a compile-time count the compiler unrolls); K = 0: any.
template <SkinningMethod M, std::size_t K>
void skin_range(const Skin& skin, const SkinPalette& pal, const SkinnedVertices& out, std::size_t b, std::size_t e) {
  const std::size_t n = skin.vertex_count(), slots = K > 0 ? K : skin.slots();
  const std::uint32_t* __restrict bone = skin.slot_bones().data();
  const float* __restrict weight = skin.slot_weights().data();
  const float* __restrict mats = pal.matrices.data();
  const float* __restrict dqs = pal.dual_quaternions.data();
  const float* __restrict scales = pal.scale_shear.data();
  const float *__restrict px = skin.px().data(), *__restrict py = skin.py().data(), *__restrict pz = skin.pz().data();
  const float *nx = skin.nx().data(), *ny = skin.ny().data(), *nz = skin.nz().data();
  const float *tx = skin.tx().data(), *ty = skin.ty().data(), *tz = skin.tz().data();
  const float *cx = skin.cx().data(), *cy = skin.cy().data(), *cz = skin.cz().data();
  float *__restrict opx = out.px.data(), *__restrict opy = out.py.data(), *__restrict opz = out.pz.data();
  float *onx = out.nx.data(), *ony = out.ny.data(), *onz = out.nz.data();
  float *otx = out.tx.data(), *oty = out.ty.data(), *otz = out.tz.data();
  const bool normals = !out.nx.empty(), tangents = !out.tx.empty();
  // The linear phase (Kavan's two-phase method) is needed by DQS and CoR only when a bind scales.
  const bool scaled = M != SkinningMethod::lbs && skin.has_scale_shear();
  for (std::size_t v = b; v < e; ++v) {
    const V3 p{px[v], py[v], pz[v]};
    float mat[12] = {};  // blended 3x4 matrix (LBS, CoR)
    float dq[8] = {};    // blended dual quaternion (DQS; CoR uses its real part)
    float lin[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};  // blended scale/shear (two-phase)
    if constexpr (M != SkinningMethod::lbs) {
      const float* r0 = dqs + 8 * bone[v];  // slot 0: the pivot (largest weight, then lowest bone)
      constexpr int parts = M == SkinningMethod::dqs ? 8 : 4;
      for (int c = 0; c < parts; ++c) dq[c] = weight[v] * r0[c];
      for (std::size_t k = 1; k < slots; ++k) {
        const float* q = dqs + 8 * bone[k * n + v];
        const float d = q[0] * r0[0] + q[1] * r0[1] + q[2] * r0[2] + q[3] * r0[3];
        const float s = std::copysign(weight[k * n + v], d);  // antipodality: the pivot's hemisphere
        for (int c = 0; c < parts; ++c) dq[c] += s * q[c];
      }
    }
    if constexpr (M != SkinningMethod::dqs) {
      for (std::size_t k = 0; k < slots; ++k) {
        const float* m = mats + 12 * bone[k * n + v];
        const float w = weight[k * n + v];
        for (int c = 0; c < 12; ++c) mat[c] += w * m[c];
      }
    }
    if (scaled) {
      for (float& x : lin) x = 0;
      for (std::size_t k = 0; k < slots; ++k) {
        const float* m = scales + 12 * bone[k * n + v];
        const float w = weight[k * n + v];
        for (int c = 0; c < 12; ++c) lin[c] += w * m[c];
      }
    }
    auto write = [v](V3 x, float* ox, float* oy, float* oz) { ox[v] = x.x, oy[v] = x.y, oz[v] = x.z; };
    if constexpr (M == SkinningMethod::lbs) {
      write(affine(mat, p), opx, opy, opz);
      if (normals) write(unit(cofactor(mat, {nx[v], ny[v], nz[v]})), onx, ony, onz);
      if (tangents) write(unit(linear(mat, {tx[v], ty[v], tz[v]})), otx, oty, otz);
    } else {
      // The blend is not normalized: with q = (w, u), |q|² = n2, the unit rotation's action is
      // v + (2/n2) (w (u × v) + u × (u × v)) and the translation (2/n2) (w d⃗ − d_w u + u × d⃗).
      // One reciprocal and no square root (which would sit on the critical path of every vertex).
      const float w = dq[0];
      const V3 u{dq[1], dq[2], dq[3]};
      const float k = 2.0f / (w * w + u.x * u.x + u.y * u.y + u.z * u.z);
      auto rotate_blend = [&](V3 x) {
        const V3 c = cross3(u, x);
        return add(x, scale(add(scale(c, w), cross3(u, c)), k));
      };
      if constexpr (M == SkinningMethod::dqs) {
        const V3 d{dq[5], dq[6], dq[7]};
        const V3 t = scale(add(add(scale(d, w), scale(u, -dq[4])), cross3(u, d)), k);
        write(add(rotate_blend(scaled ? linear(lin, p) : p), t), opx, opy, opz);
      } else {
        // CoR: rotate about the centre c by the blended rotation, move c by the blended matrix.
        const V3 c{cx[v], cy[v], cz[v]};
        const V3 rel{p.x - c.x, p.y - c.y, p.z - c.z};
        write(add(rotate_blend(scaled ? linear(lin, rel) : rel), affine(mat, c)), opx, opy, opz);
      }
      if (normals) {
        const V3 nv{nx[v], ny[v], nz[v]};
        write(rotate_blend(scaled ? unit(cofactor(lin, nv)) : nv), onx, ony, onz);
      }
      if (tangents) {
        const V3 tv{tx[v], ty[v], tz[v]};
        write(rotate_blend(scaled ? unit(linear(lin, tv)) : tv), otx, oty, otz);
      }
    }
  }
}

/// The usual influence counts (1 to 4, and 8) get kernels unrolled for them.
template <SkinningMethod M>
void dispatch_slots(const Skin& skin, const SkinPalette& pal, const SkinnedVertices& out, std::size_t b, std::size_t e) {
  switch (skin.slots()) {
    case 1: return skin_range<M, 1>(skin, pal, out, b, e);
    case 2: return skin_range<M, 2>(skin, pal, out, b, e);
    case 3: return skin_range<M, 3>(skin, pal, out, b, e);
    case 4: return skin_range<M, 4>(skin, pal, out, b, e);
    case 8: return skin_range<M, 8>(skin, pal, out, b, e);
    default: return skin_range<M, 0>(skin, pal, out, b, e);
  }
}

}  // namespace

void SkinningJob::run() const {
  DQ_PRECONDITION(validate().ok(), "SkinningJob::run on a job that does not validate");
  switch (method) {
    case SkinningMethod::lbs: return dispatch_slots<SkinningMethod::lbs>(*skin, *palette, out, first, first + count);
    case SkinningMethod::dqs: return dispatch_slots<SkinningMethod::dqs>(*skin, *palette, out, first, first + count);
    case SkinningMethod::cor: return dispatch_slots<SkinningMethod::cor>(*skin, *palette, out, first, first + count);
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

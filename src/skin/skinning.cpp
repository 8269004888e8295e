#include "dq/skin/skinning.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cfenv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#if defined(__linux__)
#include <sched.h>
#endif
#include <string>

#include "dq/convert/matrix.hpp"
#include "dq/simd/batch.hpp"
#include "dq/util/assert.hpp"
#include "../simd/records.hpp"

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

namespace {

/// What a job writes of each output: [first, first + count) of an array, [3 first, 3 (first +
/// count)) of rows; empty for an output not given. Precondition: the outputs are long enough.
std::array<std::span<float>, 12> written_parts(const SkinnedVertices& o, std::size_t first, std::size_t count) {
  std::array<std::span<float>, 12> parts;
  std::size_t k = 0;
  for (std::span<float> a : {o.px, o.py, o.pz, o.nx, o.ny, o.nz, o.tx, o.ty, o.tz}) parts[k++] = a.empty() ? a : a.subspan(first, count);
  for (std::span<float> r : {o.positions, o.normals, o.tangents}) parts[k++] = r.empty() ? r : r.subspan(3 * first, 3 * count);
  return parts;
}

/// One quantity's output, as three arrays or as rows (`or_else`: what else it may be), checked
/// against the vertex range's end. Allocates only for an error (validate() runs for every job).
Status check_output(const char* quantity, const char* arrays, const char* or_else, std::span<float> x, std::span<float> y,
                    std::span<float> z, std::span<float> rows, std::size_t end) {
  const bool all = !x.empty() && !y.empty() && !z.empty(), any = !x.empty() || !y.empty() || !z.empty();
  const auto refused = [quantity](const std::string& why) { return Error{"skinning job: " + (quantity + why)}; };
  if (any && !rows.empty()) return refused(" given both as rows and as arrays (" + std::string(arrays) + ")");
  if (any && !all) return refused(" need all three arrays (" + std::string(arrays) + ") " + or_else);
  if (!rows.empty() && rows.size() / 3 < end)
    return Error{"skinning job: the rows of " + std::string(quantity) + " are shorter than the vertex range (3 floats a vertex)"};
  return {};
}

}  // namespace

Status SkinningJob::validate() const {
  if (!skin || !palette) return Error{"skinning job: no skin or no palette"};
  if (palette->size() != skin->bone_count()) return Error{"skinning job: the palette has " + std::to_string(palette->size()) + " bones, the skin " + std::to_string(skin->bone_count())};
  if (first > skin->vertex_count() || count > skin->vertex_count() - first) return Error{"skinning job: the vertex range exceeds the skin"};
  const std::size_t end = first + count;
  if (Status s = check_output("positions", "px, py, pz", "or rows", out.px, out.py, out.pz, out.positions, end); !s) return s;
  if (out.positions.empty())  // positions are always written: as rows, or as arrays (empty ones only for an empty range)
    for (auto a : {out.px, out.py, out.pz})
      if (a.size() < end) return Error{"skinning job: a position array is shorter than the vertex range"};
  // Normals and tangents are written as triples: all three arrays, or rows, or none.
  if (Status s = check_output("normals", "nx, ny, nz", "or rows or none", out.nx, out.ny, out.nz, out.normals, end); !s) return s;
  if (Status s = check_output("tangents", "tx, ty, tz", "or rows or none", out.tx, out.ty, out.tz, out.tangents, end); !s) return s;
  const auto short_of = [end](std::span<float> x, std::span<float> y, std::span<float> z) {
    return !x.empty() && (x.size() < end || y.size() < end || z.size() < end);
  };
  if ((!out.nx.empty() || !out.normals.empty()) && (!skin->has_normals() || short_of(out.nx, out.ny, out.nz)))
    return Error{"skinning job: normals requested but the skin has none or an array is too short"};
  if ((!out.tx.empty() || !out.tangents.empty()) && (!skin->has_tangents() || short_of(out.tx, out.ty, out.tz)))
    return Error{"skinning job: tangents requested but the skin has none or an array is too short"};
  // Each output's part is written once per vertex: two parts that overlap would receive each
  // other's values.
  const auto written = written_parts(out, first, count);
  for (std::size_t i = 0; i < written.size(); ++i)
    for (std::size_t j = i + 1; j < written.size(); ++j)
      if (overlaps(written[i], written[j])) return Error{"skinning job: two output arrays overlap in the vertex range"};
  if (method == SkinningMethod::cor && !skin->has_centers()) return Error{"skinning job: CoR needs a skin built with centres of rotation"};
  return {};
}

namespace {

// ---- the per-vertex formulas, written once over a "lane" type V --------------------------------
// V is float (the scalar path, the reference) or a vector of N floats (GCC's vector extensions,
// one vertex per lane). Every path performs the same operations in the same order, without fused
// multiply-adds (-ffp-contract=off), so each lane is bit-identical to the scalar result.

template <class V>
struct V3 {
  V x, y, z;
};
template <class V>
[[gnu::always_inline]] inline V3<V> cross3(V3<V> a, V3<V> b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
template <class V>
[[gnu::always_inline]] inline V3<V> add(V3<V> a, V3<V> b) {
  return {a.x + b.x, a.y + b.y, a.z + b.z};
}
template <class V>
[[gnu::always_inline]] inline V3<V> scale(V3<V> a, V s) {
  return {a.x * s, a.y * s, a.z * s};
}
[[gnu::always_inline]] inline float root(float x) { return std::sqrt(x); }
[[gnu::always_inline]] inline float copysign_of(float magnitude, float sign) { return std::copysign(magnitude, sign); }
#if DQKIT_VECTOR_EXTENSIONS && defined(__x86_64__)
// The vector types, with root and copysign_of on them (declared before the formulas that call
// them: the lookup of a dependent name finds no overload declared later for a built-in type).
using namespace kernels;  // the vector types (src/simd/vector_types.hpp)

template <class F, class I = typename VectorOf<static_cast<int>(sizeof(F) / sizeof(float))>::bits>
[[gnu::always_inline]] inline F root(F x) {
  F r;
  for (std::size_t i = 0; i < sizeof(F) / sizeof(float); ++i) r[i] = __builtin_sqrtf(x[i]);  // one instruction (-fno-math-errno)
  return r;
}
template <class F, class I = typename VectorOf<static_cast<int>(sizeof(F) / sizeof(float))>::bits>
[[gnu::always_inline]] inline F copysign_of(F magnitude, F sign) {
  const I m = __builtin_bit_cast(I, magnitude), s = __builtin_bit_cast(I, sign);
  const std::int32_t top = std::numeric_limits<std::int32_t>::min();  // the sign bit
  return __builtin_bit_cast(F, (m & ~top) | (s & top));
}

#endif
template <class V>
[[gnu::always_inline]] inline V3<V> unit(V3<V> a) {
  const V n = root(a.x * a.x + a.y * a.y + a.z * a.z);
  const V inv = 1.0f / n;  // (unused where n = 0)
  const auto positive = n > 0.0f;
  return {positive ? a.x * inv : a.x, positive ? a.y * inv : a.y, positive ? a.z * inv : a.z};
}
/// The linear part of a 3x4 matrix (row-major a[r*4+c]) times v.
template <class V>
[[gnu::always_inline]] inline V3<V> linear(const V* a, V3<V> v) {
  return {a[0] * v.x + a[1] * v.y + a[2] * v.z, a[4] * v.x + a[5] * v.y + a[6] * v.z, a[8] * v.x + a[9] * v.y + a[10] * v.z};
}
template <class V>
[[gnu::always_inline]] inline V3<V> affine(const V* a, V3<V> v) {
  return add(linear(a, v), V3<V>{a[3], a[7], a[11]});
}
/// The cofactor matrix's linear action (det · A⁻ᵀ): how a normal transforms, up to length.
template <class V>
[[gnu::always_inline]] inline V3<V> cofactor(const V* a, V3<V> n) {
  const V3<V> c0{a[0], a[4], a[8]}, c1{a[1], a[5], a[9]}, c2{a[2], a[6], a[10]};
  const V3<V> r0 = cross3(c1, c2), r1 = cross3(c2, c0), r2 = cross3(c0, c1);
  return {r0.x * n.x + r1.x * n.y + r2.x * n.z, r0.y * n.x + r1.y * n.y + r2.y * n.z, r0.z * n.x + r1.z * n.y + r2.z * n.z};
}

/// How far ahead of the vertex being skinned the vector kernels prefetch, in vertices: 512 bytes per
/// stream, about 0.4 µs of work at 300 M vertices/s, several memory latencies. Farther is slower:
/// twenty streams 1024 vertices ahead hold 80 KB in flight, more than an L1 data cache, and DQS from
/// DRAM ran slower in eight of nine paired runs (docs/skinning.md). bench_skin's skin_streams cases
/// prefetch the same distance.
constexpr std::size_t kPrefetchAhead = 128;

/// What a kernel reads and writes, resolved once per range.
struct Streams {
  std::size_t slots, stride;  ///< influence slots, values from one slot's array to the next's
  const std::uint32_t* bone;
  const float *weight, *mats, *dqs, *scales;
  const float *px, *py, *pz, *nx, *ny, *nz, *tx, *ty, *tz, *cx, *cy, *cz;
  float *opx, *opy, *opz, *onx, *ony, *onz, *otx, *oty, *otz;
  float *op, *on, *ot;  ///< rows (x, y, z a vertex), where a quantity is written as rows; else null
  bool normals, tangents, scaled, centers;
  Streams(const Skin& skin, const SkinPalette& pal, const SkinnedVertices& out, SkinningMethod m)
      : slots(skin.slots()), stride(skin.slot_stride()), bone(skin.slot_bones(0).data()), weight(skin.slot_weights(0).data()),
        mats(pal.matrices.data()), dqs(pal.dual_quaternions.data()), scales(pal.scale_shear.data()),
        px(skin.px().data()), py(skin.py().data()), pz(skin.pz().data()), nx(skin.nx().data()), ny(skin.ny().data()), nz(skin.nz().data()),
        tx(skin.tx().data()), ty(skin.ty().data()), tz(skin.tz().data()), cx(skin.cx().data()), cy(skin.cy().data()), cz(skin.cz().data()),
        opx(out.px.data()), opy(out.py.data()), opz(out.pz.data()), onx(out.nx.data()), ony(out.ny.data()), onz(out.nz.data()),
        otx(out.tx.data()), oty(out.ty.data()), otz(out.tz.data()), op(rows(out.positions)), on(rows(out.normals)),
        ot(rows(out.tangents)), normals(!out.nx.empty() || on), tangents(!out.tx.empty() || ot),
        // The linear phase (Kavan's two-phase method) is needed by DQS and CoR only when a bind scales.
        scaled(m != SkinningMethod::lbs && skin.has_scale_shear()), centers(m == SkinningMethod::cor) {}

  /// Rows given (validate() goes by emptiness, as this does: an empty span may have a pointer).
  static float* rows(std::span<float> r) { return r.empty() ? nullptr : r.data(); }

  /// Asks for the cache lines of vertex v in every stream the kernel reads and writes. With some
  /// twenty streams (a vertex's coordinates, normals and slots, and the outputs) the hardware
  /// prefetchers fall behind, and measured at 1M vertices the kernels are then well below the
  /// memory's bandwidth (docs/skinning.md).
  [[gnu::always_inline]] void prefetch(std::size_t v) const {
    auto read = [v](const float* p) __attribute__((always_inline)) { __builtin_prefetch(p + v, 0, 3); };
    // An output's 16 vertices: a cache line of each array, or three of rows.
    auto write = [v](float* rows, float* x, float* y, float* z) __attribute__((always_inline)) {
      if (rows) {
        for (std::size_t line = 0; line < 3; ++line) __builtin_prefetch(rows + 3 * v + 16 * line, 1, 3);
      } else {
        for (float* p : {x, y, z}) __builtin_prefetch(p + v, 1, 3);
      }
    };
    for (const float* p : {px, py, pz}) read(p);
    write(op, opx, opy, opz);
    if (normals) {
      for (const float* p : {nx, ny, nz}) read(p);
      write(on, onx, ony, onz);
    }
    if (tangents) {
      for (const float* p : {tx, ty, tz}) read(p);
      write(ot, otx, oty, otz);
    }
    if (centers)
      for (const float* p : {cx, cy, cz}) read(p);
    for (std::size_t k = 0; k < slots; ++k) {
      __builtin_prefetch(bone + k * stride + v, 0, 3);
      read(weight + k * stride);
    }
  }
};

/// One vertex per call: the scalar path.
struct ScalarLanes {
  using V = float;
  [[gnu::always_inline]] static V load(const float* p) { return *p; }
  [[gnu::always_inline]] static void store(float* p, V x) { *p = x; }
  [[gnu::always_inline]] static void store_points(float* p, V x, V y, V z) { p[0] = x, p[1] = y, p[2] = z; }
  /// out[c] = table[stride * bones[0] + offset + c] for c < C.
  template <int C>
  [[gnu::always_inline]] static void rows(const float* table, std::size_t stride, const std::uint32_t* bones, std::size_t offset, V* out) {
    const float* e = table + stride * bones[0] + offset;
    for (int c = 0; c < C; ++c) out[c] = e[c];
  }
};

/// Skins the vertices of one call of P (one, or one per vector lane) from v. K > 0: the skin has exactly K slots (a compile-time
/// count the compiler unrolls); K = 0: any.
template <SkinningMethod M, std::size_t K, class P>
[[gnu::always_inline]] inline void skin_block(const Streams& s, std::size_t v) {
  using V = typename P::V;
  const std::size_t slots = K > 0 ? K : s.slots;
  const V3<V> p{P::load(s.px + v), P::load(s.py + v), P::load(s.pz + v)};
  V mat[12];  // blended 3x4 matrix (LBS, CoR)
  V dq[8];    // blended dual quaternion (DQS; CoR uses its real part)
  V lin[12] = {};  // blended scale/shear (two-phase; set when s.scaled)
  // Σ_k w_k · table[bone_k] over the slots, for a 3x4 matrix table (rows 0-1, then row 2).
  auto blend_matrices = [&](const float* table, V* sum) __attribute__((always_inline)) {
    V m[12];
    auto load_slot = [&](std::size_t k) __attribute__((always_inline)) {
      P::template rows<8>(table, 12, s.bone + k * s.stride + v, 0, m);
      P::template rows<4>(table, 12, s.bone + k * s.stride + v, 8, m + 8);
      return P::load(s.weight + k * s.stride + v);
    };
    const V w0 = load_slot(0);
    for (int c = 0; c < 12; ++c) sum[c] = w0 * m[c];
    for (std::size_t k = 1; k < slots; ++k) {
      const V w = load_slot(k);
      for (int c = 0; c < 12; ++c) sum[c] = sum[c] + w * m[c];
    }
  };
  if constexpr (M != SkinningMethod::lbs) {
    constexpr std::size_t parts = M == SkinningMethod::dqs ? 8 : 4;
    V r0[parts];  // slot 0: the pivot (largest weight, then lowest bone)
    P::template rows<parts>(s.dqs, 8, s.bone + v, 0, r0);
    const V w0 = P::load(s.weight + v);
    for (std::size_t c = 0; c < parts; ++c) dq[c] = w0 * r0[c];
    for (std::size_t k = 1; k < slots; ++k) {
      V q[parts];
      P::template rows<parts>(s.dqs, 8, s.bone + k * s.stride + v, 0, q);
      const V d = q[0] * r0[0] + q[1] * r0[1] + q[2] * r0[2] + q[3] * r0[3];
      const V w = copysign_of(P::load(s.weight + k * s.stride + v), d);  // antipodality: the pivot's hemisphere
      for (std::size_t c = 0; c < parts; ++c) dq[c] = dq[c] + w * q[c];
    }
  }
  if constexpr (M != SkinningMethod::dqs) blend_matrices(s.mats, mat);
  if (s.scaled) blend_matrices(s.scales, lin);
  auto write = [v](V3<V> x, float* rows, float* ox, float* oy, float* oz) __attribute__((always_inline)) {
    if (rows)
      P::store_points(rows + 3 * v, x.x, x.y, x.z);
    else
      P::store(ox + v, x.x), P::store(oy + v, x.y), P::store(oz + v, x.z);
  };
  auto read = [v](const float* x, const float* y, const float* z) __attribute__((always_inline)) { return V3<V>{P::load(x + v), P::load(y + v), P::load(z + v)}; };
  if constexpr (M == SkinningMethod::lbs) {
    write(affine(mat, p), s.op, s.opx, s.opy, s.opz);
    if (s.normals) write(unit(cofactor(mat, read(s.nx, s.ny, s.nz))), s.on, s.onx, s.ony, s.onz);
    if (s.tangents) write(unit(linear(mat, read(s.tx, s.ty, s.tz))), s.ot, s.otx, s.oty, s.otz);
  } else {
    // The blend is not normalized: with q = (w, u), |q|² = n2, the unit rotation's action is
    // v + (2/n2) (w (u × v) + u × (u × v)) and the translation (2/n2) (w d⃗ − d_w u + u × d⃗).
    // One reciprocal and no square root (which would sit on the critical path of every vertex).
    const V w = dq[0];
    const V3<V> u{dq[1], dq[2], dq[3]};
    const V k = 2.0f / (w * w + u.x * u.x + u.y * u.y + u.z * u.z);
    auto rotate_blend = [&](V3<V> x) __attribute__((always_inline)) {
      const V3<V> c = cross3(u, x);
      return add(x, scale(add(scale(c, w), cross3(u, c)), k));
    };
    if constexpr (M == SkinningMethod::dqs) {
      const V3<V> d{dq[5], dq[6], dq[7]};
      const V3<V> t = scale(add(add(scale(d, w), scale(u, -dq[4])), cross3(u, d)), k);
      write(add(rotate_blend(s.scaled ? linear(lin, p) : p), t), s.op, s.opx, s.opy, s.opz);
    } else {
      // CoR: rotate about the centre c by the blended rotation, move c by the blended matrix.
      const V3<V> c = read(s.cx, s.cy, s.cz);
      const V3<V> rel{p.x - c.x, p.y - c.y, p.z - c.z};
      write(add(rotate_blend(s.scaled ? linear(lin, rel) : rel), affine(mat, c)), s.op, s.opx, s.opy, s.opz);
    }
    if (s.normals) {
      const V3<V> nv = read(s.nx, s.ny, s.nz);
      write(rotate_blend(s.scaled ? unit(cofactor(lin, nv)) : nv), s.on, s.onx, s.ony, s.onz);
    }
    if (s.tangents) {
      const V3<V> tv = read(s.tx, s.ty, s.tz);
      write(rotate_blend(s.scaled ? unit(linear(lin, tv)) : tv), s.ot, s.otx, s.oty, s.otz);
    }
  }
}

/// The scalar path over [b, e): the reference the vector paths are tested against, and their tail.
template <SkinningMethod M, std::size_t K>
void skin_scalar(const Streams& s, std::size_t b, std::size_t e) {
  for (std::size_t v = b; v < e; ++v) skin_block<M, K, ScalarLanes>(s, v);
}

/// The usual influence counts (1 to 4, and 8) get scalar kernels unrolled for them.
template <SkinningMethod M>
void skin_scalar_slots(const Streams& s, std::size_t b, std::size_t e) {
  switch (s.slots) {
    case 1: return skin_scalar<M, 1>(s, b, e);
    case 2: return skin_scalar<M, 2>(s, b, e);
    case 3: return skin_scalar<M, 3>(s, b, e);
    case 4: return skin_scalar<M, 4>(s, b, e);
    case 8: return skin_scalar<M, 8>(s, b, e);
    default: return skin_scalar<M, 0>(s, b, e);
  }
}

#if DQKIT_VECTOR_EXTENSIONS && defined(__x86_64__)
// ---- vector lanes, one instruction set per function ---------------------------------------------
// As in src/simd/batch.cpp: each target's kernel is a function with GCC's `target` attribute and
// `flatten`, so the generic code above, instantiated on GCC's vector types, is inlined and
// compiled for that target (never a per-file -m flag). Every helper it reaches, lambdas included,
// is always_inline as well: clang 14's flatten inlines only the calls written in the function
// itself, and a helper left out of line is compiled for baseline x86-64, where a wide vector it
// returns crosses an ABI boundary (wrong skinning with scaled binds, found by the clang build).
// Palette entries are loaded per lane (one vector load of a bone's record) and transposed to
// component vectors with shuffles: no gathers.

/// N vertices per call (N = 4, 8, 16).
template <int N>
struct VectorLanes {
  using V = typename VectorOf<N>::type;
  [[gnu::always_inline]] static V load(const float* p) { return load_as<V>(p); }
  [[gnu::always_inline]] static void store(float* p, V x) { std::memcpy(p, &x, sizeof x); }
  /// Lane j's x, y, z to p[3 j + c]: N rows in three vector stores.
  [[gnu::always_inline]] static void store_points(float* p, V x, V y, V z) { Points<N>::store(x, y, z, p); }
  /// out[c] lane j = table[stride * bones[j] + offset + c] for c < C (C = 4 or 8): one load of C
  /// floats per lane, then a transpose (load_records).
  template <int C>
  [[gnu::always_inline]] static void rows(const float* table, std::size_t stride, const std::uint32_t* bones, std::size_t offset, V* out) {
    load_records<N, C>([&](int j) __attribute__((always_inline)) { return table + stride * bones[j] + offset; }, out);
  }
};

/// Whole vectors over [b, e), the scalar path for the tail.
template <SkinningMethod M, int N>
[[gnu::always_inline]] inline void skin_vectors(const Streams& s, std::size_t b, std::size_t e) {
  std::size_t v = b;
  for (; v + N <= e; v += N) {
    // (Only whole 16-vertex blocks in the range: their rows are 48 floats from 3 (v + ahead).)
    if ((v - b) % 16 == 0 && v + kPrefetchAhead + 16 <= e) s.prefetch(v + kPrefetchAhead);
    skin_block<M, 0, VectorLanes<N>>(s, v);
  }
  for (; v < e; ++v) skin_block<M, 0, ScalarLanes>(s, v);
}

#define DQKIT_SKIN_TARGET(name, lanes, attribute)                                                                      \
  template <SkinningMethod M>                                                                                          \
  [[gnu::target(attribute), gnu::flatten]] void skin_##name(const Streams& s, std::size_t b, std::size_t e) {          \
    skin_vectors<M, lanes>(s, b, e);                                                                                   \
  }
DQKIT_SKIN_TARGET(sse2, 4, "sse2")
DQKIT_SKIN_TARGET(sse42, 4, "sse4.2")
DQKIT_SKIN_TARGET(avx2, 8, "avx2,fma")
DQKIT_SKIN_TARGET(avx512, 16, "avx512f")
#undef DQKIT_SKIN_TARGET
#endif

/// The kernel of the target in use (simd::current_target, chosen from the CPU at run time).
template <SkinningMethod M>
void skin_range(const Skin& skin, const SkinPalette& pal, const SkinnedVertices& out, std::size_t b, std::size_t e) {
  const Streams s(skin, pal, out, M);
  switch (simd::current_target()) {
#if DQKIT_VECTOR_EXTENSIONS && defined(__x86_64__)
    case simd::Target::avx512: return skin_avx512<M>(s, b, e);
    case simd::Target::avx2: return skin_avx2<M>(s, b, e);
    case simd::Target::sse42: return skin_sse42<M>(s, b, e);
    case simd::Target::sse2: return skin_sse2<M>(s, b, e);
#endif
    default: return skin_scalar_slots<M>(s, b, e);
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

namespace {
std::size_t divided_up(std::size_t n, std::size_t d) { return n / d + (n % d != 0); }  // ⌈n / d⌉, without overflow
std::size_t whole_vectors(std::size_t vertices) { return divided_up(vertices, 16) * 16; }  // rounded up to AVX-512's 16 lanes

void pause() noexcept {  // in a spin: lets the core's other thread run, and saves power
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#endif
}

/// The CPUs this process may run on (its affinity mask), or the hardware's threads where that is unknown.
unsigned cpus_available() noexcept {
#if defined(__linux__)
  cpu_set_t set;
  if (sched_getaffinity(0, sizeof set, &set) == 0) return static_cast<unsigned>(CPU_COUNT(&set));
#endif
  return std::max(1u, std::thread::hardware_concurrency());
}

/// Spins until `done()` or for `microseconds`, whichever comes first (the clock read once in 64 turns).
template <class Done>
void spin(Done done, unsigned microseconds) noexcept {
  if (microseconds == 0) return;
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::microseconds(microseconds);
  for (unsigned i = 0; !done() && (++i % 64 != 0 || std::chrono::steady_clock::now() < give_up);) pause();
}
}  // namespace

SkinningThreads::SkinningThreads(unsigned threads, std::size_t min_part, unsigned worker_spin_microseconds)
    : min_part_(std::max<std::size_t>(16, whole_vectors(std::min(min_part, std::numeric_limits<std::size_t>::max() - 15)))),
      worker_spin_(worker_spin_microseconds != kAutomaticWorkerSpin ? worker_spin_microseconds
                   : std::max(1u, threads) <= cpus_available()   ? kWorkerSpinMicroseconds
                                                                 : 0) {
  try {
    for (unsigned i = 1; i < std::max(1u, threads); ++i) workers_.emplace_back([this] { work(); });
  } catch (...) {  // a thread that could not start (std::system_error): stop those that did, or their destruction would terminate
    stop();
    throw;
  }
}

SkinningThreads::~SkinningThreads() { stop(); }

void SkinningThreads::stop() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
    ++generation_;  // ends the spins of workers between calls
  }
  start_.notify_all();
  for (auto& t : workers_) t.join();
}

void SkinningThreads::run_parts() noexcept {
  // Parts are numbered job after job, and a thread claims increasing numbers: it finds a part's job
  // by moving on from the job of its last part.
  std::size_t k = 0, before = 0;  // the job, and the number of parts of the jobs before it
  for (std::size_t i; (i = next_part_.fetch_add(1, std::memory_order_relaxed)) < parts_;) {
    for (std::size_t n; i - before >= (n = divided_up(jobs_[k].count, part_size_)); ++k) before += n;
    SkinningJob part = jobs_[k];
    const std::size_t offset = (i - before) * part_size_;
    part.first += offset;
    part.count = std::min(part_size_, jobs_[k].count - offset);
    part.run();
  }
}

Status SkinningThreads::run(std::span<const SkinningJob> jobs) {
  for (std::size_t k = 0; k < jobs.size(); ++k)
    if (Status s = jobs[k].validate(); !s) {
      // validate() says "skinning job: …"; with several jobs, say which.
      const std::string said = s.error().message, prefix = "skinning job";
      if (jobs.size() == 1 || !said.starts_with(prefix)) return s;
      return Error{prefix + " " + std::to_string(k) + said.substr(prefix.size())};
    }
  if (jobs.size() > 1) {
    // Two parts of different jobs could run at once: no element may be written by two jobs.
    written_.clear();
    written_.reserve(9 * jobs.size());  // so that it grows only with the number of jobs
    for (std::size_t k = 0; k < jobs.size(); ++k)
      for (std::span<float> part : written_parts(jobs[k].out, jobs[k].first, jobs[k].count))
        if (!part.empty()) {
          const auto begin = reinterpret_cast<std::uintptr_t>(part.data());
          written_.push_back({begin, begin + part.size_bytes(), k});
        }
    std::sort(written_.begin(), written_.end(), [](const Written& x, const Written& y) { return x.begin < y.begin; });
    for (std::size_t i = 1; i < written_.size(); ++i)
      if (written_[i].begin < written_[i - 1].end)
        return Error{"skinning jobs " + std::to_string(std::min(written_[i - 1].job, written_[i].job)) + " and " +
                     std::to_string(std::max(written_[i - 1].job, written_[i].job)) + " write the same output elements"};
  }
  std::size_t total = 0;  // no overflow: the jobs write this many distinct floats
  for (const SkinningJob& job : jobs) total += job.count;
  // Parts of whole 16-vertex vectors, about kPartsPerThread per thread (plus at most one per job),
  // none but a job's last smaller than min_part_.
  const std::size_t most_parts = std::size_t{size()} * kPartsPerThread;
  const std::size_t part = std::max(min_part_, whole_vectors(divided_up(total, most_parts)));
  if (workers_.empty() || total <= part) {
    for (const SkinningJob& job : jobs) job.run();
    return {};
  }
  {
    std::lock_guard lock(mutex_);  // no worker holds a call here (the last run closed it with none joined)
    jobs_ = jobs;
    part_size_ = part;
    parts_ = 0;
    for (const SkinningJob& job : jobs) parts_ += divided_up(job.count, part);
    std::fegetenv(&env_);  // rounding and flush-to-zero as the caller has them, for the workers too
    next_part_.store(0, std::memory_order_relaxed);
    open_ = true;
    ++generation_;
  }
  start_.notify_all();
  run_parts();
  // Every part is claimed: close the call to the workers that have not joined (they would find
  // nothing to do, and keep this thread waiting), then wait for those that did. Their parts are
  // short, so spin first: a sleep here would add a wake-up (tens of microseconds) to the call.
  {
    std::lock_guard lock(mutex_);
    open_ = false;
  }
  spin([this] { return joined_.load() == 0; }, kSpinMicroseconds);
  std::unique_lock lock(mutex_);
  done_.wait(lock, [this] { return joined_ == 0; });
  jobs_ = {};  // the caller's jobs, which may not outlive this call
  return {};
}

void SkinningThreads::work() {
  std::size_t seen = 0;
  for (;;) {
    // Calls back to back (a script's loop) find the worker awake: it spins a while for the next
    // call before it sleeps, as a wake-up takes tens of microseconds (and, with glibc, run()'s
    // notify makes no system call while no worker sleeps).
    spin([&] { return generation_.load(std::memory_order_relaxed) != seen; }, worker_spin_);
    std::unique_lock lock(mutex_);
    start_.wait(lock, [&] { return stop_ || generation_ != seen; });
    if (stop_) return;
    seen = generation_;
    if (!open_) continue;  // that call closed before this worker came: wait for the next
    ++joined_;
    lock.unlock();
    std::fesetenv(&env_);  // env_ does not change while a worker has joined
    run_parts();  // jobs_ does not change while a worker has joined
    lock.lock();
    --joined_;
    lock.unlock();
    done_.notify_one();
  }
}

}  // namespace dq

// N float (or double) lanes that behave as one scalar, so that the generic formulas of the scalar types
// (detail::hamilton, detail::dual_product, transform_point, ...) instantiate on vectors: the
// kernels of src/simd/batch.cpp and src/simd/pose_blocks.cpp. Private to dqkit.
#pragma once

#include <array>
#include <cstddef>
#include <cstring>
#include <type_traits>
#include <utility>

#include "dq/anim/forward_kinematics.hpp"
#include "vector_types.hpp"

/// For the scalar parts of the kernels (their tails, the scalar target): compiled without GCC's
/// vectorizers, which where FMA is enabled fuse the generic scalar formulas (the Hamilton product)
/// into vfmaddsub despite -ffp-contract=off (docs/design.md): the SLP vectorizer in straight-line
/// code, and the loop vectorizer in a loop of independent products. So the elements they compute
/// keep the bits of those on the lanes in every build.
#if defined(__clang__)
#define DQKIT_NOT_VECTORIZED
#else
#define DQKIT_NOT_VECTORIZED gnu::optimize("no-tree-vectorize")
#endif

#if DQKIT_VECTOR_EXTENSIONS && defined(__x86_64__)
namespace dq::kernels {

/// N lanes of S (float, or double for the frames' kernel) that behave as a scalar for the generic
/// formulas (T(2), T(0.5) broadcast a constant).
template <int N, class S = float>
struct Lanes {
  using Vector = vector_of<S, N>;
  Vector v;
  [[gnu::always_inline]] Lanes() : v{} {}
  [[gnu::always_inline]] Lanes(Vector x) : v(x) {}          // NOLINT: implicit, as a scalar
  [[gnu::always_inline]] Lanes(S s) : v(Vector{} + s) {}  // NOLINT
  // Copies as a vector. The implicit copy is a struct copy, which GCC 12, in the functions built
  // for AVX2 and AVX-512, made in 16-byte pieces through general registers (vmovq, vpinsrq)
  // wherever a value passed through memory: AVX2's to_matrices ran at 0.75 × SSE2's speed. Copied
  // as a vector, to_matrices, normalize, dlb and sclerp run 1.15–1.54 × faster with AVX2, and
  // the first three 1.15–1.35 × with AVX-512 (bench_batch's OnTarget cases, docs/performance.md).
  [[gnu::always_inline]] Lanes(const Lanes& o) : v(o.v) {}
  [[gnu::always_inline]] Lanes& operator=(const Lanes& o) {
    v = o.v;
    return *this;
  }
  [[gnu::always_inline]] friend Lanes operator+(Lanes a, Lanes b) { return a.v + b.v; }
  [[gnu::always_inline]] friend Lanes operator-(Lanes a, Lanes b) { return a.v - b.v; }
  [[gnu::always_inline]] friend Lanes operator*(Lanes a, Lanes b) { return a.v * b.v; }
  [[gnu::always_inline]] friend Lanes operator/(Lanes a, Lanes b) { return a.v / b.v; }
  [[gnu::always_inline]] friend Lanes operator-(Lanes a) { return -a.v; }
  /// Lane by lane: a where x < y, else b.
  [[gnu::always_inline]] friend Lanes select_less(Lanes x, Lanes y, Lanes a, Lanes b) { return x.v < y.v ? a.v : b.v; }
  [[gnu::always_inline]] friend Lanes sqrt(Lanes a) {
    Vector r;
    for (int i = 0; i < N; ++i) {  // one vector instruction (-fno-math-errno)
      if constexpr (std::is_same_v<S, float>)
        r[i] = __builtin_sqrtf(a.v[i]);
      else
        r[i] = __builtin_sqrt(a.v[i]);
    }
    return r;
  }
};

/// s in every lane, exactly. Lanes(s) computes 0 + s, which turns −0 into +0: no matter for the
/// formulas' constants, but a caller's value (a blend's t, a transform's component) must keep its
/// sign, as the scalar functions keep it. A shuffle, not s − 0: GCC 12 builds s − 0 lane by lane
/// (docs/performance.md, "One transform for a cloud of points").
template <int N, class S>
[[gnu::always_inline]] inline Lanes<N, S> splat(S s) {
  using V = vector_of<S, N>;
  V v{};
  v[0] = s;
  return [v]<int... E>(std::integer_sequence<int, E...>) { return V(__builtin_shufflevector(v, v, (E * 0)...)); }(std::make_integer_sequence<int, N>{});
}

/// Σ c_k x^k on lanes by Estrin's scheme: the pairs c_k + c_(k+1) x, then pairs of those joined
/// by x², then by x⁴, ...: a chain of about 2 log₂ K dependent operations where Horner's rule has
/// 2K (the kernels that use it, slerp and sclerp, are bound by their chains' latency).
template <int N, std::size_t K>
[[gnu::always_inline]] inline Lanes<N> polynomial(Lanes<N> x, const std::array<float, K>& c) {
  // Unrolled, so that the terms stay in registers (a loop left rolled keeps them in memory).
  std::array<Lanes<N>, (K + 1) / 2> terms;
#pragma GCC unroll 16
  for (std::size_t k = 0; k < K; k += 2) terms[k / 2] = k + 1 < K ? Lanes<N>(c[k]) + Lanes<N>(c[k + 1]) * x : Lanes<N>(c[k]);
#pragma GCC unroll 8
  for (std::size_t count = terms.size(); count > 1; count = (count + 1) / 2) {
    x = x * x;
#pragma GCC unroll 8
    for (std::size_t k = 0; k < count; k += 2) terms[k / 2] = k + 1 < count ? terms[k] + terms[k + 1] * x : terms[k];
  }
  return terms[0];
}
template <int N, class S>
[[gnu::always_inline]] inline Lanes<N, S> load(const S* p) {
  return load_as<vector_of<S, N>>(p);
}
template <int N, class S>
[[gnu::always_inline]] inline void store(S* p, const Lanes<N, S>& x) {
  std::memcpy(p, &x.v, sizeof x.v);
}

/// N dual quaternions from element i of eight component rows, and back.
template <int N, class S>
[[gnu::always_inline]] inline DualQuaternion<Lanes<N, S>> load8(detail::Row8<const S> r, std::size_t i) {
  using Q = Quaternion<Lanes<N, S>>;
  return {Q(load<N>(r.rw + i), load<N>(r.rx + i), load<N>(r.ry + i), load<N>(r.rz + i)),
          Q(load<N>(r.dw + i), load<N>(r.dx + i), load<N>(r.dy + i), load<N>(r.dz + i))};
}
template <int N, class S>
[[gnu::always_inline]] inline void store8(detail::Row8<S> r, std::size_t i, const DualQuaternion<Lanes<N, S>>& q) {
  store<N>(r.rw + i, q.real.w), store<N>(r.rx + i, q.real.x), store<N>(r.ry + i, q.real.y), store<N>(r.rz + i, q.real.z);
  store<N>(r.dw + i, q.dual.w), store<N>(r.dx + i, q.dual.x), store<N>(r.dy + i, q.dual.y), store<N>(r.dz + i, q.dual.z);
}

/// N dual quaternions from their eight component vectors (w, x, y, z real, then dual), and back.
template <int N, class S>
[[gnu::always_inline]] inline DualQuaternion<Lanes<N, S>> dual_quaternion_of(const vector_of<S, N>* c) {
  using Q = Quaternion<Lanes<N, S>>;
  return {Q(c[0], c[1], c[2], c[3]), Q(c[4], c[5], c[6], c[7])};
}
template <int N, class S>
[[gnu::always_inline]] inline void components_of(const DualQuaternion<Lanes<N, S>>& q, vector_of<S, N>* c) {
  c[0] = q.real.w.v, c[1] = q.real.x.v, c[2] = q.real.y.v, c[3] = q.real.z.v;
  c[4] = q.dual.w.v, c[5] = q.dual.x.v, c[6] = q.dual.y.v, c[7] = q.dual.z.v;
}

/// The batch product (detail::batch_product: detail::dual_product over detail::hamilton) on lanes.
template <int N, class S>
[[gnu::always_inline]] inline DualQuaternion<Lanes<N, S>> product(const DualQuaternion<Lanes<N, S>>& a, const DualQuaternion<Lanes<N, S>>& b) {
  return detail::batch_product(a, b);
}

}  // namespace dq::kernels
#endif

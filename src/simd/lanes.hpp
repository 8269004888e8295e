// N float lanes that behave as one scalar, so that the generic formulas of the scalar types
// (detail::hamilton, detail::dual_product, transform_point, ...) instantiate on vectors: the
// kernels of src/simd/batch.cpp and src/simd/pose_blocks.cpp. Private to dqkit.
#pragma once

#include <array>
#include <cstddef>
#include <cstring>

#include "vector_types.hpp"

#if DQKIT_VECTOR_EXTENSIONS && defined(__x86_64__)
namespace dq::kernels {

/// N lanes that behave as a scalar for the generic formulas (T(2), T(0.5) broadcast a constant).
template <int N>
struct Lanes {
  vec<N> v;
  [[gnu::always_inline]] Lanes() : v{} {}
  [[gnu::always_inline]] Lanes(vec<N> x) : v(x) {}          // NOLINT: implicit, as a scalar
  [[gnu::always_inline]] Lanes(float s) : v(vec<N>{} + s) {}  // NOLINT
  [[gnu::always_inline]] friend Lanes operator+(Lanes a, Lanes b) { return a.v + b.v; }
  [[gnu::always_inline]] friend Lanes operator-(Lanes a, Lanes b) { return a.v - b.v; }
  [[gnu::always_inline]] friend Lanes operator*(Lanes a, Lanes b) { return a.v * b.v; }
  [[gnu::always_inline]] friend Lanes operator/(Lanes a, Lanes b) { return a.v / b.v; }
  [[gnu::always_inline]] friend Lanes operator-(Lanes a) { return -a.v; }
  /// Lane by lane: a where x < y, else b.
  [[gnu::always_inline]] friend Lanes select_less(Lanes x, Lanes y, Lanes a, Lanes b) { return x.v < y.v ? a.v : b.v; }
  [[gnu::always_inline]] friend Lanes sqrt(Lanes a) {
    vec<N> r;
    for (int i = 0; i < N; ++i) r[i] = __builtin_sqrtf(a.v[i]);  // one vector instruction (-fno-math-errno)
    return r;
  }
};

/// Σ c_k x^k by Horner's rule on lanes.
template <int N, std::size_t K>
[[gnu::always_inline]] inline Lanes<N> polynomial(Lanes<N> x, const std::array<float, K>& c) {
  Lanes<N> acc = c[K - 1];
  for (std::size_t k = K - 1; k-- > 0;) acc = acc * x + Lanes<N>(c[k]);
  return acc;
}
template <int N>
[[gnu::always_inline]] inline Lanes<N> load(const float* p) {
  return load_as<vec<N>>(p);
}
template <int N>
[[gnu::always_inline]] inline void store(float* p, const Lanes<N>& x) {
  std::memcpy(p, &x.v, sizeof x.v);
}

}  // namespace dq::kernels
#endif

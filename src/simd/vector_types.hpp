// The compiler's generic vector types of 4, 8 and 16 floats (and of 32-bit integers, for bit
// operations; and of 2, 4 and 8 doubles) used by the kernels per instruction set: src/simd/batch.cpp and
// src/skin/skinning.cpp. Private to dqkit. They pass by value only inside target functions that
// inline everything (`flatten`, and every helper always_inline, which clang needs): GCC's -Wpsabi
// note on the helpers' signatures does not apply, and is silenced for the files that include this
// header.
#pragma once

#include <cstdint>
#include <cstring>

#include "dq/core/scalar.hpp"

#if DQKIT_VECTOR_EXTENSIONS && defined(__x86_64__)
#pragma GCC diagnostic ignored "-Wpsabi"
namespace dq::kernels {

// Spelled out per width: GCC drops `vector_size` with a size that depends on a template
// parameter, silently leaving a plain float.
using float4 = float __attribute__((vector_size(16)));
using float8 = float __attribute__((vector_size(32)));
using float16 = float __attribute__((vector_size(64)));
using int4 = std::int32_t __attribute__((vector_size(16)));
using int8 = std::int32_t __attribute__((vector_size(32)));
using int16 = std::int32_t __attribute__((vector_size(64)));

/// The vector of N floats (`type`) and of N 32-bit integers (`bits`).
template <int N>
struct VectorOf;
template <>
struct VectorOf<4> {
  using type = float4;
  using bits = int4;
};
template <>
struct VectorOf<8> {
  using type = float8;
  using bits = int8;
};
template <>
struct VectorOf<16> {
  using type = float16;
  using bits = int16;
};
template <int N>
using vec = typename VectorOf<N>::type;
static_assert(sizeof(vec<8>) == 8 * sizeof(float));

using double2 = double __attribute__((vector_size(16)));
using double4 = double __attribute__((vector_size(32)));
using double8 = double __attribute__((vector_size(64)));

/// The vector of N values of S, float (N = 4, 8, 16) or double (N = 2, 4, 8).
template <class S, int N>
struct VectorType;
template <int N>
struct VectorType<float, N> {
  using type = typename VectorOf<N>::type;
};
template <>
struct VectorType<double, 2> {
  using type = double2;
};
template <>
struct VectorType<double, 4> {
  using type = double4;
};
template <>
struct VectorType<double, 8> {
  using type = double8;
};
template <class S, int N>
using vector_of = typename VectorType<S, N>::type;

/// A vector loaded from `p` (no alignment required).
template <class T, class S>
[[gnu::always_inline]] inline T load_as(const S* p) {
  T v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

/// A non-temporal store of `x` to `p` (aligned to the vector's size): written past the cache, for
/// Stores::streaming. Not the intrinsics, which would need the instruction set's target attribute
/// on every function that inlines them, while the kernels' templates serve all three targets:
/// clang's builtin, and for GCC, which has none, the instruction itself. A kernel that streams
/// ends with stream_fence().
template <class V>
[[gnu::always_inline]] inline void store_streaming(float* p, const V& x) {
  V* at = reinterpret_cast<V*>(p);
#if defined(__clang__)
  __builtin_nontemporal_store(x, at);
#else
  if constexpr (sizeof(V) == 16)
    asm("{movntps %1, %0|movntps %0, %1}" : "=m"(*at) : "x"(x));  // AT&T | Intel syntax
  else
    asm("{vmovntps %1, %0|vmovntps %0, %1}" : "=m"(*at) : "v"(x));
#endif
}
/// Orders the non-temporal stores before the stores that follow, so that they are visible to
/// other threads, as ordinary stores are, once the job has returned.
[[gnu::always_inline]] inline void stream_fence() { asm volatile("sfence" ::: "memory"); }

}  // namespace dq::kernels
#endif

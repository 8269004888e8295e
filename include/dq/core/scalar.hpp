// Scalar traits shared by every generic algorithm in dqkit.
//
// Algorithms are written once over a scalar T. T is a built-in floating-point type or one of
// dqkit's derivative-carrying scalars (Dual, HyperDual, and, for operation counting, Counted).
// Such scalars specialise `scalar_traits` so that tolerances and branch decisions use the
// underlying real value.
#pragma once

#include <cmath>
#include <limits>
#include <numbers>
#include <type_traits>

/// 1 where the compiler has generic vector types (`vector_size`) and __builtin_shufflevector
/// (GCC 12+, Clang): SIMD written once for every instruction set, with no intrinsics of one.
#if !defined(DQKIT_VECTOR_EXTENSIONS)
#if defined(__clang__) || (defined(__GNUC__) && __GNUC__ >= 12)
#define DQKIT_VECTOR_EXTENSIONS 1
#else
#define DQKIT_VECTOR_EXTENSIONS 0
#endif
#endif
/// 1 where Quaternion<float>::rotate and DualQuaternion<float>::transform_point run x, y and z in
/// the lanes of one vector: with vector extensions, unless the build targets AVX2. There GCC
/// vectorizes the scalar formula of a loop over points eight elements at a time, faster than one
/// point per vector (bench_core's PointDualQuaternion: 1.5 against 2.6 ns per point); in a
/// baseline x86-64 build it does not (4.4 ns, against 2.5–3.3 with lanes). Either way the results are
/// bit-identical, so translation units built with and without AVX2 agree (docs/design.md, on the
/// one-definition rule); define it to 0 or 1 to have one body everywhere.
#if !defined(DQKIT_VEC3_LANES)
#if DQKIT_VECTOR_EXTENSIONS && !defined(__AVX2__)
#define DQKIT_VEC3_LANES 1
#else
#define DQKIT_VEC3_LANES 0
#endif
#endif

/// 1 where DualQuaternion<float>'s product runs in AVX's eight lanes (detail::dual_product_lanes):
/// with vector extensions, where the build targets AVX. In -mavx2 -mfma builds that took the
/// product from 43 to 34 instructions and from 1.27–1.42 × GLM `dualquat`'s time to 0.87–0.94
/// (docs/performance.md). Bit-identical to the four-lane form, as DQKIT_VEC3_LANES' two
/// bodies are (docs/design.md, on the one-definition rule); define it to 0 to have one body everywhere.
#if !defined(DQKIT_PRODUCT_EIGHT_LANES)
#if DQKIT_VECTOR_EXTENSIONS && defined(__AVX__)
#define DQKIT_PRODUCT_EIGHT_LANES 1
#else
#define DQKIT_PRODUCT_EIGHT_LANES 0
#endif
#elif DQKIT_PRODUCT_EIGHT_LANES && !(DQKIT_VECTOR_EXTENSIONS && defined(__AVX__))
#error "DQKIT_PRODUCT_EIGHT_LANES=1 needs vector extensions and a build that targets AVX"
#endif

namespace dq {

template <class T>
struct scalar_traits {
  static_assert(std::is_floating_point_v<T>, "specialise dq::scalar_traits for this scalar");
  using real_type = T;  // the built-in type at the bottom of a nested scalar
  static constexpr real_type value(const T& x) noexcept { return x; }
  static constexpr real_type largest_part(const T& x) noexcept { return x < T(0) ? -x : x; }
  static constexpr bool has_derivatives = false;  ///< carries derivative parts (Dual, HyperDual)
};

template <class T>
using real_t = typename scalar_traits<T>::real_type;

/// The real value of a scalar: itself for float/double, the value part for derivative scalars.
/// Used for branch decisions (thresholds, signs) so that derivative parts follow the same branch.
template <class T>
constexpr real_t<T> value_of(const T& x) noexcept {
  return scalar_traits<T>::value(x);
}

/// Whether T carries derivative parts: generic code then takes the forms whose derivatives are
/// right (series in θ², core/series.hpp), where plain values take the faster closed forms.
template <class T>
inline constexpr bool has_derivatives_v = scalar_traits<T>::has_derivatives;

/// The largest magnitude among all parts of x (value and derivative parts): iterations over
/// derivative scalars converge when this, not only the value, is small.
template <class T>
constexpr real_t<T> largest_part(const T& x) noexcept {
  return scalar_traits<T>::largest_part(x);
}

/// 0 for a finite x, NaN for NaN or ±∞: added to a result that would otherwise drop x, it keeps
/// the NaN policy (NaN in, NaN out) on paths that return a constant.
template <class T>
constexpr T nan_if_not_finite(const T& x) noexcept {
  return x * T(0);
}

/// Machine epsilon of the underlying real type.
template <class T>
constexpr real_t<T> epsilon() noexcept {
  return std::numeric_limits<real_t<T>>::epsilon();
}

namespace detail {
/// √x at compile time (Newton's iteration from above), for tolerances derived from epsilon.
template <class R>
constexpr R constexpr_sqrt(R x) {
  R r = x < R(1) ? R(1) : x;
  for (int i = 0; i < 200; ++i) {
    const R next = (r + x / r) / 2;
    if (next >= r) break;
    r = next;
  }
  return r;
}
}  // namespace detail

/// ε^(1/4): below it, series replace closed forms like sin(x)/x (their error is then under ε).
template <class T>
inline constexpr real_t<T> fourth_root_epsilon = detail::constexpr_sqrt(detail::constexpr_sqrt(epsilon<T>()));

template <class T>
inline constexpr real_t<T> pi_v = std::numbers::pi_v<real_t<T>>;

}  // namespace dq

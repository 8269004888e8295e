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

namespace dq {

template <class T>
struct scalar_traits {
  static_assert(std::is_floating_point_v<T>, "specialise dq::scalar_traits for this scalar");
  using real_type = T;  // the built-in type at the bottom of a nested scalar
  static constexpr real_type value(const T& x) noexcept { return x; }
};

template <class T>
using real_t = typename scalar_traits<T>::real_type;

/// The real value of a scalar: itself for float/double, the value part for derivative scalars.
/// Used for branch decisions (thresholds, signs) so that derivative parts follow the same branch.
template <class T>
constexpr real_t<T> value_of(const T& x) noexcept {
  return scalar_traits<T>::value(x);
}

/// Machine epsilon of the underlying real type.
template <class T>
constexpr real_t<T> epsilon() noexcept {
  return std::numeric_limits<real_t<T>>::epsilon();
}

template <class T>
inline constexpr real_t<T> pi_v = std::numbers::pi_v<real_t<T>>;

}  // namespace dq

// Alexa's "linear combination of transformations" (SIGGRAPH 2002) for 4x4 matrices, with the real
// matrix logarithm and exponential: A ⊕ B = e^{log A + log B}, α ⊙ A = e^{α log A}, so that
// interpolation is e^{(1−t) log A + t log B}. (The Arends thesis applies log and exp element-wise,
// which is not the operator; see docs/seed-errata.md.) This is the seeds' matrix baseline: it
// is not the screw motion (log A and log B do not commute) and costs far more than sclerp.
#pragma once

#include <cmath>
#include <type_traits>
#include <optional>
#include <ranges>
#include <span>

#include "dq/core/matrix.hpp"
#include "dq/util/assert.hpp"

namespace dq {

namespace detail {
template <class T, int N>
T max_abs_entry(const Mat<T, N, N>& a) {
  using std::abs;
  T m = T(0);
  for (const T& v : a.m) m = abs(v) > m ? abs(v) : m;
  return m;
}
/// Inverse by Gauss–Jordan elimination with partial pivoting; nullopt if singular.
template <class T, int N>
std::optional<Mat<T, N, N>> inverse(Mat<T, N, N> a) {
  using std::abs;
  Mat<T, N, N> inv = Mat<T, N, N>::identity();
  for (int c = 0; c < N; ++c) {
    int piv = c;
    for (int r = c + 1; r < N; ++r)
      if (abs(a(r, c)) > abs(a(piv, c))) piv = r;
    if (a(piv, c) == T(0)) return std::nullopt;
    for (int k = 0; k < N; ++k) {
      std::swap(a(c, k), a(piv, k));
      std::swap(inv(c, k), inv(piv, k));
    }
    const T d = a(c, c);
    for (int k = 0; k < N; ++k) {
      a(c, k) = a(c, k) / d;
      inv(c, k) = inv(c, k) / d;
    }
    for (int r = 0; r < N; ++r) {
      if (r == c) continue;
      const T f = a(r, c);
      for (int k = 0; k < N; ++k) {
        a(r, k) = a(r, k) - f * a(c, k);
        inv(r, k) = inv(r, k) - f * inv(c, k);
      }
    }
  }
  return inv;
}
}  // namespace detail

/// e^A by scaling and squaring with a Taylor polynomial (the scaled norm is below 1/4, where 18
/// terms reach full double precision).
template <class T, int N>
Mat<T, N, N> matrix_exp(const Mat<T, N, N>& a) {
  int squarings = 0;
  Mat<T, N, N> x = a;
  while (value_of(detail::max_abs_entry(x)) * N > 0.25 && squarings < 64) {
    x = x * T(0.5);
    ++squarings;
  }
  Mat<T, N, N> sum = Mat<T, N, N>::identity(), term = Mat<T, N, N>::identity();
  for (int k = 1; k <= 18; ++k) {
    term = term * x * (T(1) / T(k));
    sum = sum + term;
  }
  for (int i = 0; i < squarings; ++i) sum = sum * sum;
  return sum;
}

/// The principal logarithm of A by inverse scaling and squaring: Denman–Beavers square roots
/// until A^(1/2^k) is near I, then the series of log(I + E). Requires no eigenvalue on the closed
/// negative real axis (for a rigid transform: rotation angle below π); otherwise nullopt.
template <class T, int N>
std::optional<Mat<T, N, N>> matrix_log(const Mat<T, N, N>& a) {
  using std::isfinite;
  const Mat<T, N, N> id = Mat<T, N, N>::identity();
  Mat<T, N, N> y = a;
  int roots = 0;
  while (value_of(detail::max_abs_entry(y - id)) * N > 0.25) {
    if (++roots > 40) return std::nullopt;
    Mat<T, N, N> z = id;  // Denman–Beavers: y → √A, z → √A⁻¹
    for (int it = 0; it < 100; ++it) {
      const auto yi = detail::inverse(y), zi = detail::inverse(z);
      if (!yi || !zi) return std::nullopt;
      const Mat<T, N, N> ny = (y + *zi) * T(0.5), nz = (z + *yi) * T(0.5);
      const T change = detail::max_abs_entry(ny - y);
      y = ny;
      z = nz;
      if (value_of(change) <= 8 * epsilon<T>() * value_of(detail::max_abs_entry(y))) break;
    }
    for (const T& v : y.m)
      if (!isfinite(value_of(v))) return std::nullopt;
  }
  const Mat<T, N, N> e = y - id;
  Mat<T, N, N> sum{}, power = id;
  for (int k = 1; k <= 40; ++k) {
    power = power * e;
    sum = sum + power * (T(k % 2 ? 1 : -1) / T(k));
  }
  return sum * T(real_t<T>(1ull << roots));
}

/// Alexa's weighted combination ⊕ᵢ (wᵢ ⊙ Aᵢ) = e^{Σ wᵢ log Aᵢ}; nullopt if a logarithm does not
/// exist (a rotation by exactly π). Precondition: one weight per matrix.
template <class T>
std::optional<Mat4<T>> alexa_blend(std::span<const Mat4<T>> matrices, std::span<const T> weights) {
  DQ_PRECONDITION(weights.size() == matrices.size(), "alexa_blend needs one weight per matrix", std::nullopt);
  Mat4<T> sum{};
  for (std::size_t i = 0; i < matrices.size(); ++i) {
    const auto l = matrix_log(matrices[i]);
    if (!l) return std::nullopt;
    sum = sum + *l * weights[i];
  }
  return matrix_exp(sum);
}

/// alexa_blend over any contiguous containers, the scalar type taken from the weights.
template <std::ranges::contiguous_range Ms, std::ranges::contiguous_range Ws>
auto alexa_blend(const Ms& matrices, const Ws& weights) {
  using T = std::ranges::range_value_t<Ws>;
  return alexa_blend(std::span<const Mat4<T>>(matrices), std::span<const T>(weights));
}

/// Alexa interpolation e^{(1−t) log A + t log B}.
template <class T>
std::optional<Mat4<T>> alexa_interpolate(const Mat4<T>& a, const Mat4<T>& b, const std::type_identity_t<T>& t) {
  const std::array<Mat4<T>, 2> m{a, b};
  const std::array<T, 2> w{T(1) - t, t};
  return alexa_blend<T>(m, w);
}

}  // namespace dq

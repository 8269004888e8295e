// Interpolating and blending rigid transforms: ScLERP, dual quaternion linear blending (DLB),
// iterative blending (DIB, the dual-quaternion mean), and decoupled interpolation.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>
#include <ranges>
#include <span>

#include "dq/core/exp_log.hpp"
#include "dq/interp/rotation.hpp"
#include "dq/util/assert.hpp"

namespace dq {

namespace detail {
/// For plain values, q itself if it is a unit dual quaternion to rounding (|q_r|² within 4 ε of 1,
/// q_r · q_d within 4 ε of the dual part's size, bounded by its 1-norm), else q.normalized():
/// inputs that drifted (read from files, composed in float) become the rigid transforms they
/// stand for, and ones within 4 ε keep their bits (the products of a few unit transforms mostly
/// are). With derivative parts, always q.normalized(): derivatives off the unit surface are then
/// those of the normalized input, whatever the value's rounding.
template <class T>
DualQuaternion<T> unit_to_rounding(const DualQuaternion<T>& q) {
  using std::abs;
  using R = real_t<T>;
  if constexpr (!has_derivatives_v<T>) {
    const R rd = value_of(dot(q.real, q.dual));
    const R size = abs(value_of(q.dual.w)) + abs(value_of(q.dual.x)) + abs(value_of(q.dual.y)) + abs(value_of(q.dual.z));
    if (is_unit_to_rounding(value_of(dot(q.real, q.real))) && abs(rd) <= R(4) * std::numeric_limits<R>::epsilon() * (R(1) + size)) [[likely]]
      return q;
  }
  return q.normalized();
}
}  // namespace detail

/// Screw linear interpolation a · (a⁻¹ b)^t between rigid transforms: the screw motion from a
/// (t = 0) to b (t = 1) at constant angular and linear speed. Shortest by default (the sign of
/// a⁻¹ b is chosen with w ≥ 0); Path::longest turns the other way round the same screw axis.
/// Inputs that are not unit are normalized first (as slerp's are; a zero real part reads as the
/// identity, as in normalized()). Defined for every pair: identical rotations and pure
/// translations give the straight line, exactly. When the rotations are exactly π apart both ways
/// are equally short: the sign of b as given decides, and `report->ambiguous` is set. Never NaN
/// for finite input.
template <class T>
DualQuaternion<T> sclerp(const DualQuaternion<T>& a_in, const DualQuaternion<T>& b_in, const std::type_identity_t<T>& t,
                         Path path = Path::shortest, InterpolationReport* report = nullptr) {
  const DualQuaternion<T> a = detail::unit_to_rounding(a_in), b = detail::unit_to_rounding(b_in);
  DualQuaternion<T> d = a.conjugate() * b;  // a⁻¹ b for unit a
  d = detail::align_sign(d, d.real.w, path, report);
  // Renormalized: with translations far larger than the result's, the product cancels and its
  // rounding (tiny relative to the inputs) would otherwise break the unit condition of the output.
  return (a * exp(log(d) * t)).normalized();
}

/// The sign policy of dlb: each input's sign is aligned with a pivot, not with the running sum.
/// (Aligning with the running sum makes the result depend on the input order.)
enum class BlendPivot {
  largest_weight,  ///< the input with the largest weight (ties: the first); the default
  first,           ///< the first input
};

/// Dual quaternion linear blending (Kavan et al. 2008): Σ wᵢ sᵢ Qᵢ normalized, with sᵢ = ±1
/// aligning each real part with the pivot's. Weights need not sum to 1 (only their ratios
/// matter) and may be zero. The result is always a unit dual quaternion, returned with the sign
/// of the first input (q_r · first ≥ 0), so that it is continuous in the weights even where the
/// pivot changes; an empty input, or one whose weighted sum has a zero real part, gives the
/// identity. Precondition: one weight per input.
template <class T>
DualQuaternion<T> dlb(std::span<const DualQuaternion<T>> qs, std::span<const T> weights,
                      BlendPivot pivot = BlendPivot::largest_weight) {
  DQ_PRECONDITION(weights.size() == qs.size(), "dlb needs one weight per dual quaternion", detail::nan_dual_quaternion<T>());
  if (qs.empty()) return DualQuaternion<T>::identity();
  std::size_t p = 0;
  if (pivot == BlendPivot::largest_weight)
    for (std::size_t i = 1; i < qs.size(); ++i)
      if (weights[i] > weights[p]) p = i;
  DualQuaternion<T> sum{Quaternion<T>(T(0), T(0), T(0), T(0)), Quaternion<T>(T(0), T(0), T(0), T(0))};
  for (std::size_t i = 0; i < qs.size(); ++i) {
    const T w = dot(qs[p].real, qs[i].real) < T(0) ? -weights[i] : weights[i];
    sum = sum + qs[i] * w;
  }
  const DualQuaternion<T> blend = sum.normalized();
  return dot(blend.real, qs[0].real) < T(0) ? -blend : blend;
}

/// dlb of two keys, (1 − t) a + t b with b's sign aligned to a's, normalized: the interpolation
/// that skinning and animation runtimes use between keys. Continuous in t, including extrapolation;
/// the result has a's sign.
template <class T>
DualQuaternion<T> dlb(const DualQuaternion<T>& a, const DualQuaternion<T>& b, const std::type_identity_t<T>& t) {
  const T wb = dot(a.real, b.real) < T(0) ? -t : t;
  const DualQuaternion<T> blend = (a * (T(1) - t) + b * wb).normalized();
  return dot(blend.real, a.real) < T(0) ? -blend : blend;
}

/// The result of dib: the blend and how the iteration went.
template <class T>
struct IterativeBlend {
  DualQuaternion<T> value;
  int iterations = 0;
  bool converged = false;
  T residual{};  ///< |Σ wᵢ log(b⁻¹ Qᵢ)| at the end (0 at the exact mean)
};

/// Dual quaternion iterative blending (Kavan's DIB): starting from dlb, repeats
/// b ← b · exp(Σ wᵢ log(b⁻¹ Qᵢ) / Σ wᵢ) until the update is below `tolerance` (or
/// `max_iterations`). The fixed point is the screw-consistent mean: for two inputs it lies on the
/// sclerp between them. Weights must be non-negative with a positive sum.
template <class T>
IterativeBlend<T> dib(std::span<const DualQuaternion<T>> qs, std::span<const T> weights, int max_iterations = 20,
                      const std::type_identity_t<T>& tolerance = T(64) * T(epsilon<T>())) {
  using std::sqrt;
  IterativeBlend<T> out;
  DQ_PRECONDITION(weights.size() == qs.size(), "dib needs one weight per dual quaternion",
                  IterativeBlend<T>{detail::nan_dual_quaternion<T>(), 0, false, T(0)});
  out.value = dlb(qs, weights);
  T total = T(0);
  for (const T& w : weights) total += w;
  if (qs.empty() || !(total > T(0))) {
    out.converged = true;
    return out;
  }
  for (out.iterations = 0; out.iterations < max_iterations;) {
    DualQuaternion<T> step{Quaternion<T>(T(0), T(0), T(0), T(0)), Quaternion<T>(T(0), T(0), T(0), T(0))};
    const DualQuaternion<T> inv = out.value.conjugate();
    for (std::size_t i = 0; i < qs.size(); ++i) {
      DualQuaternion<T> rel = inv * qs[i];
      if (rel.real.w < T(0)) rel = -rel;
      step = step + log(rel) * (weights[i] / total);
    }
    out.residual = sqrt(dot(step.real, step.real) + dot(step.dual, step.dual));
    ++out.iterations;
    out.value = (out.value * exp(step)).normalized();
    // Converged when every part of the step is small, derivative parts included (they converge
    // with the value, but need not be small when it is).
    real_t<T> largest = 0;
    for (const T* c : {&step.real.x, &step.real.y, &step.real.z, &step.dual.x, &step.dual.y, &step.dual.z})
      largest = std::max(largest, largest_part(*c));
    if (largest <= value_of(tolerance)) {
      out.converged = true;
      break;
    }
  }
  return out;
}

/// dlb and dib over any contiguous containers (std::vector, std::array, ...), the scalar type
/// taken from the elements: `dlb(poses, weights)` without naming T.
template <std::ranges::contiguous_range Qs, std::ranges::contiguous_range Ws>
  requires detail::is_dual_quaternion_v<std::ranges::range_value_t<Qs>>
auto dlb(const Qs& qs, const Ws& weights, BlendPivot pivot = BlendPivot::largest_weight) {
  using T = typename std::ranges::range_value_t<Qs>::scalar_type;
  return dlb(std::span<const DualQuaternion<T>>(qs), std::span<const T>(weights), pivot);
}
template <std::ranges::contiguous_range Qs, std::ranges::contiguous_range Ws>
  requires detail::is_dual_quaternion_v<std::ranges::range_value_t<Qs>>
auto dib(const Qs& qs, const Ws& weights, int max_iterations = 20) {
  using T = typename std::ranges::range_value_t<Qs>::scalar_type;
  return dib(std::span<const DualQuaternion<T>>(qs), std::span<const T>(weights), max_iterations);
}

/// Decoupled interpolation: slerp for the rotation, a straight line for the translation (what
/// most engines do). The path differs from sclerp whenever the rotation changes.
template <class T>
DualQuaternion<T> decoupled_interpolate(const DualQuaternion<T>& a, const DualQuaternion<T>& b, const std::type_identity_t<T>& t,
                                        Path path = Path::shortest) {
  const Vec3<T> ta = a.translation(), tb = b.translation();
  return DualQuaternion<T>::from_rotation_translation(slerp(a.real, b.real, t, path), ta + (tb - ta) * t);
}

}  // namespace dq

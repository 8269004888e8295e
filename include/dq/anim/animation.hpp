// Animations as sampled local transforms, and sampling them at any time with a chosen
// interpolation, looping or clamped.
#pragma once

#include <cmath>
#include <limits>
#include <ranges>
#include <span>
#include <type_traits>
#include <vector>

#include "dq/util/assert.hpp"
#include "dq/anim/animation_data.hpp"
#include "dq/convert/matrix.hpp"
#include "dq/interp/rigid.hpp"

namespace dq {

enum class Interpolation {
  screw,              ///< sclerp: constant-speed screw motion between frames
  dual_quaternion_linear,  ///< dlb of the two frames (cheap, what skinning uses; not constant speed)
  decoupled,          ///< slerp rotation + linear translation
  matrix,             ///< element-wise lerp of 3x4 matrices, rotation re-orthonormalized (polar)
};

enum class WrapMode {
  clamp,  ///< before 0: frame 0; after the last frame: the last frame
  loop,   ///< period frame_count × frame_time: after the last frame it blends back into frame 0
};

/// Interpolates one transform between a (u = 0) and b (u = 1).
template <class T>
DualQuaternion<T> interpolate(const DualQuaternion<T>& a, const DualQuaternion<T>& b, const T& u, Interpolation mode) {
  switch (mode) {
    case Interpolation::screw: return sclerp(a, b, u);
    case Interpolation::dual_quaternion_linear: {
      const std::array<DualQuaternion<T>, 2> q{a, b};
      const std::array<T, 2> w{T(1) - u, u};
      return dlb<T>(q, w, BlendPivot::first);
    }
    case Interpolation::decoupled: return decoupled_interpolate(a, b, u);
    case Interpolation::matrix: {
      const Mat34<T> m = to_mat34(a) * (T(1) - u) + to_mat34(b) * u;
      Mat34<T> r = m;
      const Mat3<T> rot = orthonormalize_polar(rotation_block(m));
      for (int c = 0; c < 3; ++c)
        for (int row = 0; row < 3; ++row) r(row, c) = rot(row, c);
      return from_matrix(r);
    }
  }
  return a;
}

/// Samples the animation at `time` (seconds) into `out` (any scalar type). An animation with no
/// frames leaves `out` unchanged; one frame is constant. With WrapMode::clamp a time beyond the
/// ends, ±∞ included, gives the first or the last frame; a NaN time, or an infinite one with
/// WrapMode::loop (no phase), gives NaN transforms (docs/reliability.md, the NaN policy).
/// Precondition: one output per joint.
template <class T>
void sample(const Animation& anim, double time, Interpolation mode, WrapMode wrap, std::span<DualQuaternion<T>> out) {
  DQ_PRECONDITION(out.size() == anim.joint_count, "sample needs one output per joint of the animation");
  if (anim.frame_count == 0) return;
  const double n = static_cast<double>(anim.frame_count);
  const double x_unwrapped = anim.frame_time > 0 ? time / anim.frame_time : 0;  // in frames; ±∞ where it overflows
  if (std::isnan(time) || std::isnan(x_unwrapped) || (wrap == WrapMode::loop && (std::isinf(time) || std::isinf(x_unwrapped)))) {
    const T nan = T(std::numeric_limits<real_t<T>>::quiet_NaN());
    const Quaternion<T> q(nan, nan, nan, nan);
    for (DualQuaternion<T>& o : out) o = DualQuaternion<T>(q, q);
    return;
  }
  double x = x_unwrapped;
  if (wrap == WrapMode::loop) {
    x = std::fmod(x, n);
    if (x < 0) x += n;
  } else {
    x = std::clamp(x, 0.0, n - 1);
  }
  const std::size_t f0 = std::min(static_cast<std::size_t>(x), anim.frame_count - 1);
  const std::size_t f1 = (f0 + 1 < anim.frame_count) ? f0 + 1 : (wrap == WrapMode::loop ? 0 : f0);
  const T u = static_cast<T>(x - static_cast<double>(f0));
  const auto a = anim.frame(f0), b = anim.frame(f1);
  for (std::size_t j = 0; j < anim.joint_count; ++j) {
    out[j] = (u == T(0) || f0 == f1) ? a[j].template cast<T>()
                                      : interpolate(a[j].template cast<T>(), b[j].template cast<T>(), u, mode);
  }
}
/// sample into any contiguous container of dual quaternions (std::vector, std::array): the scalar
/// type deduced, not named.
template <std::ranges::contiguous_range Out>
  requires detail::is_dual_quaternion_v<std::ranges::range_value_t<Out>> &&
           (!std::is_const_v<std::remove_reference_t<std::ranges::range_reference_t<Out>>>)
void sample(const Animation& anim, double time, Interpolation mode, WrapMode wrap, Out&& out) {
  using Q = std::ranges::range_value_t<Out>;
  sample<typename Q::scalar_type>(anim, time, mode, wrap, std::span<Q>(std::ranges::data(out), std::ranges::size(out)));
}

}  // namespace dq

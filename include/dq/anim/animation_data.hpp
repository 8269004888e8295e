// Animations as data: sampled local transforms of every joint. What file readers produce and
// runtime code consumes; sampling at any time is in dq/anim/animation.hpp.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include "dq/core/dual_quaternion.hpp"

namespace dq {

/// Local (parent-relative) transforms of every joint at evenly spaced frames.
struct Animation {
  double frame_time = 1.0 / 30;  ///< seconds between frames
  std::size_t frame_count = 0;
  std::size_t joint_count = 0;
  std::vector<DualQuaternion<double>> locals;  ///< frame-major: locals[frame * joint_count + joint]

  /// Time of the last frame: (frame_count − 1) × frame_time.
  double duration() const noexcept { return frame_count ? frame_time * static_cast<double>(frame_count - 1) : 0; }
  std::span<const DualQuaternion<double>> frame(std::size_t f) const {
    return std::span(locals).subspan(f * joint_count, joint_count);
  }
};

}  // namespace dq

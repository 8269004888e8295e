// local_to_model_frames in its two steps, so that local_to_model_frames_parallel (src/simd/parallel.cpp)
// checks the whole batch once and then computes its ranges. Private to dqkit.
#pragma once

#include <span>

#include "dq/core/dual_quaternion.hpp"
#include "dq/util/expected.hpp"

namespace dq::simd {

/// local_to_model_frames' checks of its arguments: the error it returns, or none (T = float, double).
template <class T>
Status check_frames(std::span<const int> parents, std::span<const DualQuaternion<T>> local,
                    std::span<const DualQuaternion<T>> model);

/// local_to_model_frames' computation, on arguments that check_frames accepted.
void compute_frames(std::span<const int> parents, std::span<const DualQuaternion<float>> local,
                    std::span<DualQuaternion<float>> model);
void compute_frames(std::span<const int> parents, std::span<const DualQuaternion<double>> local,
                    std::span<DualQuaternion<double>> model);

}  // namespace dq::simd

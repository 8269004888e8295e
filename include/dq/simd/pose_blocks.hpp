// Forward kinematics of poses in blocks of 16 (dq/anim/pose_blocks.hpp) with the product
// vectorized for the CPU's widest instruction set, chosen at run time as the other batch kernels
// (dq/simd/batch.hpp); on one thread or on oneTBB's workers.
#pragma once

#include <cstddef>
#include <span>

#include "dq/anim/pose_blocks.hpp"
#include "dq/simd/batch.hpp"

namespace dq::simd {

/// Runs the job with the dispatched product: bit for bit job.run()'s result. Precondition:
/// job.validate().
void run(const BlockedForwardKinematicsJob<float>& job);

/// Forward kinematics of many frames stored one after another, each frame's joints in order
/// (joint j of frame f at [f · J + j], J = parents.size(): a NumPy (F, J, 8) array, or the frames
/// of dq::sample one after the other): model[j] = model[parent(j)] · local[j] in every frame, with
/// the dispatched product on as many frames at a time as the vector has lanes, each joint's local
/// transforms loaded and transposed in place (no copy of the batch in another layout; the model
/// transforms of up to 128 joints kept transposed on the stack, 64 KB with AVX-512). Bit for bit
/// the blocked job's result (the product of the batch kernels; the scalar types' float operator*
/// may differ in the sign of an exact zero, docs/design.md). `model` may not overlap `local`.
/// Returns the error, and computes nothing, when a parent does not come before its child or the
/// spans are not one whole number of frames of the same length.
Status local_to_model_frames(std::span<const int> parents, std::span<const DualQuaternion<float>> local,
                             std::span<DualQuaternion<float>> model);
/// The same for double, with the same checks and errors: 2, 4 or 8 frames at a time (SSE2, AVX2,
/// AVX-512), records of eight doubles transposed the same way; bit for bit dq::local_to_model on
/// each frame alone (DualQuaternion<double>'s product is the batch product, with no fused
/// multiply-adds).
Status local_to_model_frames(std::span<const int> parents, std::span<const DualQuaternion<double>> local,
                             std::span<DualQuaternion<double>> model);

/// local_to_model_frames on oneTBB's persistent worker threads (in a build without oneTBB: one
/// thread per part, started for the call): the frames split at multiples of 16 frames (whole
/// vectors on every target, so only the last range has a scalar tail) into ranges of about `grain`
/// frames or more (at least 16; oneTBB splits a range only while it is longer than `grain`, as far
/// as its workers need; without oneTBB, one range per thread), each computed by one task.
/// `threads` limits the workers used (0: every hardware thread; 1: this thread, no task). Bit for
/// bit local_to_model_frames' result, with the same errors, returned before any work. For float
/// and double.
Status local_to_model_frames_parallel(std::span<const int> parents, std::span<const DualQuaternion<float>> local,
                                      std::span<DualQuaternion<float>> model, unsigned threads = 0, std::size_t grain = 256);
Status local_to_model_frames_parallel(std::span<const int> parents, std::span<const DualQuaternion<double>> local,
                                      std::span<DualQuaternion<double>> model, unsigned threads = 0, std::size_t grain = 256);

/// Runs a job on oneTBB's persistent worker threads (in a build without oneTBB: one thread per part,
/// started for the call), split into block ranges of about `grain` blocks or more (16 poses each;
/// oneTBB splits a range only while it is longer than `grain`, as far as its workers need; without
/// oneTBB, one range per thread), each written by one task. `threads` limits the workers used (0:
/// every hardware thread; 1: this thread, no task). Float jobs use the dispatched product. Returns
/// the job's validation error instead of running an invalid job.
template <class T>
Status run_parallel(const BlockedForwardKinematicsJob<T>& job, unsigned threads = 0, std::size_t grain = 16);
extern template Status run_parallel(const BlockedForwardKinematicsJob<float>&, unsigned, std::size_t);
extern template Status run_parallel(const BlockedForwardKinematicsJob<double>&, unsigned, std::size_t);

}  // namespace dq::simd

// Batch kernels over structure-of-arrays float data, with the instruction set chosen at run time
// (dqkit::simd). The same formulas as the scalar types (detail::hamilton, detail::dual_product,
// DualQuaternion::transform_point), evaluated on vectors of 4, 8 or 16 lanes: compiled once per
// instruction set in src/simd/batch.cpp and dispatched by what the CPU supports. Every path
// performs the scalar formula's operations in the same order, without fused multiply-adds, so each
// lane is bit-identical to the scalar result (tested for every path the CPU has).
#pragma once

#include <array>
#include <cstddef>
#include <string_view>

#include "dq/anim/forward_kinematics.hpp"

namespace dq::simd {

enum class Target { scalar, sse2, avx2, avx512 };

/// The widest target this CPU supports (scalar only if the build has no vector extensions).
Target best_target() noexcept;
/// The target in use: best_target() unless limited by use_target.
Target current_target() noexcept;
/// Uses at most `t` (for tests and measurements); returns the target now in use (the lower of
/// `t` and best_target()). Not thread-safe with running kernels.
Target use_target(Target t) noexcept;
std::string_view to_string(Target t) noexcept;

using ConstRows = detail::Row8<const float>;  ///< eight component arrays of dual quaternions
using Rows = detail::Row8<float>;

/// out[i] = a[i] · b[i] for i < n. `out` may be `a` or `b` (element by element); partial overlaps
/// are not allowed.
void compose(ConstRows a, ConstRows b, Rows out, std::size_t n);

/// out[i] = q[i] applied to the point p[i] (R p + t), for i < n; components x, y, z.
void transform_points(ConstRows q, std::array<const float*, 3> p, std::array<float*, 3> out, std::size_t n);

/// Four component arrays of quaternions (w, x, y, z).
template <class T>
struct QuaternionRows {
  T *w, *x, *y, *z;
};

/// out[i] = slerp(a[i], b[i], t) for i < n: the shortest arc, inputs normalized first, no failure
/// case (equal, nearly opposite and opposite endpoints give unit results), as dq::slerp. Computed
/// branch-free on the vector lanes with polynomials accurate to float precision on the range
/// t ∈ [0, 1] covers; other t (extrapolation) run dq::slerp itself. Not bit-identical to
/// dq::slerp (a different evaluation of the same function): within a few ulps (tested).
void slerp(QuaternionRows<const float> a, QuaternionRows<const float> b, float t, QuaternionRows<float> out, std::size_t n);

/// The batch forward kinematics job with the dispatched product. Precondition: job.validate().
void run(const ForwardKinematicsJob<float>& job);

/// Runs a job on oneTBB's persistent worker threads (no thread is started per call), split into
/// pose ranges of at least `grain` poses, each written by one task (no synchronization needed).
/// `threads` limits the workers used (0: every hardware thread). Float jobs use the vectorized
/// product (run above). Returns the job's validation error instead of running an invalid job.
template <class T>
Status run_parallel(const ForwardKinematicsJob<T>& job, unsigned threads = 0, std::size_t grain = 256);
extern template Status run_parallel(const ForwardKinematicsJob<float>&, unsigned, std::size_t);
extern template Status run_parallel(const ForwardKinematicsJob<double>&, unsigned, std::size_t);

}  // namespace dq::simd

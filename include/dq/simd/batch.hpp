// Batch kernels over structure-of-arrays float data (and double, for compose, inverse and the
// transforms of points and directions), with the instruction set chosen at run time
// (dqkit::simd). The same formulas as the scalar types (detail::hamilton, detail::dual_product,
// DualQuaternion::transform_point, normalized, dq::dlb, ...), evaluated on vectors of 4, 8 or 16
// float lanes (2, 4 or 8 double ones): compiled once per instruction set in src/simd/batch.cpp and
// dispatched by what the CPU supports. Every path performs the scalar formula's operations in the
// same order, without fused multiply-adds, so each lane is bit-identical to the scalar result
// (tested for every path the CPU has); slerp and sclerp, which evaluate the same function
// differently, are within a few ulps.
//
// Common rules: n may be 0; n need not be a multiple of any vector width (the remainder runs the
// scalar formula, with the same result); an output may be the very arrays of an input of the same
// shape where a function says so (element by element), but no output may partially overlap an
// input. Results for inputs that break a function's preconditions are said next to it.
#pragma once

#include <array>
#include <cstddef>
#include <span>
#include <string_view>

#include "dq/anim/forward_kinematics.hpp"

namespace dq::simd {

/// The instruction sets, narrowest first. sse42: SSE4.2 with SSSE3 and SSE4.1, the widest of CPUs
/// without AVX (x86-64-v2 but for POPCNT and CMPXCHG16B, which the kernels do not use).
enum class Target { scalar, sse2, sse42, avx2, avx512 };
inline constexpr Target kTargets[] = {Target::scalar, Target::sse2, Target::sse42, Target::avx2, Target::avx512};

/// The widest target this CPU supports (scalar only if the build has no vector extensions).
Target best_target() noexcept;
/// The targets this CPU supports, narrowest first: kTargets up to best_target().
inline std::span<const Target> available_targets() noexcept {
  static_assert(
      [] {
        for (std::size_t i = 0; i < std::size(kTargets); ++i)
          if (static_cast<std::size_t>(kTargets[i]) != i) return false;
        return true;
      }(),
      "kTargets is indexed by Target");
  return std::span<const Target>(kTargets).first(static_cast<std::size_t>(best_target()) + 1);
}
/// The target in use: best_target() unless limited by use_target.
Target current_target() noexcept;
/// Uses at most `t` (for tests and measurements); returns the target now in use (the lower of
/// `t` and best_target()). Not thread-safe with running kernels.
Target use_target(Target t) noexcept;
std::string_view to_string(Target t) noexcept;
/// use_target(t) for a scope, then the target in use before (for tests and measurements; not
/// thread-safe with running kernels).
class ScopedTarget {
 public:
  explicit ScopedTarget(Target t) noexcept : previous_(current_target()) { use_target(t); }
  ~ScopedTarget() { use_target(previous_); }
  ScopedTarget(const ScopedTarget&) = delete;
  ScopedTarget& operator=(const ScopedTarget&) = delete;

 private:
  Target previous_;
};

using ConstRows = detail::Row8<const float>;  ///< eight component arrays of dual quaternions
using Rows = detail::Row8<float>;
/// The eight arrays of `c` (w, x, y, z of the real part, then of the dual part) as the kernels' rows.
inline ConstRows rows(const ComponentArrays<float, 8>& c) noexcept { return detail::row_of<const float>(c, 0); }
inline Rows rows(ComponentArrays<float, 8>& c) noexcept { return detail::row_of<float>(c, 0); }

/// The same in double, for the kernels that have a double form (compose, inverse,
/// transform_points and transform_directions, and the layout conversions of dual quaternions and
/// points): 2, 4 or 8 lanes a vector, half as many as float.
using ConstRowsD = detail::Row8<const double>;
using RowsD = detail::Row8<double>;
inline ConstRowsD rows(const ComponentArrays<double, 8>& c) noexcept { return detail::row_of<const double>(c, 0); }
inline RowsD rows(ComponentArrays<double, 8>& c) noexcept { return detail::row_of<double>(c, 0); }

/// out[i] = a[i] · b[i] for i < n. `out` may be `a` or `b` (element by element); partial overlaps
/// are not allowed.
void compose(ConstRows a, ConstRows b, Rows out, std::size_t n);

/// out[i] = q[i]⁻¹ for unit q[i], i < n: the quaternion conjugate q_r* + ε q_d*, bit for bit
/// DualQuaternion::inverse_unit (no division). Precondition: unit inputs; for a non-unit q the
/// result is still Q*, which is ‖Q‖² Q⁻¹ (‖Q‖² = Q Q* a dual number), not Q⁻¹: normalize first,
/// or call DualQuaternion::inverse per element. `out` may be `q`.
void inverse(ConstRows q, Rows out, std::size_t n);

/// out[i] = q[i] applied to the point p[i] (R p + t), for i < n; components x, y, z. Bit for bit
/// DualQuaternion::transform_point. Precondition: unit q (for others, the scalar formula's value,
/// which is not a rigid motion). `out` may be `p`.
void transform_points(ConstRows q, std::array<const float*, 3> p, std::array<float*, 3> out, std::size_t n);

/// out[i] = q[i] applied to the direction v[i] (R v, rotated only), for i < n; components x, y, z.
/// Bit for bit DualQuaternion::transform_direction; reads the real part of q only. Precondition:
/// unit q_r (for others, the scalar formula's value, which is not a rotation). `out` may be `v`.
void transform_directions(ConstRows q, std::array<const float*, 3> v, std::array<float*, 3> out, std::size_t n);

/// out[i] = q applied to the point in[i] (R p + t), one transform for every point: a point cloud
/// or a mesh moved rigidly, its points one after another (x, y, z; a std::vector<Vec3<float>>, a
/// NumPy (N, 3) float32 array), loaded and stored by whole vectors with no conversion pass. Bit for
/// bit DualQuaternion::transform_point. Preconditions: out.size() == in.size() (checked); unit q
/// (for others, the scalar formula's value). `out` may be `in` (not overlapping it otherwise).
void transform_points(const DualQuaternion<float>& q, std::span<const Vec3<float>> in, std::span<Vec3<float>> out);
/// The same for directions (R v, rotated only; DualQuaternion::transform_direction bit for bit).
void transform_directions(const DualQuaternion<float>& q, std::span<const Vec3<float>> in, std::span<Vec3<float>> out);

/// compose, inverse, transform_points and transform_directions in double, with the float
/// functions' rules, on the lanes of the instruction set in use. Bit for bit the scalar double
/// functions computed without fused multiply-adds: the scalar functions themselves in a build
/// without FMA; in one with it (-mfma, -march=native), GCC 12 fuses parts of the scalar double
/// functions where it inlines them (docs/design.md), and these kernels, whose elements left over
/// after the whole vectors are computed without that fusion, keep the unfused bits on every target.
void compose(ConstRowsD a, ConstRowsD b, RowsD out, std::size_t n);
void inverse(ConstRowsD q, RowsD out, std::size_t n);
void transform_points(ConstRowsD q, std::array<const double*, 3> p, std::array<double*, 3> out, std::size_t n);
void transform_directions(ConstRowsD q, std::array<const double*, 3> v, std::array<double*, 3> out, std::size_t n);
void transform_points(const DualQuaternion<double>& q, std::span<const Vec3<double>> in, std::span<Vec3<double>> out);
void transform_directions(const DualQuaternion<double>& q, std::span<const Vec3<double>> in, std::span<Vec3<double>> out);

/// compose, inverse, transform_points and transform_directions over arrays of structures, in
/// float and double: the dual quaternions one after another (a std::vector<DualQuaternion<T>>, a
/// NumPy (N, 8) array), the points too (Vec3<T>, (N, 3)), each vector of elements loaded by whole
/// elements and transposed in registers, the results transposed back and stored whole: no
/// conversion pass to component arrays. Bit for bit the same functions over component arrays
/// (above). Preconditions: the spans of one call have the same size (checked); an output may be
/// the very span of an input of its type (element by element; a point output never overlaps q),
/// not overlap it otherwise (checked).
void compose(std::span<const DualQuaternion<float>> a, std::span<const DualQuaternion<float>> b, std::span<DualQuaternion<float>> out);
void compose(std::span<const DualQuaternion<double>> a, std::span<const DualQuaternion<double>> b, std::span<DualQuaternion<double>> out);
void inverse(std::span<const DualQuaternion<float>> q, std::span<DualQuaternion<float>> out);
void inverse(std::span<const DualQuaternion<double>> q, std::span<DualQuaternion<double>> out);
void transform_points(std::span<const DualQuaternion<float>> q, std::span<const Vec3<float>> p, std::span<Vec3<float>> out);
void transform_points(std::span<const DualQuaternion<double>> q, std::span<const Vec3<double>> p, std::span<Vec3<double>> out);
void transform_directions(std::span<const DualQuaternion<float>> q, std::span<const Vec3<float>> v, std::span<Vec3<float>> out);
void transform_directions(std::span<const DualQuaternion<double>> q, std::span<const Vec3<double>> v, std::span<Vec3<double>> out);

/// The 3x4 matrices [R | t] of q[i] for i < n, in twelve arrays: out[c · 3 + r][i] is row r of
/// column c (the column-major order of Mat34::m, glTF and OpenGL). Bit for bit dq::to_mat34.
/// Precondition: unit q (for others, the scalar formula's value, which is not a rigid motion).
void to_matrices(ConstRows q, std::array<float*, 12> out, std::size_t n);

/// out[i] = q[i].normalized() for i < n (DualQuaternion::normalized, bit for bit for every input):
/// |q_r| = 1 and q_r · q_d = 0 enforced. On the vector lanes: the real part divided by its norm and
/// the dual part's component along it removed, or, where the dual part lay almost along the real
/// part, the dual part rebuilt from the translation (both branches computed, one selected per
/// lane). A vector block holding an input for one of the scalar function's other branches runs
/// that function itself, element by element: a zero real part (the identity, keeping a NaN of the
/// dual part), a tiny, huge or non-finite one (rescaled first; non-finite out), a non-finite dual
/// part. So no element is NaN where the scalar result is not. `out` may be `q`.
void normalize(ConstRows q, Rows out, std::size_t n);

/// Four component arrays of quaternions (w, x, y, z).
template <class T>
struct QuaternionRows {
  T *w, *x, *y, *z;
};

/// out[i] = slerp(a[i], b[i], t) for i < n: the shortest arc, inputs normalized first, no failure
/// case (equal, nearly opposite and opposite endpoints give unit results), as dq::slerp. Computed
/// branch-free on the vector lanes with polynomials accurate to float precision on the range
/// t ∈ [0, 1] covers; other t (extrapolation) run dq::slerp itself. Not bit-identical to
/// dq::slerp (a different evaluation of the same function): against dq::slerp in long double,
/// within 16 float ulps per component (tested; at most 3.1 measured by bench/interpolation_accuracy
/// on 16.8 million random pairs, dq::slerp<float> 3.5), on the same arc at exact ties (a · b = 0)
/// for inputs unit to rounding. Precondition on the vector lanes (t in [0, 1] and a target above
/// scalar; dq::slerp, which the others run, has none): the inputs' norms and their product between
/// 1e-18 and 1e18 (their squares normal floats); outside it results may be NaN, zero or inaccurate.
void slerp(QuaternionRows<const float> a, QuaternionRows<const float> b, float t, QuaternionRows<float> out, std::size_t n);

/// out[i] = dq::dlb(a[i], b[i], t) for i < n, bit for bit for every input: dual quaternion linear
/// blending of two keys, ((1 − t) a + t b) with b's sign aligned to a's, normalized as `normalize`
/// does (on the lanes, or by dq::dlb itself for the blocks normalize leaves to the scalar
/// function), returned with a's sign. Any t (extrapolation too). For unit inputs the result is
/// unit; for others it is what dq::dlb gives (the normalized blend; a blend with a zero real part
/// gives the identity). `out` may be `a` or `b`.
void dlb(ConstRows a, ConstRows b, float t, Rows out, std::size_t n);

/// out[i] = dq::sclerp(a[i], b[i], t) for i < n: screw linear interpolation a (a* b)^t on the
/// shortest path (a* b negated when its real part's w < 0, as dq::sclerp chooses it; where that w
/// is within rounding of 0, the choice follows its float rounding, as dq::sclerp<float> does). No
/// failure case: identical and antipodal endpoints (b = −a, the same transform), rotations nearly
/// or exactly π apart, pure translations and tiny angles give unit results, continuous in t.
/// Computed branch-free on the vector lanes for t ∈ [0, 1] (the screw's translation split along
/// and across its axis, with the polynomials of slerp; src/simd/batch.cpp derives it), then
/// renormalized as dq::sclerp is; other t (extrapolation) run dq::sclerp itself. Not bit-identical
/// to dq::sclerp: against it in long double, within 8 float ulps of 1 in the real part and 8 ulps
/// of (1 + |t_a| + |t_b|)/2 in the dual part (t_a, t_b the inputs' translations), tested; at most
/// 3.1 and 6.0 measured by bench/interpolation_accuracy on 16.8 million random pairs and t,
/// dq::sclerp<float> 3.2 and 6.4.
/// Precondition: unit inputs (to float rounding, as products of unit dual quaternions are); the
/// relative motion is rescaled to a unit real part, so slightly drifted inputs give a slightly
/// different but unit result; a zero real part is not a rigid transform and gives NaN.
/// `out` may be `a` or `b`.
void sclerp(ConstRows a, ConstRows b, float t, Rows out, std::size_t n);

// ---- layouts: arrays of structures in and out ------------------------------------------------------
// The kernels take component arrays. These move elements stored one after another (a
// std::vector<DualQuaternion<float>>, glm::dualquat or a NumPy (n, 8) float32 array read as such)
// into the component arrays and back: whole elements loaded per vector lane and transposed with
// shuffles, as the skinning kernels load the palette. n is the span's size; each component array
// must hold n floats from the given start; the arrays and the span must not overlap. Exact copies
// (every bit, NaNs included).

/// out.rw[i] = in[i].real.w, ..., out.dz[i] = in[i].dual.z for i < in.size().
void to_rows(std::span<const DualQuaternion<float>> in, Rows out);
/// out[i] = the dual quaternion of component i of the eight arrays, for i < out.size().
void from_rows(ConstRows in, std::span<DualQuaternion<float>> out);
/// Quaternions (w, x, y, z), as the slerp kernel takes them.
void to_rows(std::span<const Quaternion<float>> in, QuaternionRows<float> out);
void from_rows(QuaternionRows<const float> in, std::span<Quaternion<float>> out);
/// Points and directions (x, y, z), as transform_points and transform_directions take them.
void to_rows(std::span<const Vec3<float>> in, std::array<float*, 3> out);
void from_rows(std::array<const float*, 3> in, std::span<Vec3<float>> out);
/// Dual quaternions and points in double.
void to_rows(std::span<const DualQuaternion<double>> in, RowsD out);
void from_rows(ConstRowsD in, std::span<DualQuaternion<double>> out);
void to_rows(std::span<const Vec3<double>> in, std::array<double*, 3> out);
void from_rows(std::array<const double*, 3> in, std::span<Vec3<double>> out);

/// The batch forward kinematics job with the dispatched product. Precondition: job.validate().
void run(const ForwardKinematicsJob<float>& job);

/// Runs a job on oneTBB's persistent worker threads (no thread is started per call; in a build
/// without oneTBB, one thread per part, started for the call), split into pose ranges of about
/// `grain` poses or more (oneTBB splits a range only while it is longer than `grain`, as far as its
/// workers need; without oneTBB, one range per thread), each written by one task (no
/// synchronization needed).
/// `threads` limits the workers used (0: every hardware thread; 1: this thread, no task). Float
/// jobs use the vectorized product (run above). Returns the job's validation error instead of
/// running an invalid job.
template <class T>
Status run_parallel(const ForwardKinematicsJob<T>& job, unsigned threads = 0, std::size_t grain = 256);
extern template Status run_parallel(const ForwardKinematicsJob<float>&, unsigned, std::size_t);
extern template Status run_parallel(const ForwardKinematicsJob<double>&, unsigned, std::size_t);

}  // namespace dq::simd

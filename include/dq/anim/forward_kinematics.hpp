// Forward kinematics: local (parent-relative) transforms to model space,
// model[j] = model[parent(j)] · local[j], with dual quaternions and, as the seeds' baseline, with
// 4x4 matrices. Spans in, spans out, no allocation. The batch job runs many poses (characters or
// frames) stored structure-of-arrays, so the inner loop over poses is independent lane work.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <concepts>
#include <limits>
#include <ranges>
#include <span>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "dq/anim/skeleton.hpp"
#include "dq/core/matrix.hpp"
#include "dq/util/assert.hpp"
#include "dq/util/component_arrays.hpp"
#include "dq/util/expected.hpp"

namespace dq {

/// model[j] = model[parent(j)] · local[j] for the joints in [first, last). Joints before `first`
/// must already hold model transforms (partial update of a subtree: first = j,
/// last = skeleton.subtree_end(j)). Preconditions: `local` and `model` have one entry per joint,
/// each parent comes before its child, and `model` is either `local` itself (in place) or does
/// not overlap it.
template <class X>
void local_to_model(std::span<const int> parents, std::span<const X> local, std::span<X> model, std::size_t first = 0,
                    std::size_t last = static_cast<std::size_t>(-1)) {
  DQ_PRECONDITION(local.size() == parents.size() && model.size() == parents.size(),
                  "local_to_model needs one local and one model transform per joint");
  DQ_PRECONDITION(local.data() == model.data() || !overlaps(local, model),
                  "local_to_model: model must be local itself or not overlap it");
  last = std::min(last, parents.size());
  for (std::size_t j = first; j < last; ++j) {
    const int p = parents[j];
    DQ_PRECONDITION(p < static_cast<int>(j), "local_to_model: a parent must come before its child");
    model[j] = p < 0 ? local[j] : model[static_cast<std::size_t>(p)] * local[j];
  }
}
template <class X>
void local_to_model(const Skeleton& skeleton, std::span<const X> local, std::span<X> model) {
  local_to_model<X>(skeleton.parents(), local, model);
}
/// local_to_model over any contiguous containers of one transform type (std::vector, std::array):
/// the type deduced, not named.
template <std::ranges::contiguous_range Local, std::ranges::contiguous_range Model>
  requires std::same_as<std::remove_cv_t<std::ranges::range_value_t<Local>>, std::ranges::range_value_t<Model>> &&
           (!std::is_const_v<std::remove_reference_t<std::ranges::range_reference_t<Model>>>)
void local_to_model(const Skeleton& skeleton, const Local& local, Model&& model) {
  using X = std::ranges::range_value_t<Model>;
  local_to_model<X>(skeleton.parents(), std::span<const X>(std::ranges::data(local), std::ranges::size(local)),
                    std::span<X>(std::ranges::data(model), std::ranges::size(model)));
}
/// Recomputes only the subtree of joint j (after its local transform, or its parent's model
/// transform, changed).
template <class X>
void update_subtree(const Skeleton& skeleton, std::size_t j, std::span<const X> local, std::span<X> model) {
  local_to_model<X>(skeleton.parents(), local, model, j, skeleton.subtree_end(j));
}

/// Dual quaternions of many poses in structure-of-arrays layout: component c of joint j in pose p
/// is at `c[j * stride + p]` (poses contiguous per joint). The caller owns the storage.
/// `DualQuaternionSoA<const T>` is a read-only view (the inputs of jobs); a mutable view converts
/// to it.
template <class T>
struct DualQuaternionSoA {
  using value_type = std::remove_const_t<T>;
  std::span<T> rw, rx, ry, rz, dw, dx, dy, dz;
  std::size_t stride = 0;  ///< poses per joint row (≥ the number of poses)

  DualQuaternion<value_type> get(std::size_t joint, std::size_t pose) const {
    const std::size_t i = joint * stride + pose;
    return {rw[i], rx[i], ry[i], rz[i], dw[i], dx[i], dy[i], dz[i]};
  }
  void set(std::size_t joint, std::size_t pose, const DualQuaternion<value_type>& q) const
    requires(!std::is_const_v<T>)
  {
    const std::size_t i = joint * stride + pose;
    rw[i] = q.real.w, rx[i] = q.real.x, ry[i] = q.real.y, rz[i] = q.real.z;
    dw[i] = q.dual.w, dx[i] = q.dual.x, dy[i] = q.dual.y, dz[i] = q.dual.z;
  }
  std::size_t size() const { return rw.size(); }
  std::array<std::span<T>, 8> components() const { return {rw, rx, ry, rz, dw, dx, dy, dz}; }

  operator DualQuaternionSoA<const T>() const  // NOLINT: implicit, like span<T> to span<const T>
    requires(!std::is_const_v<T>)
  {
    return {rw, rx, ry, rz, dw, dx, dy, dz, stride};
  }
};

/// Owning storage for DualQuaternionSoA (allocates once, at construction, zeroed), laid out for
/// SIMD: the stride (poses per joint row) is rounded up to whole 64-byte cache lines, and the eight
/// component arrays are ComponentArrays (aligned, skewed so that the 24 streams of a product do not
/// evict each other). Throws std::length_error when joints × stride values cannot be addressed.
template <class T>
class DualQuaternionSoAStorage {
 public:
  static constexpr std::size_t alignment = ComponentArrays<T, 8>::alignment;
  static constexpr std::size_t line = ComponentArrays<T, 8>::line;  ///< elements per cache line

  DualQuaternionSoAStorage(std::size_t joints, std::size_t poses) : stride_(round_up(poses)), arrays_(values(joints, stride_)) {}

  DualQuaternionSoA<T> view() {
    return {arrays_[0], arrays_[1], arrays_[2], arrays_[3], arrays_[4], arrays_[5], arrays_[6], arrays_[7], stride_};
  }
  std::size_t stride() const noexcept { return stride_; }

 private:
  static std::size_t round_up(std::size_t n) {
    if (n > std::numeric_limits<std::size_t>::max() - line) throw std::length_error("dq::DualQuaternionSoAStorage: too many poses");
    return (n + line - 1) / line * line;
  }
  static std::size_t values(std::size_t joints, std::size_t stride) {
    if (stride != 0 && joints > std::numeric_limits<std::size_t>::max() / stride)
      throw std::length_error("dq::DualQuaternionSoAStorage: too many joints × poses");
    return joints * stride;
  }

  std::size_t stride_;
  ComponentArrays<T, 8> arrays_;
};

namespace detail {
/// The batch jobs' first check: every joint's parent comes before it (roots: negative).
inline Status parents_in_order(std::span<const int> parents) {
  for (std::size_t j = 0; j < parents.size(); ++j)
    if (parents[j] >= static_cast<int>(j)) return Error{"joint " + std::to_string(j) + ": parent does not come before it"};
  return {};
}
/// Eight component pointers of a row of dual quaternions.
template <class T>
struct Row8 {
  T *rw, *rx, *ry, *rz, *dw, *dx, *dy, *dz;
  /// Writable rows read as well.
  operator Row8<const T>() const noexcept
    requires(!std::is_const_v<T>)
  {
    return {rw, rx, ry, rz, dw, dx, dy, dz};
  }
};
/// The row at `offset` of eight component arrays (X const for reading).
template <class X, class Components>
Row8<X> row_of(Components& c, std::size_t offset) {
  return {c[0].data() + offset, c[1].data() + offset, c[2].data() + offset, c[3].data() + offset,
          c[4].data() + offset, c[5].data() + offset, c[6].data() + offset, c[7].data() + offset};
}
/// The product of the batch jobs and kernels: detail::dual_product over detail::hamilton, for any
/// scalar (float, double, or the kernels' lanes), written once. The scalar types' float operator*
/// (four-lane) may differ from it in the sign of an exact zero (docs/design.md).
template <class T>
[[gnu::always_inline]] constexpr DualQuaternion<T> batch_product(const DualQuaternion<T>& a, const DualQuaternion<T>& b) noexcept {
  return dual_product(a, b, [](const Quaternion<T>& l, const Quaternion<T>& r) { return hamilton(l, r); });
}
/// out[i] = a[i] · b[i] (batch_product) for i in [first, last), component arrays; the rows never
/// overlap (a parent row is a different joint), which the restrict-qualified copies tell the
/// compiler, so that it vectorizes across poses.
template <class T>
void dual_quaternion_product_rows(Row8<const T> a, Row8<const T> b, Row8<T> out, std::size_t first, std::size_t last) {
  const T* __restrict aw = a.rw; const T* __restrict ax = a.rx; const T* __restrict ay = a.ry; const T* __restrict az = a.rz;
  const T* __restrict cw = a.dw; const T* __restrict cx = a.dx; const T* __restrict cy = a.dy; const T* __restrict cz = a.dz;
  const T* __restrict bw = b.rw; const T* __restrict bx = b.rx; const T* __restrict by = b.ry; const T* __restrict bz = b.rz;
  const T* __restrict ew = b.dw; const T* __restrict ex = b.dx; const T* __restrict ey = b.dy; const T* __restrict ez = b.dz;
  T* __restrict ow = out.rw; T* __restrict ox = out.rx; T* __restrict oy = out.ry; T* __restrict oz = out.rz;
  T* __restrict pw = out.dw; T* __restrict px = out.dx; T* __restrict py = out.dy; T* __restrict pz = out.dz;
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC ivdep  // GCC 12 does not vectorize this loop from the restrict copies alone
#endif
  for (std::size_t i = first; i < last; ++i) {
    const DualQuaternion<T> p = batch_product(DualQuaternion<T>{aw[i], ax[i], ay[i], az[i], cw[i], cx[i], cy[i], cz[i]},
                                              DualQuaternion<T>{bw[i], bx[i], by[i], bz[i], ew[i], ex[i], ey[i], ez[i]});
    ow[i] = p.real.w, ox[i] = p.real.x, oy[i] = p.real.y, oz[i] = p.real.z;
    pw[i] = p.dual.w, px[i] = p.dual.x, py[i] = p.dual.y, pz[i] = p.dual.z;
  }
}
}  // namespace detail

/// Batch forward kinematics over poses [first_pose, first_pose + pose_count): a job struct in
/// the style of ozz-animation, with a validation that says what is wrong.
template <class T>
struct ForwardKinematicsJob {
  std::span<const int> parents;
  DualQuaternionSoA<const T> local;
  DualQuaternionSoA<T> model;
  std::size_t first_pose = 0;
  std::size_t pose_count = 0;

  Status validate() const {
    const std::size_t joints = parents.size();
    if (Status order = detail::parents_in_order(parents); !order) return order;
    if (local.stride != model.stride) return Error{"local and model strides differ"};
    if (first_pose > local.stride || pose_count > local.stride - first_pose) return Error{"pose range exceeds the stride"};
    if (joints != 0 && local.stride > std::numeric_limits<std::size_t>::max() / joints) return Error{"joints × stride overflows the address range"};
    for (auto span : local.components())
      if (span.size() < joints * local.stride) return Error{"a component array is shorter than joints × stride"};
    for (auto span : model.components())
      if (span.size() < joints * model.stride) return Error{"a component array is shorter than joints × stride"};
    for (auto out : model.components()) {
      for (auto in : local.components())
        if (overlaps(in, out)) return Error{"a model component array overlaps a local one"};
      for (auto other : model.components())
        if (other.data() != out.data() && overlaps(other, out)) return Error{"two model component arrays overlap"};
    }
    return {};
  }

  /// Runs on the calling thread. Precondition: validate() succeeds (checked; a job that does not
  /// validate is reported to the precondition handler and does nothing). (Processing the poses in
  /// cache-sized blocks was measured and did not help here.) dq::simd::run (dq/simd/batch.hpp)
  /// runs the same job with the product vectorized for the CPU's widest instruction set.
  void run() const {
    DQ_PRECONDITION(validate().ok(), "ForwardKinematicsJob::run on a job that does not validate");
    run_rows(&detail::dual_quaternion_product_rows<T>);
  }

  /// The job's loop over joints with another implementation of the row product
  /// `product(parent_row, local_row, model_row, first_pose, last_pose)`. Call validate() first.
  template <class RowProduct>
  void run_rows(RowProduct product) const {
    const std::size_t s = local.stride, b = first_pose, e = first_pose + pose_count;
    const auto in = local.components();
    const auto out = model.components();
    for (std::size_t j = 0; j < parents.size(); ++j) {
      const std::size_t row = j * s;
      const int p = parents[j];
      if (p < 0) {
        for (std::size_t c = 0; c < 8; ++c) std::copy(in[c].data() + row + b, in[c].data() + row + e, out[c].data() + row + b);
        continue;
      }
      const std::size_t prow = static_cast<std::size_t>(p) * s;
      product(detail::row_of<const T>(out, prow), detail::row_of<const T>(in, row), detail::row_of<T>(out, row), b, e);
    }
  }
};

}  // namespace dq

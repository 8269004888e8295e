// Forward kinematics: local (parent-relative) transforms to model space,
// model[j] = model[parent(j)] · local[j], with dual quaternions and, as the seeds' baseline, with
// 4x4 matrices. Spans in, spans out, no allocation. The batch job runs many poses (characters or
// frames) stored structure-of-arrays, so the inner loop over poses is independent lane work.
#pragma once

#include <algorithm>
#include <cstddef>
#include <span>
#include <string>
#include <thread>
#include <vector>

#include "dq/anim/skeleton.hpp"
#include "dq/core/matrix.hpp"
#include "dq/util/expected.hpp"

namespace dq {

/// model[j] = model[parent(j)] · local[j] for the joints in [first, last). Joints before `first`
/// must already hold model transforms (partial update of a subtree: first = j,
/// last = skeleton.subtree_end(j)). `local` and `model` have one entry per joint.
template <class X>
void local_to_model(std::span<const int> parents, std::span<const X> local, std::span<X> model, std::size_t first = 0,
                    std::size_t last = static_cast<std::size_t>(-1)) {
  last = std::min(last, parents.size());
  for (std::size_t j = first; j < last; ++j) {
    const int p = parents[j];
    model[j] = p < 0 ? local[j] : model[static_cast<std::size_t>(p)] * local[j];
  }
}
template <class X>
void local_to_model(const Skeleton& skeleton, std::span<const X> local, std::span<X> model) {
  local_to_model<X>(skeleton.parents(), local, model);
}
/// Recomputes only the subtree of joint j (after its local transform, or its parent's model
/// transform, changed).
template <class X>
void update_subtree(const Skeleton& skeleton, std::size_t j, std::span<const X> local, std::span<X> model) {
  local_to_model<X>(skeleton.parents(), local, model, j, skeleton.subtree_end(j));
}

/// Dual quaternions of many poses in structure-of-arrays layout: component c of joint j in pose p
/// is at `c[j * stride + p]` (poses contiguous per joint). The caller owns the storage.
template <class T>
struct DualQuaternionSoA {
  std::span<T> rw, rx, ry, rz, dw, dx, dy, dz;
  std::size_t stride = 0;  ///< poses per joint row (≥ the number of poses)

  DualQuaternion<T> get(std::size_t joint, std::size_t pose) const {
    const std::size_t i = joint * stride + pose;
    return {rw[i], rx[i], ry[i], rz[i], dw[i], dx[i], dy[i], dz[i]};
  }
  void set(std::size_t joint, std::size_t pose, const DualQuaternion<T>& q) const {
    const std::size_t i = joint * stride + pose;
    rw[i] = q.real.w, rx[i] = q.real.x, ry[i] = q.real.y, rz[i] = q.real.z;
    dw[i] = q.dual.w, dx[i] = q.dual.x, dy[i] = q.dual.y, dz[i] = q.dual.z;
  }
  std::size_t size() const { return rw.size(); }
};

/// Owning storage for DualQuaternionSoA (allocates once, at construction).
template <class T>
class DualQuaternionSoAStorage {
 public:
  DualQuaternionSoAStorage(std::size_t joints, std::size_t poses) : stride_(poses), data_(8 * joints * poses) {}
  DualQuaternionSoA<T> view() {
    const std::size_t n = data_.size() / 8;
    std::span<T> all(data_);
    return {all.subspan(0, n),     all.subspan(n, n),     all.subspan(2 * n, n), all.subspan(3 * n, n),
            all.subspan(4 * n, n), all.subspan(5 * n, n), all.subspan(6 * n, n), all.subspan(7 * n, n), stride_};
  }

 private:
  std::size_t stride_;
  std::vector<T> data_;
};

namespace detail {
/// Eight component pointers of a row of dual quaternions.
template <class T>
struct Row8 {
  T *rw, *rx, *ry, *rz, *dw, *dx, *dy, *dz;
};
/// out[i] = a[i] · b[i] for i in [first, last), component arrays; the rows never overlap (a parent
/// row is a different joint), which the restrict-qualified copies tell the compiler, so that it
/// vectorizes across poses.
template <class T>
void dual_quaternion_product_rows(Row8<T> a, Row8<T> b, Row8<T> out, std::size_t first, std::size_t last) {
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
    // real = a_r b_r; dual = a_r b_d + a_d b_r
    ow[i] = aw[i] * bw[i] - ax[i] * bx[i] - ay[i] * by[i] - az[i] * bz[i];
    ox[i] = aw[i] * bx[i] + ax[i] * bw[i] + ay[i] * bz[i] - az[i] * by[i];
    oy[i] = aw[i] * by[i] - ax[i] * bz[i] + ay[i] * bw[i] + az[i] * bx[i];
    oz[i] = aw[i] * bz[i] + ax[i] * by[i] - ay[i] * bx[i] + az[i] * bw[i];
    pw[i] = (aw[i] * ew[i] - ax[i] * ex[i] - ay[i] * ey[i] - az[i] * ez[i]) + (cw[i] * bw[i] - cx[i] * bx[i] - cy[i] * by[i] - cz[i] * bz[i]);
    px[i] = (aw[i] * ex[i] + ax[i] * ew[i] + ay[i] * ez[i] - az[i] * ey[i]) + (cw[i] * bx[i] + cx[i] * bw[i] + cy[i] * bz[i] - cz[i] * by[i]);
    py[i] = (aw[i] * ey[i] - ax[i] * ez[i] + ay[i] * ew[i] + az[i] * ex[i]) + (cw[i] * by[i] - cx[i] * bz[i] + cy[i] * bw[i] + cz[i] * bx[i]);
    pz[i] = (aw[i] * ez[i] + ax[i] * ey[i] - ay[i] * ex[i] + az[i] * ew[i]) + (cw[i] * bz[i] + cx[i] * by[i] - cy[i] * bx[i] + cz[i] * bw[i]);
  }
}
}  // namespace detail

/// Batch forward kinematics over poses [first_pose, first_pose + pose_count): a job struct in
/// the style of ozz-animation, with a validation that says what is wrong.
template <class T>
struct ForwardKinematicsJob {
  std::span<const int> parents;
  DualQuaternionSoA<T> local;
  DualQuaternionSoA<T> model;
  std::size_t first_pose = 0;
  std::size_t pose_count = 0;

  Status validate() const {
    const std::size_t joints = parents.size();
    for (std::size_t j = 0; j < joints; ++j)
      if (parents[j] >= static_cast<int>(j)) return Error{"joint " + std::to_string(j) + ": parent does not come before it"};
    if (local.stride != model.stride) return Error{"local and model strides differ"};
    if (first_pose + pose_count > local.stride) return Error{"pose range exceeds the stride"};
    for (const auto* s : {&local, &model})
      for (auto span : {s->rw, s->rx, s->ry, s->rz, s->dw, s->dx, s->dy, s->dz})
        if (span.size() < joints * s->stride) return Error{"a component array is shorter than joints × stride"};
    return {};
  }

  /// Runs on the calling thread. Call validate() first. (Processing the poses in cache-sized
  /// blocks was measured and did not help here.)
  void run() const { run_range(first_pose, first_pose + pose_count); }

 private:
  void run_range(std::size_t b, std::size_t e) const {
    const std::size_t s = local.stride;
    for (std::size_t j = 0; j < parents.size(); ++j) {
      const std::size_t row = j * s;
      const int p = parents[j];
      if (p < 0) {
        for (auto [src, dst] : component_pairs())
          std::copy(src.begin() + static_cast<std::ptrdiff_t>(row + b), src.begin() + static_cast<std::ptrdiff_t>(row + e),
                    dst.begin() + static_cast<std::ptrdiff_t>(row + b));
        continue;
      }
      const std::size_t prow = static_cast<std::size_t>(p) * s;
      auto at = [](std::span<T> c, std::size_t offset) { return c.data() + offset; };
      detail::dual_quaternion_product_rows<T>(
          {at(model.rw, prow), at(model.rx, prow), at(model.ry, prow), at(model.rz, prow), at(model.dw, prow), at(model.dx, prow),
           at(model.dy, prow), at(model.dz, prow)},
          {at(local.rw, row), at(local.rx, row), at(local.ry, row), at(local.rz, row), at(local.dw, row), at(local.dx, row),
           at(local.dy, row), at(local.dz, row)},
          {at(model.rw, row), at(model.rx, row), at(model.ry, row), at(model.rz, row), at(model.dw, row), at(model.dx, row),
           at(model.dy, row), at(model.dz, row)},
          b, e);
    }
  }

  std::array<std::pair<std::span<T>, std::span<T>>, 8> component_pairs() const {
    return {{{local.rw, model.rw}, {local.rx, model.rx}, {local.ry, model.ry}, {local.rz, model.rz},
             {local.dw, model.dw}, {local.dx, model.dx}, {local.dy, model.dy}, {local.dz, model.dz}}};
  }
};

/// Runs a validated job split across `threads` threads by pose ranges (each thread writes its own
/// poses only, so no synchronization is needed). threads = 0 uses the hardware concurrency.
template <class T>
Status run_parallel(const ForwardKinematicsJob<T>& job, unsigned threads = 0) {
  if (Status s = job.validate(); !s) return s;
  if (threads == 0) threads = std::max(1u, std::thread::hardware_concurrency());
  threads = static_cast<unsigned>(std::min<std::size_t>(threads, std::max<std::size_t>(1, job.pose_count)));
  if (threads <= 1) {
    job.run();
    return {};
  }
  std::vector<std::jthread> workers;
  workers.reserve(threads);
  const std::size_t chunk = (job.pose_count + threads - 1) / threads;
  for (unsigned t = 0; t < threads; ++t) {
    ForwardKinematicsJob<T> part = job;
    part.first_pose = job.first_pose + t * chunk;
    if (part.first_pose >= job.first_pose + job.pose_count) break;
    part.pose_count = std::min(chunk, job.first_pose + job.pose_count - part.first_pose);
    workers.emplace_back([part] { part.run(); });
  }
  return {};  // jthreads join here
}

}  // namespace dq

// Many poses in blocks of 16 (an array of structures of arrays, "AoSoA"), for forward kinematics
// at the memory limit. In the joint-major layout of DualQuaternionSoA, one joint row of a batch
// is 24 streams (eight components each of the local, parent and model rows); here the 16 poses of
// a block keep all their joints together, one joint after the other, so a block's forward
// kinematics reads the local transforms as one sequential stream, writes the model transforms as
// another, and finds each parent in the block it is writing (in L1 or L2 cache).
#pragma once

#include <algorithm>
#include <cstddef>
#include <limits>
#include <span>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>

#include "dq/anim/forward_kinematics.hpp"
#include "dq/util/component_arrays.hpp"
#include "dq/util/stores.hpp"

namespace dq {

/// Dual quaternions of many poses in blocks of `poses_per_block` = 16 poses. Component c (real w, x, y, z,
/// dual w, x, y, z) of joint j in pose p is at
///   data[((p / 16 · joints + j) · 8 + c) · 16 + p % 16],
/// so one joint of one block is 8 × 16 contiguous values (a 64-byte cache line per component in
/// float), and a block holds all the joints of its 16 poses. The caller owns the storage
/// (DualQuaternionBlockStorage below allocates it); `DualQuaternionBlocks<const T>` is a read-only
/// view, and a mutable view converts to it.
template <class T>
struct DualQuaternionBlocks {
  using value_type = std::remove_const_t<T>;
  static constexpr std::size_t poses_per_block = 16;
  static constexpr std::size_t joint_values = 8 * poses_per_block;  ///< values of one joint in one block

  std::span<T> data;
  std::size_t joints = 0;
  std::size_t blocks = 0;  ///< room for blocks × 16 poses

  std::size_t poses() const noexcept { return blocks * poses_per_block; }
  /// The 8 × 16 values of `joint` in `block`: component c of the block's pose l at [c · 16 + l].
  T* joint_block(std::size_t block, std::size_t joint) const noexcept { return data.data() + (block * joints + joint) * joint_values; }
  /// The same values as eight component rows of 16 poses (the rows the batch products take).
  detail::Row8<T> joint_rows(std::size_t block, std::size_t joint) const noexcept {
    T* v = joint_block(block, joint);
    constexpr std::size_t L = poses_per_block;
    return {v, v + L, v + 2 * L, v + 3 * L, v + 4 * L, v + 5 * L, v + 6 * L, v + 7 * L};
  }

  DualQuaternion<value_type> get(std::size_t joint, std::size_t pose) const {
    DQ_PRECONDITION(joint < joints && pose < poses(), "DualQuaternionBlocks::get: joint or pose out of range",
                    detail::nan_dual_quaternion<value_type>());
    constexpr std::size_t L = poses_per_block;
    const T* v = joint_block(pose / L, joint) + pose % L;
    return {v[0], v[L], v[2 * L], v[3 * L], v[4 * L], v[5 * L], v[6 * L], v[7 * L]};
  }
  void set(std::size_t joint, std::size_t pose, const DualQuaternion<value_type>& q) const
    requires(!std::is_const_v<T>)
  {
    DQ_PRECONDITION(joint < joints && pose < poses(), "DualQuaternionBlocks::set: joint or pose out of range");
    constexpr std::size_t L = poses_per_block;
    T* v = joint_block(pose / L, joint) + pose % L;
    const value_type c[8] = {q.real.w, q.real.x, q.real.y, q.real.z, q.dual.w, q.dual.x, q.dual.y, q.dual.z};
    for (std::size_t k = 0; k < 8; ++k) v[k * L] = c[k];
  }

  operator DualQuaternionBlocks<const T>() const  // NOLINT: implicit, like span<T> to span<const T>
    requires(!std::is_const_v<T>)
  {
    return {data, joints, blocks};
  }
};

/// Owning storage for DualQuaternionBlocks: allocated once, at construction, aligned to 64 bytes
/// (every component row of a block is a whole cache line in float), zero-initialized, with room
/// for `poses` rounded up to whole blocks.
template <class T>
class DualQuaternionBlockStorage {
 public:
  static constexpr std::size_t alignment = ComponentArrays<T, 1>::alignment;

  DualQuaternionBlockStorage(std::size_t joints, std::size_t poses)
      : joints_(joints),
        blocks_(poses / DualQuaternionBlocks<T>::poses_per_block + (poses % DualQuaternionBlocks<T>::poses_per_block != 0)),
        data_(values(joints_, blocks_)) {}

  DualQuaternionBlocks<T> view() noexcept { return {data_[0], joints_, blocks_}; }
  DualQuaternionBlocks<const T> view() const noexcept { return {data_[0], joints_, blocks_}; }
  /// A moved-from storage holds nothing (its views are empty).
  DualQuaternionBlockStorage(DualQuaternionBlockStorage&& o) noexcept
      : joints_(std::exchange(o.joints_, 0)), blocks_(std::exchange(o.blocks_, 0)), data_(std::move(o.data_)) {}
  DualQuaternionBlockStorage& operator=(DualQuaternionBlockStorage&& o) noexcept {
    joints_ = std::exchange(o.joints_, 0), blocks_ = std::exchange(o.blocks_, 0);
    data_ = std::move(o.data_);
    return *this;
  }

 private:
  static std::size_t values(std::size_t joints, std::size_t blocks) {
    constexpr std::size_t per_joint_block = DualQuaternionBlocks<T>::joint_values;
    if (blocks != 0 && joints > std::numeric_limits<std::size_t>::max() / per_joint_block / blocks)
      throw std::length_error("dq::DualQuaternionBlockStorage: too many joints × poses");
    return joints * blocks * per_joint_block;
  }

  std::size_t joints_, blocks_;
  ComponentArrays<T, 1> data_;  // one array, 64-byte aligned, zeroed
};

/// Forward kinematics of the poses in blocks [first_block, first_block + block_count), in the
/// style of ForwardKinematicsJob: model[j] = model[parent(j)] · local[j] for every pose, block by
/// block, with the same product as the joint-major job (bit for bit) and the scalar types (whose
/// float operator* may differ in the sign of an exact zero, docs/design.md).
/// dq::simd::run (dq/simd/pose_blocks.hpp) runs it with the product vectorized for the CPU.
template <class T>
struct BlockedForwardKinematicsJob {
  std::span<const int> parents;
  DualQuaternionBlocks<const T> local;
  DualQuaternionBlocks<T> model;
  std::size_t first_block = 0;
  std::size_t block_count = 0;
  /// How dq::simd::run's float kernels write the model transforms (dq/util/stores.hpp): with
  /// Stores::streaming, 100,000 poses of 64 joints ran 1.12–1.26× faster on one thread
  /// (docs/performance.md). Streaming is honoured by the AVX2 and AVX-512 kernels for up to 128
  /// joints and model storage aligned to 64 bytes (DualQuaternionBlockStorage's is), and then needs
  /// 64 KB of stack; otherwise (the SSE2 and SSE4.2 kernels, which it slowed down, run(), double, a build
  /// without the vector kernels) the stores are cached.
  Stores stores = Stores::cached;

  Status validate() const {
    const std::size_t joints = parents.size();
    if (Status order = detail::parents_in_order(parents); !order) return order;
    if (local.joints != joints || model.joints != joints) return Error{"the local and model blocks must have one joint per parent entry"};
    if (local.blocks != model.blocks) return Error{"local and model hold different numbers of blocks"};
    if (first_block > local.blocks || block_count > local.blocks - first_block) return Error{"block range exceeds the blocks held"};
    if (joints != 0 && local.blocks > std::numeric_limits<std::size_t>::max() / DualQuaternionBlocks<T>::joint_values / joints)
      return Error{"blocks × joints × 128 values overflow the address range"};
    const std::size_t needed = local.blocks * joints * DualQuaternionBlocks<T>::joint_values;
    if (local.data.size() < needed || model.data.size() < needed) return Error{"a block array is shorter than blocks × joints × 128"};
    if (overlaps(local.data, model.data)) return Error{"the model blocks overlap the local ones"};
    return {};
  }

  /// Runs on the calling thread. Precondition: validate() succeeds (checked; a job that does not
  /// validate is reported to the precondition handler and does nothing).
  void run() const {
    DQ_PRECONDITION(validate().ok(), "BlockedForwardKinematicsJob::run on a job that does not validate");
    run_blocks([](detail::Row8<const T> parent, detail::Row8<const T> in, detail::Row8<T> out) {
      detail::dual_quaternion_product_rows<T>(parent, in, out, 0, DualQuaternionBlocks<T>::poses_per_block);
    });
  }

  /// The job's loops with another implementation of the product of one joint of one block:
  /// `product(parent, local, model)`, each the eight component rows of 16 poses (joint_rows).
  /// Roots are copied. Call validate() first.
  template <class BlockProduct>
  void run_blocks(BlockProduct product) const {
    for (std::size_t b = first_block; b < first_block + block_count; ++b)
      for (std::size_t j = 0; j < parents.size(); ++j) {
        const int p = parents[j];
        if (p < 0) {
          const T* in = local.joint_block(b, j);
          std::copy(in, in + DualQuaternionBlocks<T>::joint_values, model.joint_block(b, j));
        } else {
          const DualQuaternionBlocks<const T> written = model;
          product(written.joint_rows(b, static_cast<std::size_t>(p)), local.joint_rows(b, j), model.joint_rows(b, j));
        }
      }
  }
};

}  // namespace dq

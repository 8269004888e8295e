// The blocked forward kinematics kernel once per instruction set, chosen at run time as in
// src/simd/batch.cpp: one joint of one block is 16 poses, so one AVX-512 vector, two AVX2 or four
// SSE2 vectors per component, and the formula is detail::dual_product with detail::hamilton
// instantiated on lanes (bit for bit the scalar product).
#include "dq/simd/pose_blocks.hpp"

#include <cstdint>
#include <string>
#include <type_traits>

#include "dq/util/assert.hpp"
#include "frames.hpp"
#include "lanes.hpp"
#include "records.hpp"

namespace dq::simd {

namespace {

#if DQKIT_VECTOR_EXTENSIONS && defined(__x86_64__)
using kernels::load8;
using kernels::load_records;
using kernels::product;
using kernels::store8;
using kernels::store_records;
using kernels::store_streaming;
using kernels::stream_fence;

constexpr std::size_t kLanes = DualQuaternionBlocks<float>::poses_per_block;

/// How far ahead of the joint block being computed the local and model streams are prefetched:
/// four joint blocks (2 KB). With the hardware prefetcher alone, one thread reached 0.79 of the
/// copy bandwidth at 100,000 skeletons; with this, 0.82 to 1.01 in eight runs (docs/performance.md).
constexpr std::uintptr_t kPrefetchAhead = 4 * DualQuaternionBlocks<float>::joint_values * sizeof(float);

/// Prefetches the 8 cache lines of the joint block `kPrefetchAhead` bytes after the one whose first
/// row is at `p`. The address is computed as an integer: past the end of the array it is never a
/// pointer, and a prefetch of it does not fault.
template <int Write>
[[gnu::always_inline]] inline void prefetch_ahead(const float* p) {
  const std::uintptr_t at = reinterpret_cast<std::uintptr_t>(p) + kPrefetchAhead;
  for (std::uintptr_t line = 0; line < 8; ++line) __builtin_prefetch(reinterpret_cast<const void*>(at + 64 * line), Write, 0);
}

/// model = parent · local for the 16 poses of one joint block, N lanes at a time.
template <int N>
[[gnu::always_inline]] inline void block_product(ConstRows parent, ConstRows local, Rows model) {
  prefetch_ahead<0>(local.rw);
  prefetch_ahead<1>(model.rw);
  for (std::size_t k = 0; k < kLanes; k += N) store8<N>(model, k, product(load8<N>(parent, k), load8<N>(local, k)));
}

/// The joints a streaming job may have: one block's model transforms, kept for the children, fill
/// 64 KB of the stack.
constexpr std::size_t kStreamingJoints = 128;

/// The job with Stores::streaming: each joint block's model transforms go to a copy of the block
/// on the stack (in L1 or L2 cache, where the children find their parent), and from there, as
/// eight whole cache lines in order, to the model storage with non-temporal stores, which skip
/// reading the lines they overwrite and leave the cache to the data still to be read. The fence
/// makes those stores visible to other threads before the job returns, as ordinary stores are.
template <int N>
[[gnu::always_inline]] inline void run_streaming(const BlockedForwardKinematicsJob<float>& job) {
  constexpr std::size_t values = DualQuaternionBlocks<float>::joint_values;
  alignas(64) float kept[kStreamingJoints * values];
  const DualQuaternionBlocks<float> block{kept, job.parents.size(), 1};
  const DualQuaternionBlocks<const float> written = block;
  for (std::size_t b = job.first_block; b < job.first_block + job.block_count; ++b)
    for (std::size_t j = 0; j < job.parents.size(); ++j) {
      const int p = job.parents[j];
      const ConstRows local = job.local.joint_rows(b, j);
      prefetch_ahead<0>(local.rw);
      for (std::size_t k = 0; k < kLanes; k += N)
        store8<N>(block.joint_rows(0, j), k,
                  p < 0 ? load8<N>(local, k) : product(load8<N>(written.joint_rows(0, static_cast<std::size_t>(p)), k), load8<N>(local, k)));
      const float* from = written.joint_block(0, j);
      float* to = job.model.joint_block(b, j);
      for (std::size_t i = 0; i < values; i += N) store_streaming(to + i, kernels::load<N>(from + i).v);
    }
  stream_fence();
}

/// Whether `job` runs with non-temporal stores: asked for, with few enough joints for the stack
/// copy and model storage aligned for the widest vector. (On AVX2 and AVX-512 only: the SSE2
/// kernel, compute-bound at 100,000 × 64, measured 1.24 × slower with them, AVX2 1.02 × faster
/// and AVX-512 1.16 × faster, in one run with the target forced.)
bool streams(const BlockedForwardKinematicsJob<float>& job) {
  return job.stores == Stores::streaming && job.parents.size() <= kStreamingJoints &&
         reinterpret_cast<std::uintptr_t>(job.model.data.data()) % 64 == 0;
}

/// The joints whose model transforms local_to_model_frames keeps transposed on the stack, for
/// their children (8 vectors a joint: 64 KB with AVX-512); beyond them, a parent's are loaded
/// back from `model` and transposed again.
constexpr std::size_t kFramesKeptJoints = 128;

/// Forward kinematics of N consecutive frames from `first` (local_to_model_frames), in float or
/// double (S): each joint's local transforms loaded per lane and transposed, the product with its
/// parent's model transforms on the lanes, the result transposed back and stored.
template <class S, int N>
[[gnu::always_inline]] inline void frames_product(std::span<const int> parents, const S* local, S* model, std::size_t first) {
  using V = kernels::vector_of<S, N>;
  const std::size_t joints = parents.size();
  const bool keep = joints <= kFramesKeptJoints;
  V kept[kFramesKeptJoints][8];
  auto at = [&](auto* base, std::size_t joint) __attribute__((always_inline)) {
    return [base, joint, joints, first](int lane) __attribute__((always_inline)) {
      return base + 8 * ((first + static_cast<std::size_t>(lane)) * joints + joint);
    };
  };
  for (std::size_t j = 0; j < joints; ++j) {
    V l[8], reloaded[8];
    V* out = keep ? kept[j] : reloaded;
    load_records<N, 8>(at(local, j), l);
    const int p = parents[j];
    if (p < 0) {
      for (int c = 0; c < 8; ++c) out[c] = l[c];
    } else {
      V m[8];
      const V* parent = m;
      if (keep)
        parent = kept[p];
      else
        load_records<N, 8>(at(model, static_cast<std::size_t>(p)), m);
      kernels::components_of(product(kernels::dual_quaternion_of<N, S>(parent), kernels::dual_quaternion_of<N, S>(l)), out);
    }
    store_records<N, 8>(out, at(model, j));
  }
}

#define DQKIT_TARGET_KERNEL(name, lanes, attribute)                                                       \
  [[gnu::target(attribute), gnu::flatten]] void run_##name(const BlockedForwardKinematicsJob<float>& job) { \
    job.run_blocks([](ConstRows parent, ConstRows local, Rows model) { block_product<lanes>(parent, local, model); }); \
  }
DQKIT_TARGET_KERNEL(sse2, 4, "sse2")
DQKIT_TARGET_KERNEL(sse42, 4, "sse4.2")
DQKIT_TARGET_KERNEL(avx2, 8, "avx2")
DQKIT_TARGET_KERNEL(avx512, 16, "avx512f")
#undef DQKIT_TARGET_KERNEL
// The frames' kernel per target, for float or double (S): whole vectors of frames (as many as the
// target's vector has lanes of S); returns the frames done.
#define DQKIT_FRAMES_KERNEL(name, float_lanes, attribute)                                                \
  template <class S>                                                                                     \
  [[gnu::target(attribute), gnu::flatten]] std::size_t frames_##name(std::span<const int> parents, const S* local, \
                                                                     S* model, std::size_t frames) {     \
    constexpr int lanes = float_lanes * static_cast<int>(sizeof(float)) / static_cast<int>(sizeof(S));  \
    std::size_t f = 0;                                                                                   \
    for (; f + lanes <= frames; f += lanes) frames_product<S, lanes>(parents, local, model, f);          \
    return f;                                                                                            \
  }
DQKIT_FRAMES_KERNEL(sse2, 4, "sse2")
DQKIT_FRAMES_KERNEL(sse42, 4, "sse4.2")
DQKIT_FRAMES_KERNEL(avx2, 8, "avx2")
DQKIT_FRAMES_KERNEL(avx512, 16, "avx512f")
#undef DQKIT_FRAMES_KERNEL
// The streaming kernels are functions of their own, so that their 64 KB stack copy is not part of
// the cached kernels' frames.
#define DQKIT_STREAMING_KERNEL(name, lanes, attribute)                                                    \
  [[gnu::target(attribute), gnu::flatten]] void stream_##name(const BlockedForwardKinematicsJob<float>& job) { \
    run_streaming<lanes>(job);                                                                            \
  }
DQKIT_STREAMING_KERNEL(avx2, 8, "avx2")
DQKIT_STREAMING_KERNEL(avx512, 16, "avx512f")
#undef DQKIT_STREAMING_KERNEL
#endif

}  // namespace

void run(const BlockedForwardKinematicsJob<float>& job) {
  DQ_PRECONDITION(job.validate().ok(), "simd::run on a blocked job that does not validate");
  switch (current_target()) {
#if DQKIT_VECTOR_EXTENSIONS && defined(__x86_64__)
    case Target::avx512: return streams(job) ? stream_avx512(job) : run_avx512(job);
    case Target::avx2: return streams(job) ? stream_avx2(job) : run_avx2(job);
    case Target::sse42: return run_sse42(job);
    case Target::sse2: return run_sse2(job);
#endif
    default: return job.run();
  }
}

template <class T>
Status check_frames(std::span<const int> parents, std::span<const DualQuaternion<T>> local,
                    std::span<const DualQuaternion<T>> model) {
  const std::size_t joints = parents.size();
  if (Status order = detail::parents_in_order(parents); !order) return order;
  if (local.size() != model.size() || (joints == 0 ? !local.empty() : local.size() % joints != 0))
    return Error{"local and model must hold the same whole number of frames of " + std::to_string(joints) + " joints"};
  if (overlaps(local, model)) return Error{"model must not overlap local"};
  return {};
}
template Status check_frames(std::span<const int>, std::span<const DualQuaternion<float>>, std::span<const DualQuaternion<float>>);
template Status check_frames(std::span<const int>, std::span<const DualQuaternion<double>>, std::span<const DualQuaternion<double>>);

namespace {
/// Frames [first, frames) on scalars, with the kernels' product (detail::batch_product, which for
/// double is DualQuaternion<double>'s), without GCC's vectorizers (DQKIT_NOT_VECTORIZED): the frames
/// left over keep the bits of the frames on the lanes in every build.
template <class T>
[[gnu::noinline, DQKIT_NOT_VECTORIZED]] void frames_on_scalars(std::span<const int> parents, const DualQuaternion<T>* in,
                                                       DualQuaternion<T>* out, std::size_t first, std::size_t frames) {
  const std::size_t joints = parents.size();
  for (std::size_t f = first; f < frames; ++f)
    for (std::size_t j = 0; j < joints; ++j) {
      const int p = parents[j];
      out[f * joints + j] = p < 0 ? in[f * joints + j] : detail::batch_product(out[f * joints + static_cast<std::size_t>(p)], in[f * joints + j]);
    }
}

/// compute_frames for float and double: whole vectors of frames on the target in use, the frames
/// left over on scalars.
template <class T>
void frames_on_target(std::span<const int> parents, std::span<const DualQuaternion<T>> local, std::span<DualQuaternion<T>> model) {
  if (local.empty()) return;
  const std::size_t joints = parents.size();
  const auto* in = local.data();
  auto* out = model.data();
  static_assert(sizeof(DualQuaternion<T>) == 8 * sizeof(T) && std::is_trivially_copyable_v<DualQuaternion<T>>);
  const std::size_t frames = local.size() / joints;
  [[maybe_unused]] const T* l = reinterpret_cast<const T*>(in);
  [[maybe_unused]] T* m = reinterpret_cast<T*>(out);
  std::size_t done = 0;
  switch (current_target()) {
#if DQKIT_VECTOR_EXTENSIONS && defined(__x86_64__)
    case Target::avx512: done = frames_avx512(parents, l, m, frames); break;
    case Target::avx2: done = frames_avx2(parents, l, m, frames); break;
    case Target::sse42: done = frames_sse42(parents, l, m, frames); break;
    case Target::sse2: done = frames_sse2(parents, l, m, frames); break;
#endif
    default: break;
  }
  frames_on_scalars(parents, in, out, done, frames);
}
}  // namespace

void compute_frames(std::span<const int> parents, std::span<const DualQuaternion<float>> local,
                    std::span<DualQuaternion<float>> model) {
  frames_on_target<float>(parents, local, model);
}
void compute_frames(std::span<const int> parents, std::span<const DualQuaternion<double>> local,
                    std::span<DualQuaternion<double>> model) {
  frames_on_target<double>(parents, local, model);
}

namespace {
template <class T>
Status checked_frames(std::span<const int> parents, std::span<const DualQuaternion<T>> local, std::span<DualQuaternion<T>> model) {
  if (Status s = check_frames<T>(parents, local, model); !s) return s;
  compute_frames(parents, local, model);
  return {};
}
}  // namespace

Status local_to_model_frames(std::span<const int> parents, std::span<const DualQuaternion<float>> local,
                             std::span<DualQuaternion<float>> model) {
  return checked_frames<float>(parents, local, model);
}
Status local_to_model_frames(std::span<const int> parents, std::span<const DualQuaternion<double>> local,
                             std::span<DualQuaternion<double>> model) {
  return checked_frames<double>(parents, local, model);
}

}  // namespace dq::simd

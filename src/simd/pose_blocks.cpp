// The blocked forward kinematics kernel once per instruction set, chosen at run time as in
// src/simd/batch.cpp: one joint of one block is 16 poses, so one AVX-512 vector, two AVX2 or four
// SSE2 vectors per component, and the formula is detail::dual_product with detail::hamilton
// instantiated on lanes (bit for bit the scalar product).
#include "dq/simd/pose_blocks.hpp"

#include <cstdint>

#include "lanes.hpp"

namespace dq::simd {

namespace {

#if DQKIT_VECTOR_EXTENSIONS && defined(__x86_64__)
using kernels::load8;
using kernels::product;
using kernels::store8;

constexpr std::size_t kLanes = DualQuaternionBlocks<float>::poses_per_block;

/// How far ahead of the joint block being computed the local and model streams are prefetched:
/// four joint blocks (2 KB). With the hardware prefetcher alone, one thread reached 0.79 of the
/// copy bandwidth at 100,000 skeletons; with this, 0.89 to 1.01 in four runs (docs/performance.md).
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

#define DQKIT_TARGET_KERNEL(name, lanes, attribute)                                                       \
  [[gnu::target(attribute), gnu::flatten]] void run_##name(const BlockedForwardKinematicsJob<float>& job) { \
    job.run_blocks([](ConstRows parent, ConstRows local, Rows model) { block_product<lanes>(parent, local, model); }); \
  }
DQKIT_TARGET_KERNEL(sse2, 4, "sse2")
DQKIT_TARGET_KERNEL(avx2, 8, "avx2")
DQKIT_TARGET_KERNEL(avx512, 16, "avx512f")
#undef DQKIT_TARGET_KERNEL
#endif

}  // namespace

void run(const BlockedForwardKinematicsJob<float>& job) {
  DQ_PRECONDITION(job.validate().ok(), "simd::run on a blocked job that does not validate");
  switch (current_target()) {
#if DQKIT_VECTOR_EXTENSIONS && defined(__x86_64__)
    case Target::avx512: return run_avx512(job);
    case Target::avx2: return run_avx2(job);
    case Target::sse2: return run_sse2(job);
#endif
    default: return job.run();
  }
}

}  // namespace dq::simd

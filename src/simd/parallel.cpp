#include <algorithm>
#include <thread>
#include <vector>

#include "dq/simd/batch.hpp"
#include "dq/simd/pose_blocks.hpp"
#include "frames.hpp"

#if defined(DQKIT_HAVE_TBB)
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#endif

namespace dq::simd {

namespace {

/// Calls part(begin, count) on ranges that split [first, first + count), on oneTBB's workers (at
/// most `threads` of them; 0: all; 1: the whole range on this thread), which split a range only
/// while it is longer than `grain`, and only as far as the workers need (oneTBB's automatic
/// partitioner): parts hold about grain/2 items or more.
template <class Part>
void split(std::size_t first, std::size_t count, unsigned threads, std::size_t grain, const Part& part) {
  grain = std::max<std::size_t>(1, grain);
  if (threads == 1) return part(first, count);  // on this thread: no task, no arena
#if defined(DQKIT_HAVE_TBB)
  auto body = [&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(first, first + count, grain),
                      [&](const tbb::blocked_range<std::size_t>& r) { part(r.begin(), r.size()); });
  };
  if (threads == 0 || threads >= std::thread::hardware_concurrency()) {
    body();
  } else {
    tbb::task_arena arena(static_cast<int>(threads));
    arena.execute(body);
  }
#else
  // Without oneTBB (or under ThreadSanitizer, which cannot see oneTBB's uninstrumented
  // synchronization): one thread per range, started for this call.
  if (threads == 0) threads = std::max(1u, std::thread::hardware_concurrency());
  const std::size_t parts = std::clamp<std::size_t>(count / grain, 1, threads);
  const std::size_t chunk = (count + parts - 1) / parts;
  std::vector<std::jthread> workers;
  for (std::size_t begin = first; begin < first + count; begin += chunk)
    workers.emplace_back([&part, begin, n = std::min(chunk, first + count - begin)] { part(begin, n); });
#endif
}

/// Float jobs run with the dispatched product, others with the job's own.
void run_part(const ForwardKinematicsJob<float>& part) { run(part); }
void run_part(const BlockedForwardKinematicsJob<float>& part) { run(part); }
template <class Job>
void run_part(const Job& part) {
  part.run();
}

/// Validates the job, then runs it in parts: copies of the job whose range (the members `first`
/// and `count`) covers one part of the job's range each.
template <class Job>
Status run_in_parts(const Job& job, std::size_t Job::*first, std::size_t Job::*count, unsigned threads, std::size_t grain) {
  if (Status s = job.validate(); !s) return s;
  split(job.*first, job.*count, threads, grain, [&](std::size_t part_first, std::size_t part_count) {
    Job part = job;
    part.*first = part_first, part.*count = part_count;
    run_part(part);
  });
  return {};
}

/// local_to_model_frames_parallel for float and double.
template <class T>
Status frames_in_parts(std::span<const int> parents, std::span<const DualQuaternion<T>> local, std::span<DualQuaternion<T>> model,
                       unsigned threads, std::size_t grain) {
  // Checked over the whole batch first, so that an error leaves all of model untouched.
  if (Status s = check_frames<T>(parents, local, model); !s) return s;
  if (local.empty()) return {};
  constexpr std::size_t kUnit = 16;  // frames: for float, a whole number of vectors on every target
  const std::size_t joints = parents.size(), frames = local.size() / joints;
  split(0, (frames + kUnit - 1) / kUnit, threads, grain / kUnit, [&](std::size_t first, std::size_t count) {
    const std::size_t begin = first * kUnit * joints, size = std::min(frames, (first + count) * kUnit) * joints - begin;
    compute_frames(parents, local.subspan(begin, size), model.subspan(begin, size));
  });
  return {};
}

}  // namespace

template <class T>
Status run_parallel(const ForwardKinematicsJob<T>& job, unsigned threads, std::size_t grain) {
  return run_in_parts(job, &ForwardKinematicsJob<T>::first_pose, &ForwardKinematicsJob<T>::pose_count, threads, grain);
}
template <class T>
Status run_parallel(const BlockedForwardKinematicsJob<T>& job, unsigned threads, std::size_t grain) {
  return run_in_parts(job, &BlockedForwardKinematicsJob<T>::first_block, &BlockedForwardKinematicsJob<T>::block_count, threads, grain);
}

Status local_to_model_frames_parallel(std::span<const int> parents, std::span<const DualQuaternion<float>> local,
                                      std::span<DualQuaternion<float>> model, unsigned threads, std::size_t grain) {
  return frames_in_parts<float>(parents, local, model, threads, grain);
}
Status local_to_model_frames_parallel(std::span<const int> parents, std::span<const DualQuaternion<double>> local,
                                      std::span<DualQuaternion<double>> model, unsigned threads, std::size_t grain) {
  return frames_in_parts<double>(parents, local, model, threads, grain);
}

template Status run_parallel(const ForwardKinematicsJob<float>&, unsigned, std::size_t);
template Status run_parallel(const ForwardKinematicsJob<double>&, unsigned, std::size_t);
template Status run_parallel(const BlockedForwardKinematicsJob<float>&, unsigned, std::size_t);
template Status run_parallel(const BlockedForwardKinematicsJob<double>&, unsigned, std::size_t);

}  // namespace dq::simd

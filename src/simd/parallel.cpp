#include <algorithm>
#include <thread>
#include <vector>

#include "dq/simd/batch.hpp"

#if defined(DQKIT_HAVE_TBB)
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#endif

namespace dq::simd {

namespace {
template <class T>
void run_part(const ForwardKinematicsJob<T>& part) {
  if constexpr (std::is_same_v<T, float>)
    run(part);
  else
    part.run();
}
}  // namespace

template <class T>
Status run_parallel(const ForwardKinematicsJob<T>& job, unsigned threads, std::size_t grain) {
  if (Status s = job.validate(); !s) return s;
#if defined(DQKIT_HAVE_TBB)
  auto body = [&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(job.first_pose, job.first_pose + job.pose_count, std::max<std::size_t>(1, grain)),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        ForwardKinematicsJob<T> part = job;
                        part.first_pose = r.begin();
                        part.pose_count = r.size();
                        run_part(part);
                      });
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
  const std::size_t parts = std::clamp<std::size_t>(job.pose_count / std::max<std::size_t>(1, grain), 1, threads);
  const std::size_t chunk = (job.pose_count + parts - 1) / parts;
  std::vector<std::jthread> workers;
  for (std::size_t k = 0; k < parts; ++k) {
    ForwardKinematicsJob<T> part = job;
    part.first_pose = job.first_pose + k * chunk;
    if (part.first_pose >= job.first_pose + job.pose_count) break;
    part.pose_count = std::min(chunk, job.first_pose + job.pose_count - part.first_pose);
    workers.emplace_back([part] { run_part(part); });
  }
#endif
  return {};
}

template Status run_parallel(const ForwardKinematicsJob<float>&, unsigned, std::size_t);
template Status run_parallel(const ForwardKinematicsJob<double>&, unsigned, std::size_t);

}  // namespace dq::simd

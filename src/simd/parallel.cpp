#include <algorithm>

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
  if (threads == 0) {
    body();
  } else {
    tbb::task_arena arena(static_cast<int>(threads));
    arena.execute(body);
  }
#else
  (void)threads, (void)grain;
  run_part(job);  // built without oneTBB: on the calling thread
#endif
  return {};
}

template Status run_parallel(const ForwardKinematicsJob<float>&, unsigned, std::size_t);
template Status run_parallel(const ForwardKinematicsJob<double>&, unsigned, std::size_t);

}  // namespace dq::simd

// Batch forward kinematics, joints per second: dqkit's structure-of-arrays job (one and two
// threads) against the same work done pose by pose with dqkit dual quaternions, Eigen Isometry3f
// and GLM mat4, on 1024 frames of the CMU capture 01_01.bvh (38 joints), in float.
//   build/release/bench/bench_fk --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>

#include <Eigen/Geometry>
#include <cstdlib>
#include <glm/gtc/quaternion.hpp>
#include <glm/mat4x4.hpp>

#include "dq/anim/forward_kinematics.hpp"
#include "dq/simd/batch.hpp"
#include "dq/interop/eigen.hpp"
#include "dq/interop/glm.hpp"
#include "dq/io/bvh.hpp"

namespace {

struct Data {
  dq::Skeleton skeleton;
  std::size_t poses = 1024;
  std::vector<dq::DualQuaternion<float>> local;  // pose-major: [pose * joints + joint]
};

const Data& data() {
  static const Data d = [] {
    Data out;
    const auto bvh = dq::read_bvh_file(std::string(DQKIT_ASSIMP_MODELS) + "/BVH/01_01.bvh");
    if (!bvh) {
      std::fprintf(stderr, "%s\n", bvh.error().message.c_str());
      std::exit(1);
    }
    out.skeleton = *dq::bvh_skeleton(*bvh);
    const dq::Animation anim = dq::bvh_animation(*bvh, out.skeleton);
    for (std::size_t p = 0; p < out.poses; ++p)
      for (const auto& q : anim.frame(p % anim.frame_count))
        out.local.push_back(q.cast<float>());
    return out;
  }();
  return d;
}

void report(benchmark::State& state) {
  const Data& d = data();
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * d.poses * d.skeleton.size()));
}

void SoAJob(benchmark::State& state) {
  const Data& d = data();
  const std::size_t joints = d.skeleton.size();
  dq::DualQuaternionSoAStorage<float> local_store(joints, d.poses), model_store(joints, d.poses);
  auto local = local_store.view(), model = model_store.view();
  for (std::size_t p = 0; p < d.poses; ++p)
    for (std::size_t j = 0; j < joints; ++j) local.set(j, p, d.local[p * joints + j]);
  dq::ForwardKinematicsJob<float> job{d.skeleton.parents(), local, model, 0, d.poses};
  const unsigned threads = static_cast<unsigned>(state.range(0));
  for (auto _ : state) {
    if (threads == 1) {
      job.run();
    } else {
      (void)dq::simd::run_parallel(job, threads);
    }
    benchmark::DoNotOptimize(model.rw.data());
    benchmark::ClobberMemory();
  }
  report(state);
}

void DualQuaternionPerPose(benchmark::State& state) {
  const Data& d = data();
  const std::size_t joints = d.skeleton.size();
  std::vector<dq::DualQuaternion<float>> model(d.local.size());
  for (auto _ : state) {
    for (std::size_t p = 0; p < d.poses; ++p)
      dq::local_to_model<dq::DualQuaternion<float>>(d.skeleton.parents(), std::span(d.local).subspan(p * joints, joints),
                                                    std::span(model).subspan(p * joints, joints));
    benchmark::DoNotOptimize(model.data());
    benchmark::ClobberMemory();
  }
  report(state);
}

template <class M, class Make>
void MatrixPerPose(benchmark::State& state, Make make) {
  const Data& d = data();
  const std::size_t joints = d.skeleton.size();
  std::vector<M> local, model(d.local.size());
  for (const auto& q : d.local) local.push_back(make(q));
  const auto parents = d.skeleton.parents();
  for (auto _ : state) {
    for (std::size_t p = 0; p < d.poses; ++p) {
      const M* l = local.data() + p * joints;
      M* m = model.data() + p * joints;
      for (std::size_t j = 0; j < joints; ++j) m[j] = parents[j] < 0 ? l[j] : m[parents[j]] * l[j];
    }
    benchmark::DoNotOptimize(model.data());
    benchmark::ClobberMemory();
  }
  report(state);
}
void EigenIsometry3f(benchmark::State& s) {
  MatrixPerPose<Eigen::Isometry3f>(s, [](const dq::DualQuaternion<float>& q) { return dq::eigen::to_isometry(q); });
}
void GlmMat4(benchmark::State& s) {
  MatrixPerPose<glm::mat4>(s, [](const dq::DualQuaternion<float>& q) { return dq::glm_interop::to_glm(dq::to_mat4(q)); });
}
void DqkitMat4(benchmark::State& s) {
  MatrixPerPose<dq::Mat4<float>>(s, [](const dq::DualQuaternion<float>& q) { return dq::to_mat4(q); });
}

}  // namespace

BENCHMARK(SoAJob)->Arg(1)->Arg(2)->UseRealTime();
BENCHMARK(DualQuaternionPerPose);
BENCHMARK(EigenIsometry3f);
BENCHMARK(GlmMat4);
BENCHMARK(DqkitMat4);
BENCHMARK_MAIN();

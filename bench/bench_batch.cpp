// Batch kernels at the memory limit, with the machine's limits measured in the same run:
// copy and triad bandwidth over arrays four times the last-level cache (read from the CPU, which is
// 32 MB on some machines of this kind and 260 MB on others), one and two threads, and the peak
// rate of vector multiply-adds; then forward kinematics of 10,000 and 100,000 skeletons of 64
// joints (dqkit's run-time dispatched kernel, the scalar job, Eigen Isometry3f and Matrix4f pose by
// pose; one and two threads), one skeleton at a time, frames stored one after another (1024 in
// cache: local_to_model_frames against dq::local_to_model frame by frame; 100,000 in DRAM, one and
// two threads), transforming points, and
// composing arrays hot in cache and in DRAM, against Eigen and GLM in the same binary; inverse,
// directions, normalize, DLB, sclerp and the layout conversions (to_rows, from_rows) over 4096
// elements hot in cache against GLM, Eigen, dqkit's scalar sclerp per element and the
// component-by-component loop, and the layout conversions over arrays of 4 × LLC;
// and each of these kernels on every instruction set the CPU has, the target forced (OnTarget).
// Every variant's result is checked once,
// outside the timing, against dqkit's scalar types (the OnTarget cases' results are not: the tests
// check every target against the scalar path). Counters: bytes_per_second and, for the
// memory-bound cases, `roofline` = achieved bytes/s ÷ the measured copy bandwidth.
//   build/release/bench/bench_batch --benchmark_repetitions=3 --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <glm/gtx/dual_quaternion.hpp>
#include <glm/gtx/norm.hpp>  // length2, which mat3x4_cast uses
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "dq/interop/eigen.hpp"
#include "dq/interop/glm.hpp"
#include "dq/interp/rigid.hpp"
#include "dq/simd/batch.hpp"
#include "dq/simd/pose_blocks.hpp"
#include "dq/util/component_arrays.hpp"
#include "agreement.hpp"
#include "machine.hpp"

namespace {

using namespace dq;

// ---- the machine (bench/machine.hpp) -------------------------------------------------------------------

using bench::dram_floats;
using bench::Copy;
using bench::Triad;
using bench::same_transform;

double& copy_bandwidth() {  // bytes/s of the one-thread copy, measured first (the roofline's roof)
  static double b = 0;
  return b;
}

/// Peak vector multiply-add rate: 16 independent chains of the widest width this build's
/// dispatch uses (AVX-512 or AVX2 with FMA, per the CPU), in floating-point operations per second.
[[gnu::target("avx2,fma")]] float fma_chains_avx2(long n) {
  using v8 = float __attribute__((vector_size(32)));
  v8 acc[16];
  for (int k = 0; k < 16; ++k) acc[k] = v8{} + static_cast<float>(k);
  const v8 m = v8{} + 0.999999f, a = v8{} + 1e-7f;
  for (long i = 0; i < n; ++i)
    for (auto& x : acc) x = __builtin_ia32_vfmaddps256(x, m, a);
  float s = 0;
  for (auto& x : acc) s += x[0];
  return s;
}
void PeakFma(benchmark::State& state) {
  if (!__builtin_cpu_supports("fma")) return state.SkipWithError("no FMA on this CPU");
  long n = 1 << 16;
  for (auto _ : state) {
    benchmark::DoNotOptimize(n);  // opaque: the chains cannot be hoisted out of the timing loop
    benchmark::DoNotOptimize(fma_chains_avx2(n));
  }
  state.counters["flops"] =
      benchmark::Counter(static_cast<double>(state.iterations()) * static_cast<double>(n) * 16 * 8 * 2, benchmark::Counter::kIsRate);
}

// ---- forward kinematics of many skeletons ------------------------------------------------------------

constexpr std::size_t kJoints = 64;
/// The peers' FK results against dqkit's: chains at most 8 joints deep below the root, random unit
/// translations; float rounding of about 1e-6 with room, far below what a wrong parent or product gives.
constexpr double kFkTolerance = 1e-4;

/// A 64-joint tree, parents before children, branching like a character: eight chains of eight
/// joints from the root.
const std::vector<int>& tree_parents() {
  static const std::vector<int> parents = [] {
    std::vector<int> p{-1};
    for (std::size_t j = 1; j < kJoints; ++j) p.push_back(j % 8 == 1 ? 0 : static_cast<int>(j) - 1);
    return p;
  }();
  return parents;
}

/// The tree of tree_parents() and random local poses.
struct Skeletons {
  std::vector<int> parents;
  std::size_t poses;
  DualQuaternionSoAStorage<float> local, model;
  DualQuaternionBlockStorage<float> block_local, block_model;  // the same poses in blocks of 16
  explicit Skeletons(std::size_t n)
      : poses(n), local(kJoints, n), model(kJoints, n), block_local(kJoints, n), block_model(kJoints, n) {
    std::mt19937 rng(7);
    parents = tree_parents();
    std::normal_distribution<float> g;
    auto v = local.view();
    for (std::size_t j = 0; j < kJoints; ++j)
      for (std::size_t p = 0; p < n; ++p)
        v.set(j, p, DualQuaternion<float>::from_rotation_translation(Quaternion<float>(g(rng), g(rng), g(rng), g(rng)).normalized(),
                                                                      {g(rng), g(rng), g(rng)}));
    for (std::size_t j = 0; j < kJoints; ++j)
      for (std::size_t p = 0; p < n; ++p) block_local.view().set(j, p, v.get(j, p));
  }
  ForwardKinematicsJob<float> job() { return {parents, local.view(), model.view(), 0, poses}; }
  BlockedForwardKinematicsJob<float> blocked_job() { return {parents, block_local.view(), block_model.view(), 0, block_local.view().blocks}; }
};
Skeletons& skeletons(std::size_t n) {
  static Skeletons small(10'000), large(100'000);
  return n == 10'000 ? small : large;
}

/// `bytes_per_joint`: a float dual quaternion's 32 bytes of local pose read and 32 of model pose
/// written (the parent is in cache); 128 for Eigen's 4x4 matrices.
void report_fk(benchmark::State& state, std::size_t poses, double bytes_per_joint = 64) {
  const double joints = static_cast<double>(state.iterations()) * static_cast<double>(poses * kJoints);
  state.counters["joints_per_s"] = benchmark::Counter(joints, benchmark::Counter::kIsRate);
  state.SetBytesProcessed(static_cast<int64_t>(joints * bytes_per_joint));
  if (copy_bandwidth() > 0) state.counters["roofline"] = benchmark::Counter(joints * bytes_per_joint / copy_bandwidth(), benchmark::Counter::kIsRate);
}

void FkDispatched(benchmark::State& state) {
  const auto poses = static_cast<std::size_t>(state.range(0));
  const auto threads = static_cast<unsigned>(state.range(1));
  Skeletons& s = skeletons(poses);
  const ForwardKinematicsJob<float> job = s.job();
  state.SetLabel(std::string(simd::to_string(simd::current_target())));
  for (auto _ : state) {
    if (threads == 1)
      simd::run(job);
    else
      (void)simd::run_parallel(job, threads, 1024);
    benchmark::ClobberMemory();
  }
  report_fk(state, poses);
}
/// The same poses in blocks of 16 (dq/anim/pose_blocks.hpp): two streams instead of 24.
void FkBlocks(benchmark::State& state, Stores stores) {
  const auto poses = static_cast<std::size_t>(state.range(0));
  const auto threads = static_cast<unsigned>(state.range(1));
  Skeletons& s = skeletons(poses);
  BlockedForwardKinematicsJob<float> job = s.blocked_job();
  job.stores = stores;
  state.SetLabel(std::string(simd::to_string(simd::current_target())));
  for (auto _ : state) {
    if (threads == 1)
      simd::run(job);
    else
      (void)simd::run_parallel(job, threads, 64);
    benchmark::ClobberMemory();
  }
  // Checked once against the joint-major job's result: bit for bit, unless this file is built with
  // FMA (-mavx2 -mfma), where GCC contracts the job's multiply-adds (the benchmarks are compiled
  // as a user's code is, without dqkit's -ffp-contract=off) and the kernel's do not.
  s.job().run();
#ifdef __FMA__
  const auto same = [](const DualQuaternion<float>& x, const DualQuaternion<float>& y) { return approx_equal(x, y, 1e-5f * (1 + norm(y.translation()))); };
#else
  const auto same = [](const DualQuaternion<float>& x, const DualQuaternion<float>& y) { return x == y; };
#endif
  for (std::size_t p = 0; p < poses; p += poses / 7)
    for (std::size_t j = 0; j < kJoints; ++j)
      if (!same(s.block_model.view().get(j, p), s.model.view().get(j, p))) return state.SkipWithError("blocked and joint-major results differ");
  report_fk(state, poses);
}
void FkBlocksDispatched(benchmark::State& state) { FkBlocks(state, Stores::cached); }
/// With non-temporal stores of the model transforms (Stores::streaming).
void FkBlocksStreaming(benchmark::State& state) { FkBlocks(state, Stores::streaming); }
void FkScalarJob(benchmark::State& state) {
  const auto poses = static_cast<std::size_t>(state.range(0));
  Skeletons& s = skeletons(poses);
  const ForwardKinematicsJob<float> job = s.job();
  for (auto _ : state) {
    job.run();
    benchmark::ClobberMemory();
  }
  report_fk(state, poses);
}
/// An Eigen transform from a dual quaternion: Isometry3f, or its 4x4 matrix as Matrix4f.
template <class E>
E to_eigen_transform(const DualQuaternion<float>& q) {
  if constexpr (std::is_same_v<E, Eigen::Matrix4f>)
    return eigen::to_isometry(q).matrix();
  else
    return eigen::to_isometry(q);
}
/// parent · local into `model`: Matrix4f with noalias() (Eigen's form for a product into another
/// matrix, without a temporary); Isometry3f's product and dqkit's have no such form.
template <class E>
void compose_into(E& model, const E& parent, const E& local) {
  if constexpr (requires { model.noalias() = parent * local; })
    model.noalias() = parent * local;
  else
    model = parent * local;
}
/// What users of Eigen write: each skeleton's poses as Isometry3f (or its 4x4 matrix as
/// Matrix4f, whose product Eigen vectorizes: Isometry3f's composes a 3x3 block and a vector),
/// pose by pose.
template <class E>
void FkEigenPerPose(benchmark::State& state) {
  const auto poses = static_cast<std::size_t>(state.range(0));
  Skeletons& s = skeletons(poses);
  const auto v = s.local.view();
  std::vector<E> local(poses * kJoints), model(poses * kJoints, E::Identity());  // filled before timing
  for (std::size_t p = 0; p < poses; ++p)
    for (std::size_t j = 0; j < kJoints; ++j) local[p * kJoints + j] = to_eigen_transform<E>(v.get(j, p));
  for (auto _ : state) {
    for (std::size_t p = 0; p < poses; ++p) {
      const E* l = local.data() + p * kJoints;
      E* m = model.data() + p * kJoints;
      for (std::size_t j = 0; j < kJoints; ++j) {
        if (s.parents[j] < 0)
          m[j] = l[j];
        else
          compose_into(m[j], m[s.parents[j]], l[j]);
      }
    }
    benchmark::DoNotOptimize(model.data());
    benchmark::ClobberMemory();
  }
  // Checked once: the same model transforms as dqkit's job.
  s.job().run();
  const auto got = s.model.view();
  for (std::size_t p = 0; p < poses; p += poses / 7)
    for (std::size_t j = 0; j < kJoints; ++j)
      if (!same_transform(model[p * kJoints + j], got.get(j, p), kFkTolerance)) return state.SkipWithError("Eigen and dqkit disagree");
  report_fk(state, poses, 2.0 * sizeof(E));
}

/// One skeleton at a time (64 joints): dqkit dual quaternions and Eigen Isometry3f and Matrix4f,
/// each checked once against dqkit's batch job on the same pose.
template <class X, class Make>
void FkOneSkeleton(benchmark::State& state, Make make) {
  Skeletons& s = skeletons(10'000);
  const auto v = s.local.view();
  std::vector<X> local, model(kJoints, make(DualQuaternion<float>{}));
  for (std::size_t j = 0; j < kJoints; ++j) local.push_back(make(v.get(j, 0)));
  for (auto _ : state) {
    for (std::size_t j = 0; j < kJoints; ++j) {
      if (s.parents[j] < 0)
        model[j] = local[j];
      else
        compose_into(model[j], model[static_cast<std::size_t>(s.parents[j])], local[j]);
    }
    benchmark::DoNotOptimize(model.data());
    benchmark::ClobberMemory();
  }
  s.job().run();
  for (std::size_t j = 0; j < kJoints; ++j)
    if (!same_transform(model[j], s.model.view().get(j, 0), kFkTolerance)) return state.SkipWithError("the skeleton's model transforms differ from dqkit's job");
  state.counters["joints_per_s"] = benchmark::Counter(static_cast<double>(state.iterations() * kJoints), benchmark::Counter::kIsRate);
}
void FkOneSkeletonDualQuaternion(benchmark::State& s) {
  FkOneSkeleton<DualQuaternion<float>>(s, [](const DualQuaternion<float>& q) { return q; });
}
template <class E>
void FkOneSkeletonEigen(benchmark::State& s) {
  FkOneSkeleton<E>(s, to_eigen_transform<E>);
}

/// Frames stored one after another (frame f's joint j at [f · 64 + j], a NumPy (F, J, 8) array), in
/// float or double (T): simd::local_to_model_frames, which loads and transposes them in place,
/// against dq::local_to_model frame by frame (what the Python binding ran before, and for double
/// until 2026-12-07). The first `frames` poses of the 10,000 skeletons, or all of the 100,000 (in
/// DRAM, as FK of 100,000 skeletons: 410 MB in float).
template <class T>
struct Frames {
  std::vector<DualQuaternion<T>> local, model;
  explicit Frames(std::size_t frames) : model(frames * kJoints) {
    local.reserve(frames * kJoints);
    const auto v = skeletons(frames <= 10'000 ? 10'000 : 100'000).local.view();
    for (std::size_t f = 0; f < frames; ++f)
      for (std::size_t j = 0; j < kJoints; ++j) local.push_back(v.get(j, f).template cast<T>());
  }
};
/// A dual quaternion's bytes read and written per joint (32 in float, 64 in double, each way).
template <class T>
constexpr double kFrameBytes = 2.0 * sizeof(DualQuaternion<T>);
/// Arguments: frames, threads (local_to_model_frames_parallel on two).
template <class T>
void FkFramesDispatched(benchmark::State& state) {
  const auto frames = static_cast<std::size_t>(state.range(0));
  const auto threads = static_cast<unsigned>(state.range(1));
  Frames<T> x(frames);
  const std::vector<int>& parents = skeletons(10'000).parents;
  state.SetLabel(std::string(simd::to_string(simd::current_target())));
  for (auto _ : state) {
    if (threads == 1)
      (void)simd::local_to_model_frames(parents, x.local, x.model);
    else
      (void)simd::local_to_model_frames_parallel(parents, x.local, x.model, threads);
    benchmark::ClobberMemory();
  }
  // Checked once: every 97th frame against dq::local_to_model on that frame alone.
  std::vector<DualQuaternion<T>> frame(kJoints);
  for (std::size_t f = 0; f < frames; f += 97) {
    local_to_model<DualQuaternion<T>>(parents, std::span(x.local).subspan(f * kJoints, kJoints), frame);
    for (std::size_t j = 0; j < kJoints; ++j)
      if (!same_transform(x.model[f * kJoints + j], frame[j], kFkTolerance)) return state.SkipWithError("the batch differs from a frame computed alone");
  }
  report_fk(state, frames, kFrameBytes<T>);
}
template <class T>
void FkFramesPerFrame(benchmark::State& state) {
  const auto frames = static_cast<std::size_t>(state.range(0));
  Frames<T> x(frames);
  const std::vector<int>& parents = skeletons(10'000).parents;
  for (auto _ : state) {
    for (std::size_t f = 0; f < frames; ++f)
      local_to_model<DualQuaternion<T>>(parents, std::span(x.local).subspan(f * kJoints, kJoints), std::span(x.model).subspan(f * kJoints, kJoints));
    benchmark::ClobberMemory();
  }
  std::vector<DualQuaternion<T>> batch(x.model.size());
  (void)simd::local_to_model_frames(parents, x.local, batch);
  for (std::size_t i = 0; i < batch.size(); ++i)
    if (!same_transform(x.model[i], batch[i], kFkTolerance)) return state.SkipWithError("the frame-by-frame result differs from the batch's");
  report_fk(state, frames, kFrameBytes<T>);
}
/// The peer in double: the same frames as Eigen Isometry3d, frame by frame (what users of Eigen and
/// KDL in robotics write), checked once against dqkit's batch.
void FkFramesEigenIsometry3d(benchmark::State& state) {
  const auto frames = static_cast<std::size_t>(state.range(0));
  Frames<double> x(frames);
  const std::vector<int>& parents = skeletons(10'000).parents;
  std::vector<Eigen::Isometry3d> local, model(x.local.size(), Eigen::Isometry3d::Identity());  // filled before timing
  for (const auto& q : x.local) local.push_back(eigen::to_isometry(q));
  for (auto _ : state) {
    for (std::size_t f = 0; f < frames; ++f) {
      const Eigen::Isometry3d* l = local.data() + f * kJoints;
      Eigen::Isometry3d* m = model.data() + f * kJoints;
      for (std::size_t j = 0; j < kJoints; ++j) m[j] = parents[j] < 0 ? l[j] : m[static_cast<std::size_t>(parents[j])] * l[j];
    }
    benchmark::DoNotOptimize(model.data());
    benchmark::ClobberMemory();
  }
  (void)simd::local_to_model_frames(parents, x.local, x.model);
  for (std::size_t i = 0; i < model.size(); i += 7)
    if (!same_transform(model[i], x.model[i], kFkTolerance)) return state.SkipWithError("Eigen and dqkit disagree");
  report_fk(state, frames, 2.0 * sizeof(Eigen::Isometry3d));
}

// ---- points and compositions ---------------------------------------------------------------------------

/// n dual quaternions in SoA (8 arrays), points (3), outputs, and AoS copies for the peers. The
/// arrays are ComponentArrays: aligned, and skewed so that the 14 streams of a point transform do
/// not map to the same cache sets (in std::vectors of 2^k floats they did).
struct Arrays {
  ComponentArrays<float, 8> c, o8;
  ComponentArrays<float, 3> p, out;
  std::vector<DualQuaternion<float>> dq;
  explicit Arrays(std::size_t n) : c(n), o8(n), p(n), out(n) {
    std::mt19937 rng(3);
    std::normal_distribution<float> g;
    for (std::size_t i = 0; i < n; ++i) {
      const auto q = DualQuaternion<float>::from_rotation_translation(Quaternion<float>(g(rng), g(rng), g(rng), g(rng)).normalized(),
                                                                      {g(rng), g(rng), g(rng)});
      dq.push_back(q);
      const float* s = &q.real.w;
      for (int k = 0; k < 8; ++k) c[k][i] = s[k];
      for (std::size_t k = 0; k < 3; ++k) p[k][i] = g(rng);
    }
  }
};
// warm_up_note: the dispatched cases over these arrays run their kernel once before the timing.
// The arrays are made once and kept, while each peer's copy is made, and so touched, just before
// its timing; on a virtual machine that hands memory back to its host, pages untouched for a while
// (other cases allocating and freeing gigabytes meanwhile) cost a fault again.
Arrays& arrays(std::size_t n) {
  static Arrays hot(4096), dram(dram_floats() / 8);
  return n == 4096 ? hot : dram;
}
std::size_t size_of(benchmark::State& state) { return state.range(0) == 0 ? 4096 : dram_floats() / 8; }

void TransformPointsDispatched(benchmark::State& state) {
  Arrays& a = arrays(size_of(state));
  const std::size_t n = a.dq.size();
  state.SetLabel(std::string(simd::to_string(simd::current_target())));
  simd::transform_points(simd::rows(a.c), std::as_const(a.p).data(), a.out.data(), n);  // untimed: see warm_up_note
  for (auto _ : state) {
    simd::transform_points(simd::rows(a.c), std::as_const(a.p).data(), a.out.data(), n);
    benchmark::ClobberMemory();
  }
  state.counters["points_per_s"] = benchmark::Counter(static_cast<double>(state.iterations() * n), benchmark::Counter::kIsRate);
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations() * n * 56));  // 32 + 12 in, 12 out
}
void TransformPointsEigenIsometry3f(benchmark::State& state) {
  Arrays& a = arrays(size_of(state));
  const std::size_t n = a.dq.size();
  std::vector<Eigen::Isometry3f> m;
  // Filled, not just sized: Eigen's vectors leave their values uninitialized, so a sized
  // std::vector of them is first written in the timed loop, whose first pass then took the page
  // faults of its 800 MB in DRAM (10 µs each on a machine of this kind: 3.5 s against 0.3 s).
  std::vector<Eigen::Vector3f> p(n), out(n, Eigen::Vector3f::Zero());
  for (std::size_t i = 0; i < n; ++i) m.push_back(eigen::to_isometry(a.dq[i])), p[i] = {a.p[0][i], a.p[1][i], a.p[2][i]};
  for (auto _ : state) {
    for (std::size_t i = 0; i < n; ++i) out[i] = m[i] * p[i];
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  // Checked once against dqkit.
  simd::transform_points(simd::rows(a.c), std::as_const(a.p).data(), a.out.data(), n);
  for (std::size_t i = 0; i < n; i += 97)
    if ((out[i] - Eigen::Vector3f(a.out[0][i], a.out[1][i], a.out[2][i])).norm() > 1e-4f * (1 + out[i].norm())) state.SkipWithError("Eigen and dqkit disagree");
  state.counters["points_per_s"] = benchmark::Counter(static_cast<double>(state.iterations() * n), benchmark::Counter::kIsRate);
}

// ---- one transform for a cloud of points ---------------------------------------------------------------
// A point cloud or a mesh moved rigidly: one transform, the points one after another (x, y, z) in
// and out. Argument 0: 4096 points, hot in cache; 1: 4 × LLC bytes each way, in DRAM. Every peer
// reads and writes the same two arrays and is checked once, outside the timing, against
// DualQuaternion::transform_point (every 97th point).

struct Cloud {
  DualQuaternion<float> q;
  std::vector<Vec3<float>> in, out;
  explicit Cloud(std::size_t n) : in(n), out(n) {  // both filled: no page faults in a timed pass
    std::mt19937 rng(7);
    std::normal_distribution<float> g;
    q = DualQuaternion<float>::from_rotation_translation(Quaternion<float>(0.3f, -0.5f, 0.7f, 0.1f).normalized(), {1.5f, -2.0f, 0.25f});
    for (Vec3<float>& p : in) p = {g(rng), g(rng), g(rng)};
  }
};
Cloud& cloud(benchmark::State& state) {
  if (state.range(0) == 0) {
    static Cloud hot(4096);
    return hot;
  }
  static Cloud dram(dram_floats() / 3);
  return dram;
}
/// The timing loop of a cloud case, its check and counters (24 bytes a point: 12 in, 12 out).
/// `exact`: the result must be transform_point's bit for bit (dqkit's), else within 1e-5 of it
/// relative (the matrix peers round differently). Built with FMA (build/bench-avx2), this file's
/// transform_point may be contracted where the library's is not: there, within 1e-5 too.
template <class Move>
void time_cloud(benchmark::State& state, bool exact, Move move) {
#if defined(__FMA__)
  exact = false;
#endif
  Cloud& c = cloud(state);
  const std::size_t n = c.in.size();
  // NaN first, so that the check below sees this case's output and not the previous case's.
  std::fill(c.out.begin(), c.out.end(), Vec3<float>{std::nanf(""), std::nanf(""), std::nanf("")});
  move(c);  // untimed: see warm_up_note
  for (auto _ : state) {
    move(c);
    benchmark::DoNotOptimize(c.out.data());
    benchmark::ClobberMemory();
  }
  for (std::size_t i = 0; i < n; i += 97) {
    const Vec3<float> want = c.q.transform_point(c.in[i]);
    const bool same = exact ? std::memcmp(&c.out[i], &want, sizeof want) == 0 : norm(c.out[i] - want) <= 1e-5f * (1 + norm(want));
    if (!same) return state.SkipWithError("the result differs from transform_point");
  }
  state.counters["points_per_s"] = benchmark::Counter(static_cast<double>(state.iterations() * n), benchmark::Counter::kIsRate);
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations() * n * 24));
  if (state.range(0) == 1 && copy_bandwidth() > 0)
    state.counters["roofline"] = benchmark::Counter(static_cast<double>(state.iterations() * n * 24) / copy_bandwidth(), benchmark::Counter::kIsRate);
}
void PointCloudDispatched(benchmark::State& state) {
  state.SetLabel(std::string(simd::to_string(simd::current_target())));
  time_cloud(state, true, [](Cloud& c) { simd::transform_points(c.q, c.in, c.out); });
}
/// What users of dqkit's one-at-a-time type write.
void PointCloudScalar(benchmark::State& state) {
  time_cloud(state, true, [](Cloud& c) {
    for (std::size_t i = 0; i < c.in.size(); ++i) c.out[i] = c.q.transform_point(c.in[i]);
  });
}
/// Eigen, point by point (an Isometry3f times each Vector3f, mapped onto the same floats).
void PointCloudEigenIsometry3f(benchmark::State& state) {
  const Eigen::Isometry3f m = eigen::to_isometry(cloud(state).q);
  time_cloud(state, false, [&m](Cloud& c) {
    for (std::size_t i = 0; i < c.in.size(); ++i) Eigen::Vector3f::Map(&c.out[i].x) = m * Eigen::Vector3f::Map(&c.in[i].x);
  });
}
/// Eigen's bulk form: the points as the columns of a 3 × n matrix, R P then t added to every
/// column (two passes, each vectorized by Eigen).
void PointCloudEigenMatrix3Xf(benchmark::State& state) {
  const Eigen::Isometry3f m = eigen::to_isometry(cloud(state).q);
  time_cloud(state, false, [&m](Cloud& c) {
    const auto n = static_cast<Eigen::Index>(c.in.size());
    Eigen::Map<Eigen::Matrix3Xf> out(&c.out[0].x, 3, n);
    out.noalias() = m.linear() * Eigen::Map<const Eigen::Matrix3Xf>(&c.in[0].x, 3, n);
    out.colwise() += m.translation();
  });
}
/// GLM, point by point: a mat4 times each point as a vec4 (w = 1).
void PointCloudGlmMat4(benchmark::State& state) {
  const glm::mat4 m = glm_interop::to_glm(to_mat4(cloud(state).q));
  time_cloud(state, false, [&m](Cloud& c) {
    for (std::size_t i = 0; i < c.in.size(); ++i) {
      const glm::vec4 r = m * glm::vec4(c.in[i].x, c.in[i].y, c.in[i].z, 1.0f);
      c.out[i] = {r.x, r.y, r.z};
    }
  });
}

/// 4096 pairs of unit quaternions: the rotations of the hot arrays, each with the one n/2 places on.
struct SlerpArrays {
  static constexpr std::size_t n = 4096;
  ComponentArrays<float, 4> a{n}, b{n}, out{n};
  std::vector<Eigen::Quaternionf> ea, eb;
  SlerpArrays() {
    const auto& dq = arrays(n).dq;
    for (std::size_t i = 0; i < n; ++i) {
      const Quaternion<float>& x = dq[i].real;
      const Quaternion<float>& y = dq[(i + n / 2) % n].real;
      for (std::size_t k = 0; k < 4; ++k) a[k][i] = (&x.w)[k], b[k][i] = (&y.w)[k];
      ea.push_back(eigen::to_eigen(x)), eb.push_back(eigen::to_eigen(y));
    }
  }
  void run() {
    const auto x = std::as_const(a).data(), y = std::as_const(b).data();
    const auto o = out.data();
    simd::slerp({x[0], x[1], x[2], x[3]}, {y[0], y[1], y[2], y[3]}, 0.3f, {o[0], o[1], o[2], o[3]}, n);
  }
};
SlerpArrays& slerp_arrays() {
  static SlerpArrays s;
  return s;
}
/// slerp over the 4096 pairs, t = 0.3: the dispatched kernel (no failure case) against Eigen's
/// slerp per element (which divides by sin Ω), whose result is checked once against the kernel's.
void SlerpDispatched(benchmark::State& state) {
  SlerpArrays& s = slerp_arrays();
  state.SetLabel(std::string(simd::to_string(simd::current_target())));
  for (auto _ : state) {
    s.run();
    benchmark::ClobberMemory();
  }
  state.counters["per_s"] = benchmark::Counter(static_cast<double>(state.iterations() * s.n), benchmark::Counter::kIsRate);
}
void SlerpEigen(benchmark::State& state) {
  SlerpArrays& s = slerp_arrays();
  std::vector<Eigen::Quaternionf> out(s.n, Eigen::Quaternionf::Identity());  // filled, as TransformPointsEigenIsometry3f's
  for (auto _ : state) {
    for (std::size_t i = 0; i < s.n; ++i) out[i] = s.ea[i].slerp(0.3f, s.eb[i]);
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  s.run();
  for (std::size_t i = 0; i < s.n; ++i)
    if (!approx_equal(eigen::from_eigen(out[i]), Quaternion<float>(s.out[0][i], s.out[1][i], s.out[2][i], s.out[3][i]), 1e-5f, SignPolicy::same_rotation))
      return state.SkipWithError("Eigen and dqkit disagree");
  state.counters["per_s"] = benchmark::Counter(static_cast<double>(state.iterations() * s.n), benchmark::Counter::kIsRate);
}

void ComposeDispatched(benchmark::State& state) {
  Arrays& a = arrays(size_of(state));
  const std::size_t n = a.dq.size();
  state.SetLabel(std::string(simd::to_string(simd::current_target())));
  simd::compose(simd::rows(a.c), simd::rows(a.c), simd::rows(a.o8), n);  // untimed: see warm_up_note
  for (auto _ : state) {
    simd::compose(simd::rows(a.c), simd::rows(a.c), simd::rows(a.o8), n);
    benchmark::ClobberMemory();
  }
  state.counters["per_s"] = benchmark::Counter(static_cast<double>(state.iterations() * n), benchmark::Counter::kIsRate);
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations() * n * 64));
  if (copy_bandwidth() > 0 && state.range(0) != 0)
    state.counters["roofline"] = benchmark::Counter(static_cast<double>(state.iterations() * n * 64) / copy_bandwidth(), benchmark::Counter::kIsRate);
}
/// A peer's products x[i] · x[i] over the arrays, each of its transforms made once by `make` and
/// composed by `compose(out, a, b)`, checked once against dqkit's products (every 97th).
template <class M, class Make, class Compose>
void ComposePeer(benchmark::State& state, Make make, Compose compose) {
  Arrays& a = arrays(size_of(state));
  const std::size_t n = a.dq.size();
  std::vector<M> x;
  x.reserve(n);  // no doubling of arrays of 4 × LLC
  for (const auto& q : a.dq) x.push_back(make(q));
  std::vector<M> out(n, x[0]);  // filled before timing
  for (auto _ : state) {
    for (std::size_t i = 0; i < n; ++i) compose(out[i], x[i], x[i]);
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  for (std::size_t i = 0; i < n; i += 97)
    if (!same_transform(out[i], a.dq[i] * a.dq[i], 1e-4)) return state.SkipWithError("the peer's products differ from dqkit's");
  state.counters["per_s"] = benchmark::Counter(static_cast<double>(state.iterations() * n), benchmark::Counter::kIsRate);
}
void ComposeGlmDualquat(benchmark::State& state) {
  ComposePeer<glm::dualquat>(
      state, [](const DualQuaternion<float>& q) { return glm_interop::to_glm(q); },
      [](glm::dualquat& out, const glm::dualquat& a, const glm::dualquat& b) { out = a * b; });
}
template <class E>
void ComposeEigen(benchmark::State& state) {
  ComposePeer<E>(state, to_eigen_transform<E>, compose_into<E>);
}

// ---- inverse, directions, normalize, dlb, sclerp over arrays -------------------------------------------
// Hot in cache (4096 elements, as the compose and slerp cases), each dispatched kernel against the
// per-element code of a peer on the same data, whose result is checked once outside the timing.

constexpr float kBlendT = 0.3f;

/// 4096 pairs of unit dual quaternions (a, b) in SoA (`ComponentArrays`, as the other cases' arrays)
/// and AoS, directions, the a's scaled by 0.5–2 (for normalize), and outputs.
struct KernelArrays {
  static constexpr std::size_t n = 4096;
  ComponentArrays<float, 8> a{n}, b{n}, scaled{n}, out{n};
  ComponentArrays<float, 3> v{n};
  ComponentArrays<float, 12> matrix{n};
  std::vector<DualQuaternion<float>> dq_a, dq_b, dq_scaled, dq_out;
  // In double: the a's (also for the frames in double) and b's, in SoA too, the directions v as
  // points, and outputs.
  std::vector<DualQuaternion<double>> dq_a_double, dq_b_double, dq_out_double;
  ComponentArrays<double, 8> a_double{n}, b_double{n}, out_double{n};
  ComponentArrays<double, 3> v_double{n}, moved_double{n};
  std::vector<Vec3<double>> cloud_double, cloud_double_out;  // v as points one after another
  std::vector<Vec3<float>> cloud_out{n};
  std::vector<Vec3<float>> points_out;  // the points v as rows (x, y, z a point), by from_rows_points
  KernelArrays() : dq_out(n), dq_out_double(n), points_out(n) {
    std::mt19937 rng(5);
    std::normal_distribution<float> g;
    std::uniform_real_distribution<float> s(0.5f, 2.0f);
    auto random_transform = [&] {
      return DualQuaternion<float>::from_rotation_translation(Quaternion<float>(g(rng), g(rng), g(rng), g(rng)).normalized(), {g(rng), g(rng), g(rng)});
    };
    for (std::size_t i = 0; i < n; ++i) dq_a.push_back(random_transform()), dq_b.push_back(random_transform()), dq_scaled.push_back(dq_a[i] * s(rng));
    simd::to_rows(dq_a, simd::rows(a)), simd::to_rows(dq_b, simd::rows(b)), simd::to_rows(dq_scaled, simd::rows(scaled));
    simd::to_rows(dq_a, simd::rows(out));
    // Unit in double (the float ones, cast, are unit to float rounding only: the peers' matrices
    // would then differ from dqkit's results by about 1e-7).
    for (std::size_t i = 0; i < n; ++i)
      dq_a_double.push_back(dq_a[i].cast<double>().normalized()), dq_b_double.push_back(dq_b[i].cast<double>().normalized());
    simd::to_rows(dq_a_double, simd::rows(a_double)), simd::to_rows(dq_b_double, simd::rows(b_double));
    for (std::size_t k = 0; k < 3; ++k)
      for (std::size_t i = 0; i < n; ++i) v[k][i] = g(rng), v_double[k][i] = v[k][i];
    for (std::size_t i = 0; i < n; ++i) cloud_double.push_back(point_double(i));
    cloud_double_out = cloud_double;
    from_rows_points();
  }
  DualQuaternion<double> result_double(std::size_t i) const {
    const auto& o = out_double;
    return {o[0][i], o[1][i], o[2][i], o[3][i], o[4][i], o[5][i], o[6][i], o[7][i]};
  }
  Vec3<double> point_double(std::size_t i) const { return {v_double[0][i], v_double[1][i], v_double[2][i]}; }
  Vec3<double> moved_point_double(std::size_t i) const { return {moved_double[0][i], moved_double[1][i], moved_double[2][i]}; }
  std::array<float*, 12> matrices() { return matrix.data(); }
  DualQuaternion<float> result(std::size_t i) const {
    return {out[0][i], out[1][i], out[2][i], out[3][i], out[4][i], out[5][i], out[6][i], out[7][i]};
  }
  // The dispatched kernels on these arrays: what the *Dispatched cases time, what each peer is
  // checked against, and what OnTarget runs on each instruction set.
  void inverse() { simd::inverse(simd::rows(a), simd::rows(out), n); }
  void directions() { simd::transform_directions(simd::rows(a), {v[0].data(), v[1].data(), v[2].data()}, {out[0].data(), out[1].data(), out[2].data()}, n); }
  void to_matrices() { simd::to_matrices(simd::rows(a), matrices(), n); }
  void normalize() { simd::normalize(simd::rows(scaled), simd::rows(out), n); }
  void dlb() { simd::dlb(simd::rows(a), simd::rows(b), kBlendT, simd::rows(out), n); }
  void sclerp() { simd::sclerp(simd::rows(a), simd::rows(b), kBlendT, simd::rows(out), n); }
  void to_rows() { simd::to_rows(dq_a, simd::rows(out)); }
  void from_rows() { simd::from_rows(simd::rows(a), dq_out); }
  // Only in OnTarget (their own cases run on the Arrays and SlerpArrays above).
  void compose() { simd::compose(simd::rows(a), simd::rows(b), simd::rows(out), n); }
  void points() { simd::transform_points(simd::rows(a), {v[0].data(), v[1].data(), v[2].data()}, {out[0].data(), out[1].data(), out[2].data()}, n); }
  void slerp() {
    simd::slerp({a[0].data(), a[1].data(), a[2].data(), a[3].data()}, {b[0].data(), b[1].data(), b[2].data(), b[3].data()}, kBlendT,
                {out[0].data(), out[1].data(), out[2].data(), out[3].data()}, n);
  }
  // Only in OnTarget, with no case of their own: the points' layout conversions, and forward
  // kinematics of the a's as 64 frames of the 64-joint tree (per second: joints), in float and double.
  void to_rows_points() { simd::to_rows(points_out, {out[0].data(), out[1].data(), out[2].data()}); }
  void from_rows_points() { simd::from_rows({v[0].data(), v[1].data(), v[2].data()}, points_out); }
  void frames() { (void)simd::local_to_model_frames(tree_parents(), dq_a, dq_out); }
  void frames_double() { (void)simd::local_to_model_frames(tree_parents(), dq_a_double, dq_out_double); }
  // The kernels in double: their own cases below, and OnTarget; over component arrays, and over
  // arrays of structures (records: the dual quaternions and points one after another).
  void compose_double() { simd::compose(simd::rows(a_double), simd::rows(b_double), simd::rows(out_double), n); }
  void points_double() { simd::transform_points(simd::rows(a_double), std::as_const(v_double).data(), moved_double.data(), n); }
  void compose_records_double() { simd::compose(dq_a_double, dq_b_double, dq_out_double); }
  void points_records_double() { simd::transform_points(dq_a_double, cloud_double, cloud_double_out); }
  // The same over arrays of structures in float: only in OnTarget.
  void compose_records() { simd::compose(dq_a, dq_b, dq_out); }
  void points_records() { simd::transform_points(dq_a, points_out, cloud_out); }
  // Only in OnTarget: one transform for the v's as points one after another, in double.
  void cloud_double_moved() { simd::transform_points(dq_a_double[0], cloud_double, cloud_double_out); }
};
KernelArrays& kernel_arrays() {
  static KernelArrays k;
  return k;
}
/// Runs a dispatched kernel on the arrays: the timing loop and the rate counter.
template <class Kernel>
void run_dispatched(benchmark::State& state, Kernel kernel) {
  state.SetLabel(std::string(simd::to_string(simd::current_target())));
  for (auto _ : state) {
    kernel();
    benchmark::ClobberMemory();
  }
  state.counters["per_s"] = benchmark::Counter(static_cast<double>(state.iterations() * KernelArrays::n), benchmark::Counter::kIsRate);
}
/// Runs a peer's per-element loop `out[i] = f(i)`, then checks it once against the dispatched
/// kernel's result (`same(i, out[i])`, after `kernel()`), outside the timing.
template <class Out, class F, class Kernel, class Same>
void run_peer(benchmark::State& state, F f, Kernel kernel, Same same) {
  std::vector<Out> out(KernelArrays::n);
  for (auto _ : state) {
    for (std::size_t i = 0; i < KernelArrays::n; ++i) out[i] = f(i);
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  kernel();
  for (std::size_t i = 0; i < KernelArrays::n; ++i)
    if (!same(i, out[i])) return state.SkipWithError("the peer and dqkit's kernel disagree");
  state.counters["per_s"] = benchmark::Counter(static_cast<double>(state.iterations() * KernelArrays::n), benchmark::Counter::kIsRate);
}
std::vector<glm::dualquat> to_glm(const std::vector<DualQuaternion<float>>& q) {
  std::vector<glm::dualquat> g;
  for (const auto& x : q) g.push_back(glm_interop::to_glm(x));
  return g;
}

void InverseDispatched(benchmark::State& state) {
  KernelArrays& k = kernel_arrays();
  run_dispatched(state, [&] { k.inverse(); });
}
void InverseGlmDualquat(benchmark::State& state) {
  KernelArrays& k = kernel_arrays();
  const std::vector<glm::dualquat> a = to_glm(k.dq_a);
  run_peer<glm::dualquat>(
      state, [&](std::size_t i) { return glm::inverse(a[i]); }, [&] { k.inverse(); },
      [&](std::size_t i, const glm::dualquat& g) { return approx_equal(glm_interop::from_glm(g), k.result(i), 1e-5f); });
}

void TransformDirectionsDispatched(benchmark::State& state) {
  KernelArrays& k = kernel_arrays();
  run_dispatched(state, [&] { k.directions(); });
}
/// The peers' directions against the kernel's (in out[0..2]).
template <class V>
auto same_direction(KernelArrays& k) {
  return [&k](std::size_t i, const V& d) {
    return std::abs(d[0] - k.out[0][i]) + std::abs(d[1] - k.out[1][i]) + std::abs(d[2] - k.out[2][i]) <= 1e-5f * (1 + std::abs(d[0]) + std::abs(d[1]) + std::abs(d[2]));
  };
}
void TransformDirectionsGlmMat4(benchmark::State& state) {
  KernelArrays& k = kernel_arrays();
  std::vector<glm::mat4> m;
  std::vector<glm::vec3> v;
  for (std::size_t i = 0; i < KernelArrays::n; ++i) m.push_back(glm_interop::to_glm(to_mat4(k.dq_a[i]))), v.emplace_back(k.v[0][i], k.v[1][i], k.v[2][i]);
  run_peer<glm::vec3>(
      state, [&](std::size_t i) { return glm::vec3(m[i] * glm::vec4(v[i], 0.0f)); },
      [&] { k.directions(); },
      same_direction<glm::vec3>(k));
}
void TransformDirectionsEigenIsometry3f(benchmark::State& state) {
  KernelArrays& k = kernel_arrays();
  std::vector<Eigen::Isometry3f> m;
  std::vector<Eigen::Vector3f> v;
  for (std::size_t i = 0; i < KernelArrays::n; ++i) m.push_back(eigen::to_isometry(k.dq_a[i])), v.emplace_back(k.v[0][i], k.v[1][i], k.v[2][i]);
  run_peer<Eigen::Vector3f>(
      state, [&](std::size_t i) -> Eigen::Vector3f { return m[i].linear() * v[i]; },
      [&] { k.directions(); },
      same_direction<Eigen::Vector3f>(k));
}

/// Dual quaternions to 3x4 matrices: the kernel (twelve arrays) against GLM's mat3x4_cast.
void ToMatricesDispatched(benchmark::State& state) {
  KernelArrays& k = kernel_arrays();
  run_dispatched(state, [&] { k.to_matrices(); });
}
void ToMatricesGlmDualquat(benchmark::State& state) {
  KernelArrays& k = kernel_arrays();
  const std::vector<glm::dualquat> q = to_glm(k.dq_a);
  run_peer<glm::mat3x4>(
      state, [&](std::size_t i) { return glm::mat3x4_cast(q[i]); }, [&] { k.to_matrices(); },
      [&](std::size_t i, const glm::mat3x4& g) {  // GLM's mat3x4 holds the rows of [R | t] as its columns
        for (int r = 0; r < 3; ++r)
          for (int c = 0; c < 4; ++c)
            if (std::abs(g[r][c] - k.matrix[static_cast<std::size_t>(c * 3 + r)][i]) > 1e-5f * (1 + std::abs(g[r][c]))) return false;
        return true;
      });
}

void NormalizeDispatched(benchmark::State& state) {
  KernelArrays& k = kernel_arrays();
  run_dispatched(state, [&] { k.normalize(); });
}
void NormalizeGlmDualquat(benchmark::State& state) {
  KernelArrays& k = kernel_arrays();
  const std::vector<glm::dualquat> q = to_glm(k.dq_scaled);
  run_peer<glm::dualquat>(
      state, [&](std::size_t i) { return glm::normalize(q[i]); }, [&] { k.normalize(); },
      [&](std::size_t i, const glm::dualquat& g) { return approx_equal(glm_interop::from_glm(g), k.result(i), 1e-5f); });
}

void DlbDispatched(benchmark::State& state) {
  KernelArrays& k = kernel_arrays();
  run_dispatched(state, [&] { k.dlb(); });
}
/// What GLM users write for DLB: glm::lerp (the sign-aligned blend, unnormalized) then
/// glm::normalize (a division by |q_r|, which leaves q_r · q_d ≠ 0: checked on the transform).
void DlbGlmDualquat(benchmark::State& state) {
  KernelArrays& k = kernel_arrays();
  const std::vector<glm::dualquat> a = to_glm(k.dq_a), b = to_glm(k.dq_b);
  run_peer<glm::dualquat>(
      state, [&](std::size_t i) { return glm::normalize(glm::lerp(a[i], b[i], kBlendT)); },
      [&] { k.dlb(); },
      [&](std::size_t i, const glm::dualquat& g) { return same_transform(g, k.result(i), 1e-5); });
}

void SclerpDispatched(benchmark::State& state) {
  KernelArrays& k = kernel_arrays();
  run_dispatched(state, [&] { k.sclerp(); });
}
/// Neither peer has sclerp: dqkit's own scalar dq::sclerp, element by element (AoS).
void SclerpScalar(benchmark::State& state) {
  KernelArrays& k = kernel_arrays();
  run_peer<DualQuaternion<float>>(
      state, [&](std::size_t i) { return sclerp(k.dq_a[i], k.dq_b[i], kBlendT); },
      [&] { k.sclerp(); },
      [&](std::size_t i, const DualQuaternion<float>& q) { return approx_equal(q, k.result(i), 1e-5f * (1 + norm(q.translation()))); });
}

// ---- compose and transform points in double ---------------------------------------------------------
// The kernels in double against the scalar functions element by element (DualQuaternion<double>,
// arrays of structures: what a user of dqkit's types writes, and what NumPy float64 rows ran before
// the kernels) and Eigen's Isometry3d, hot in cache (4096 elements).

void ComposeDoubleDispatched(benchmark::State& state) {
  KernelArrays& k = kernel_arrays();
  run_dispatched(state, [&] { k.compose_double(); });
}
void ComposeDoubleRecordsDispatched(benchmark::State& state) {
  KernelArrays& k = kernel_arrays();
  run_dispatched(state, [&] { k.compose_records_double(); });
}
void ComposeDoubleScalar(benchmark::State& state) {
  KernelArrays& k = kernel_arrays();
  run_peer<DualQuaternion<double>>(
      state, [&](std::size_t i) { return k.dq_a_double[i] * k.dq_b_double[i]; }, [&] { k.compose_double(); },
      [&](std::size_t i, const DualQuaternion<double>& q) { return approx_equal(q, k.result_double(i), 1e-12); });
}
void ComposeDoubleEigenIsometry3d(benchmark::State& state) {
  KernelArrays& k = kernel_arrays();
  std::vector<Eigen::Isometry3d> a, b;
  for (std::size_t i = 0; i < KernelArrays::n; ++i) a.push_back(eigen::to_isometry(k.dq_a_double[i])), b.push_back(eigen::to_isometry(k.dq_b_double[i]));
  run_peer<Eigen::Isometry3d>(
      state, [&](std::size_t i) { return a[i] * b[i]; }, [&] { k.compose_double(); },
      [&](std::size_t i, const Eigen::Isometry3d& m) { return same_transform(m, k.result_double(i), 1e-12); });
}
void TransformPointsDoubleDispatched(benchmark::State& state) {
  KernelArrays& k = kernel_arrays();
  run_dispatched(state, [&] { k.points_double(); });
}
void TransformPointsDoubleRecordsDispatched(benchmark::State& state) {
  KernelArrays& k = kernel_arrays();
  run_dispatched(state, [&] { k.points_records_double(); });
}
void TransformPointsDoubleScalar(benchmark::State& state) {
  KernelArrays& k = kernel_arrays();
  std::vector<Vec3<double>> p;
  for (std::size_t i = 0; i < KernelArrays::n; ++i) p.push_back(k.point_double(i));
  run_peer<Vec3<double>>(
      state, [&](std::size_t i) { return k.dq_a_double[i].transform_point(p[i]); }, [&] { k.points_double(); },
      [&](std::size_t i, const Vec3<double>& x) { return norm(x - k.moved_point_double(i)) <= 1e-12 * (1 + norm(x)); });
}
void TransformPointsDoubleEigenIsometry3d(benchmark::State& state) {
  KernelArrays& k = kernel_arrays();
  std::vector<Eigen::Isometry3d> m;
  std::vector<Eigen::Vector3d> p;
  for (std::size_t i = 0; i < KernelArrays::n; ++i) {
    const Vec3<double> x = k.point_double(i);
    m.push_back(eigen::to_isometry(k.dq_a_double[i])), p.emplace_back(x.x, x.y, x.z);
  }
  run_peer<Eigen::Vector3d>(
      state, [&](std::size_t i) -> Eigen::Vector3d { return m[i] * p[i]; }, [&] { k.points_double(); },
      [&](std::size_t i, const Eigen::Vector3d& x) {
        const Vec3<double> want = k.moved_point_double(i);
        return (x - Eigen::Vector3d(want.x, want.y, want.z)).norm() <= 1e-12 * (1 + x.norm());
      });
}

// ---- layout conversions ---------------------------------------------------------------------------------
// The layout conversions, against the loops users write: each element's eight floats to or from
// the eight arrays, component by component.
void ToRowsDispatched(benchmark::State& state) {
  KernelArrays& k = kernel_arrays();
  run_dispatched(state, [&] { k.to_rows(); });
}
void ToRowsLoop(benchmark::State& state) {
  KernelArrays& k = kernel_arrays();
  ComponentArrays<float, 8> out(KernelArrays::n);
  for (auto _ : state) {
    for (std::size_t i = 0; i < KernelArrays::n; ++i) {
      const DualQuaternion<float>& q = k.dq_a[i];
      out[0][i] = q.real.w, out[1][i] = q.real.x, out[2][i] = q.real.y, out[3][i] = q.real.z;
      out[4][i] = q.dual.w, out[5][i] = q.dual.x, out[6][i] = q.dual.y, out[7][i] = q.dual.z;
    }
    benchmark::DoNotOptimize(out[0].data());
    benchmark::ClobberMemory();
  }
  k.to_rows();
  for (std::size_t c = 0; c < 8; ++c)
    if (!std::equal(out[c].begin(), out[c].end(), k.out[c].begin())) return state.SkipWithError("the loop and dqkit's conversion disagree");
  state.counters["per_s"] = benchmark::Counter(static_cast<double>(state.iterations() * KernelArrays::n), benchmark::Counter::kIsRate);
}
void FromRowsDispatched(benchmark::State& state) {
  KernelArrays& k = kernel_arrays();
  run_dispatched(state, [&] { k.from_rows(); });
}
void FromRowsLoop(benchmark::State& state) {
  KernelArrays& k = kernel_arrays();
  run_peer<DualQuaternion<float>>(
      state, [&](std::size_t i) { return DualQuaternion<float>(k.a[0][i], k.a[1][i], k.a[2][i], k.a[3][i], k.a[4][i], k.a[5][i], k.a[6][i], k.a[7][i]); },
      [&] { k.from_rows(); }, [&](std::size_t i, const DualQuaternion<float>& q) { return q == k.dq_out[i]; });
}

/// The conversions over arrays of 4 × LLC (the DRAM Arrays): 32 bytes read and 32 written per
/// dual quaternion, reported as a fraction of the copy roofline. Argument 0: to_rows, from the
/// array of values to the component arrays; 1: from_rows, back into a second array of values.
void RowsDram(benchmark::State& state) {
  Arrays& a = arrays(dram_floats() / 8);
  const std::size_t n = a.dq.size();
  const bool to = state.range(0) == 0;
  std::vector<DualQuaternion<float>> values(to ? 0 : n, DualQuaternion<float>());  // filled before timing
  const auto convert = [&] {
    if (to)
      simd::to_rows(a.dq, simd::rows(a.o8));
    else
      simd::from_rows(simd::rows(std::as_const(a.c)), values);
  };
  state.SetLabel(std::string(simd::to_string(simd::current_target())));
  convert();  // untimed: see warm_up_note
  for (auto _ : state) {
    convert();
    benchmark::ClobberMemory();
  }
  // Checked once: every 97th element, bit for bit.
  for (std::size_t i = 0; i < n; i += 97) {
    float q[8];
    for (std::size_t c = 0; c < 8; ++c) q[c] = to ? a.o8[c][i] : a.c[c][i];
    if (std::memcmp(q, to ? &a.dq[i] : &values[i], sizeof q) != 0) return state.SkipWithError("the conversion changed a value");
  }
  state.counters["per_s"] = benchmark::Counter(static_cast<double>(state.iterations() * n), benchmark::Counter::kIsRate);
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations() * n * 64));
  if (copy_bandwidth() > 0)
    state.counters["roofline"] = benchmark::Counter(static_cast<double>(state.iterations() * n * 64) / copy_bandwidth(), benchmark::Counter::kIsRate);
}

/// A dispatched kernel on the hot arrays with the instruction set forced (simd::ScopedTarget): what
/// each target brings, measured in one run. Registered in main for every target this CPU has.
void OnTarget(benchmark::State& state, void (KernelArrays::*kernel)(), simd::Target target) {
  KernelArrays& k = kernel_arrays();
  const simd::ScopedTarget scope(target);
  run_dispatched(state, [&] { (k.*kernel)(); });
}
void register_on_target() {
  const std::pair<const char*, void (KernelArrays::*)()> kernels[] = {
      {"compose", &KernelArrays::compose},         {"inverse", &KernelArrays::inverse},     {"transform_points", &KernelArrays::points},
      {"transform_directions", &KernelArrays::directions}, {"to_matrices", &KernelArrays::to_matrices}, {"normalize", &KernelArrays::normalize},
      {"slerp", &KernelArrays::slerp},             {"dlb", &KernelArrays::dlb},             {"sclerp", &KernelArrays::sclerp},
      {"to_rows", &KernelArrays::to_rows},         {"from_rows", &KernelArrays::from_rows},
      {"to_rows_points", &KernelArrays::to_rows_points}, {"from_rows_points", &KernelArrays::from_rows_points},
      {"local_to_model_frames", &KernelArrays::frames}, {"local_to_model_frames_double", &KernelArrays::frames_double},
      {"compose_double", &KernelArrays::compose_double}, {"transform_points_double", &KernelArrays::points_double},
      {"point_cloud_double", &KernelArrays::cloud_double_moved}, {"compose_records", &KernelArrays::compose_records},
      {"transform_points_records", &KernelArrays::points_records}, {"compose_records_double", &KernelArrays::compose_records_double},
      {"transform_points_records_double", &KernelArrays::points_records_double}};
  for (const auto& [name, kernel] : kernels)
    for (simd::Target target : simd::available_targets())
      benchmark::RegisterBenchmark(("OnTarget/" + std::string(name) + "/" + std::string(simd::to_string(target))).c_str(), OnTarget, kernel, target);
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::AddCustomContext("cpu_model", bench::cpu_model());
  bench::add_cache_context();
  benchmark::AddCustomContext("simd_target", std::string(simd::to_string(simd::best_target())));
  benchmark::Initialize(&argc, argv);
  register_on_target();
  // The roof: a quick copy measurement before the registered cases (the Copy case reports it too).
  copy_bandwidth() = bench::measure_bandwidth(bench::Stream::copy, 1);
  benchmark::AddCustomContext("copy_GBps_1thread", std::to_string(copy_bandwidth() / 1e9));
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}

BENCHMARK(Copy)->Arg(1)->Arg(2)->UseRealTime();
BENCHMARK(Triad)->Arg(1)->Arg(2)->UseRealTime();
BENCHMARK(PeakFma);
BENCHMARK(FkDispatched)->Args({10'000, 1})->Args({10'000, 2})->Args({100'000, 1})->Args({100'000, 2})->UseRealTime();
BENCHMARK(FkBlocksDispatched)->Args({10'000, 1})->Args({10'000, 2})->Args({100'000, 1})->Args({100'000, 2})->UseRealTime();
BENCHMARK(FkBlocksStreaming)->Args({10'000, 1})->Args({10'000, 2})->Args({100'000, 1})->Args({100'000, 2})->UseRealTime();
BENCHMARK(FkScalarJob)->Arg(10'000)->Arg(100'000)->UseRealTime();
BENCHMARK(FkEigenPerPose<Eigen::Isometry3f>)->Name("FkEigenPerPose")->Arg(10'000)->UseRealTime();
BENCHMARK(FkEigenPerPose<Eigen::Matrix4f>)->Name("FkEigenMatrix4fPerPose")->Arg(10'000)->UseRealTime();
BENCHMARK(FkOneSkeletonDualQuaternion);
BENCHMARK(FkFramesDispatched<float>)->Name("FkFramesDispatched")->Args({1024, 1})->Args({100'000, 1})->Args({100'000, 2})->UseRealTime();
BENCHMARK(FkFramesPerFrame<float>)->Name("FkFramesPerFrame")->Arg(1024)->UseRealTime();
BENCHMARK(FkFramesDispatched<double>)->Name("FkFramesDoubleDispatched")->Args({1024, 1})->Args({100'000, 1})->Args({100'000, 2})->UseRealTime();
BENCHMARK(FkFramesPerFrame<double>)->Name("FkFramesDoublePerFrame")->Arg(1024)->UseRealTime();
BENCHMARK(FkFramesEigenIsometry3d)->Arg(1024)->UseRealTime();
BENCHMARK(FkOneSkeletonEigen<Eigen::Isometry3f>)->Name("FkOneSkeletonEigenIsometry3f");
BENCHMARK(FkOneSkeletonEigen<Eigen::Matrix4f>)->Name("FkOneSkeletonEigenMatrix4f");
BENCHMARK(TransformPointsDispatched)->Arg(0)->Arg(1);
BENCHMARK(TransformPointsEigenIsometry3f)->Arg(0)->Arg(1);
BENCHMARK(PointCloudDispatched)->Arg(0)->Arg(1)->UseRealTime();
BENCHMARK(PointCloudScalar)->Arg(0)->Arg(1)->UseRealTime();
BENCHMARK(PointCloudEigenIsometry3f)->Arg(0)->Arg(1)->UseRealTime();
BENCHMARK(PointCloudEigenMatrix3Xf)->Arg(0)->Arg(1)->UseRealTime();
BENCHMARK(PointCloudGlmMat4)->Arg(0)->Arg(1)->UseRealTime();
BENCHMARK(SlerpDispatched);
BENCHMARK(SlerpEigen);
BENCHMARK(ComposeDispatched)->Arg(0)->Arg(1);
BENCHMARK(ComposeGlmDualquat)->Arg(0)->Arg(1);
BENCHMARK(ComposeEigen<Eigen::Isometry3f>)->Name("ComposeEigenIsometry3f")->Arg(0)->Arg(1);
BENCHMARK(ComposeEigen<Eigen::Matrix4f>)->Name("ComposeEigenMatrix4f")->Arg(0)->Arg(1);
BENCHMARK(ComposeDoubleDispatched);
BENCHMARK(ComposeDoubleRecordsDispatched);
BENCHMARK(ComposeDoubleScalar);
BENCHMARK(ComposeDoubleEigenIsometry3d);
BENCHMARK(TransformPointsDoubleDispatched);
BENCHMARK(TransformPointsDoubleRecordsDispatched);
BENCHMARK(TransformPointsDoubleScalar);
BENCHMARK(TransformPointsDoubleEigenIsometry3d);
BENCHMARK(InverseDispatched);
BENCHMARK(InverseGlmDualquat);
BENCHMARK(TransformDirectionsDispatched);
BENCHMARK(TransformDirectionsGlmMat4);
BENCHMARK(TransformDirectionsEigenIsometry3f);
BENCHMARK(ToMatricesDispatched);
BENCHMARK(ToMatricesGlmDualquat);
BENCHMARK(NormalizeDispatched);
BENCHMARK(NormalizeGlmDualquat);
BENCHMARK(DlbDispatched);
BENCHMARK(DlbGlmDualquat);
BENCHMARK(SclerpDispatched);
BENCHMARK(SclerpScalar);
BENCHMARK(ToRowsDispatched);
BENCHMARK(ToRowsLoop);
BENCHMARK(FromRowsDispatched);
BENCHMARK(FromRowsLoop);
BENCHMARK(RowsDram)->Arg(0)->Arg(1)->UseRealTime();

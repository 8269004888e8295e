// Timings of the core operations, with the peers in the same binary: composing rigid transforms
// (Kenwright's "dual quaternions are about 10% faster than matrices"), transforming points, and
// interpolating. Each case runs over arrays of 1024 random inputs so nothing folds at compile time.
//   build/release/bench/bench_core --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>

#include <Eigen/Geometry>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtx/dual_quaternion.hpp>
#include <random>
#include <vector>

#include "dq/dq.hpp"
#include "dq/interop/eigen.hpp"
#include "dq/interop/glm.hpp"
#include "agreement.hpp"

namespace {

using dq::bench::same_transform;

constexpr std::size_t kCount = 1024;

template <class T>
std::vector<dq::DualQuaternion<T>> random_transforms(unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g;
  std::vector<dq::DualQuaternion<T>> out;
  for (std::size_t i = 0; i < kCount; ++i) {
    const dq::Quaternion<T> r = dq::Quaternion<T>(T(g(rng)), T(g(rng)), T(g(rng)), T(g(rng))).normalized();
    out.push_back(dq::DualQuaternion<T>::from_rotation_translation(r, {T(g(rng)), T(g(rng)), T(g(rng))}));
  }
  return out;
}

/// Points made once, outside the timing, so that every case times the transform alone.
template <class T>
std::vector<dq::Vec3<T>> random_points(unsigned seed) {
  std::vector<dq::Vec3<T>> out;
  for (const auto& x : random_transforms<T>(seed)) out.push_back(x.translation());
  return out;
}

/// Checks once, outside the timing, that out[i] is a[i] · b[i] as dqkit computes it in double
/// (translations of about unit size: 1e-4 is float rounding with room, far below any error).
template <class T, class M>
void check_products(benchmark::State& state, const std::vector<dq::DualQuaternion<T>>& a, const std::vector<dq::DualQuaternion<T>>& b,
                    const std::vector<M>& out) {
  for (std::size_t i = 0; i < kCount; ++i)
    if (!same_transform(out[i], a[i].template cast<double>() * b[i].template cast<double>(), 1e-4))
      return state.SkipWithError("a product differs from the reference");
}

// ---- composition: out[i] = a[i] * b[i] -----------------------------------------------------------
template <class T>
void ComposeDualQuaternion(benchmark::State& state) {
  const auto a = random_transforms<T>(1), b = random_transforms<T>(2);
  std::vector<dq::DualQuaternion<T>> out(kCount);
  for (auto _ : state) {
    for (std::size_t i = 0; i < kCount; ++i) out[i] = a[i] * b[i];
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  check_products(state, a, b, out);
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * kCount));
}
/// A peer's product of each pair, converted once by `make`. Eigen's matrices are assigned with
/// noalias(), Eigen's documented form for a product into another matrix: a plain assignment first
/// evaluates into a temporary and copies it, which with -mavx2 -mfma GCC 12 does as 16-byte stores
/// read back by 32-byte loads, a failed store forwarding per product.
template <class M, class T, class Make>
void ComposeMatrices(benchmark::State& state, Make make) {
  const auto qa = random_transforms<T>(1), qb = random_transforms<T>(2);
  std::vector<M> a, b, out(kCount);
  for (std::size_t i = 0; i < kCount; ++i) {
    a.push_back(make(qa[i]));
    b.push_back(make(qb[i]));
  }
  for (auto _ : state) {
    for (std::size_t i = 0; i < kCount; ++i) {
      if constexpr (requires { out[i].noalias() = a[i] * b[i]; })
        out[i].noalias() = a[i] * b[i];
      else
        out[i] = a[i] * b[i];
    }
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  check_products(state, qa, qb, out);
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * kCount));
}
template <class T>
void ComposeDqkitMat4(benchmark::State& s) {
  ComposeMatrices<dq::Mat4<T>, T>(s, [](const auto& q) { return dq::to_mat4(q); });
}
template <class T>
void ComposeDqkitMat34(benchmark::State& state) {
  const auto qa = random_transforms<T>(1), qb = random_transforms<T>(2);
  std::vector<dq::Mat34<T>> a, b, out(kCount);
  for (std::size_t i = 0; i < kCount; ++i) {
    a.push_back(dq::to_mat34(qa[i]));
    b.push_back(dq::to_mat34(qb[i]));
  }
  for (auto _ : state) {
    for (std::size_t i = 0; i < kCount; ++i) out[i] = dq::compose(a[i], b[i]);
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  check_products(state, qa, qb, out);
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * kCount));
}
template <class T>
void ComposeEigenIsometry(benchmark::State& s) {
  ComposeMatrices<Eigen::Transform<T, 3, Eigen::Isometry>, T>(s, [](const auto& q) { return dq::eigen::to_isometry(q); });
}
template <class T>
void ComposeEigenMatrix4(benchmark::State& s) {
  ComposeMatrices<Eigen::Matrix<T, 4, 4>, T>(s, [](const auto& q) { return dq::eigen::to_eigen(dq::to_mat4(q)); });
}
template <class T>
void ComposeGlmMat4(benchmark::State& s) {
  ComposeMatrices<glm::mat<4, 4, T>, T>(s, [](const auto& q) { return dq::glm_interop::to_glm(dq::to_mat4(q)); });
}
template <class T>
void ComposeGlmDualquat(benchmark::State& s) {
  ComposeMatrices<glm::tdualquat<T>, T>(s, [](const auto& q) { return dq::glm_interop::to_glm(q); });
}

// ---- composition as a latency chain, each product waiting for the one before ---------------------
/// Which operand carries the chain: x = x * a[i] appends a child transform (forward kinematics
/// from the root); x = a[i] * x prepends a parent (from a leaf towards the root). A product's
/// operands enter it differently (a matrix product broadcasts the right operand's elements, the
/// four-lane Hamilton product the left's), so the two chains cost different amounts.
enum class Chained { left, right };
/// How a chain assigns each product: as users write it, x = x * a[i]; or, for Eigen, into a second
/// matrix with noalias() and back (y = x * a[i], x = y * a[i + 1]), which skips the temporary that
/// Eigen's plain assignment evaluates the product into (an aliasing product needs one).
enum class Assign { plain, two_buffers };
/// The chain's result of each representation is checked once outside the timing against the
/// dual-quaternion chain computed in double (the same work, the same result).
template <class M, Chained side = Chained::left, Assign assign = Assign::plain, class Make>
void ComposeChain(benchmark::State& state, Make make) {
  const auto q = random_transforms<float>(7);
  std::vector<M> a;
  for (const auto& x : q) a.push_back(make(x));
  const auto step = [](const auto& x, const auto& next) { return side == Chained::left ? x * next : next * x; };
  auto chain = [&a, &step] {
    M x = a[0];
    std::size_t i = 1;
    if constexpr (assign == Assign::two_buffers) {
      M y;
      for (; i + 1 < kCount; i += 2) {
        y.noalias() = step(x, a[i]);
        x.noalias() = step(y, a[i + 1]);
      }
    }
    for (; i < kCount; ++i) x = step(x, a[i]);
    return x;
  };
  dq::DualQuaternion<double> reference = q[0].template cast<double>();
  for (std::size_t i = 1; i < kCount; ++i) reference = step(reference, q[i].template cast<double>());
  if (!same_transform(chain(), reference, 1e-2)) state.SkipWithError("the chain's result differs from the reference");
  benchmark::DoNotOptimize(a.data());  // the inputs escape: the chain cannot be hoisted out of the timing loop
  for (auto _ : state) benchmark::DoNotOptimize(chain());
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * (kCount - 1)));
}
template <Chained side>
void ChainDualQuaternion(benchmark::State& s) {
  ComposeChain<dq::DualQuaternion<float>, side>(s, [](const auto& q) { return q; });
}
template <Chained side>
void ChainGlmDualquat(benchmark::State& s) {
  ComposeChain<glm::dualquat, side>(s, [](const auto& q) { return dq::glm_interop::to_glm(q); });
}
template <Chained side>
void ChainGlmMat4(benchmark::State& s) {
  ComposeChain<glm::mat4, side>(s, [](const auto& q) { return dq::glm_interop::to_glm(dq::to_mat4(q)); });
}
template <Chained side, Assign assign>
void ChainEigenMatrix4(benchmark::State& s) {
  ComposeChain<Eigen::Matrix4f, side, assign>(s, [](const auto& q) { return dq::eigen::to_eigen(dq::to_mat4(q)); });
}

// ---- transforming points: out[i] = T[i] p[i] -----------------------------------------------------
template <class T, class Apply>
void TransformPoints(benchmark::State& state, Apply apply) {
  const auto q = random_transforms<T>(3);
  const auto pts = random_points<T>(4);
  std::vector<dq::Vec3<T>> out(kCount);
  for (auto _ : state) {
    for (std::size_t i = 0; i < kCount; ++i) out[i] = apply(q[i], pts[i]);
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * kCount));
}
void PointDualQuaternion(benchmark::State& s) {
  TransformPoints<float>(s, [](const auto& q, const auto& p) { return q.transform_point(p); });
}
void PointDualQuaternionSandwich(benchmark::State& s) {
  TransformPoints<float>(s, [](const auto& q, const auto& p) { return q.transform_point_sandwich(p); });
}
void PointMat34(benchmark::State& state) {
  const auto q = random_transforms<float>(3);
  const auto pts = random_points<float>(4);
  std::vector<dq::Mat34<float>> m;
  for (const auto& x : q) m.push_back(dq::to_mat34(x));
  std::vector<dq::Vec3<float>> out(kCount);
  for (auto _ : state) {
    for (std::size_t i = 0; i < kCount; ++i) out[i] = dq::transform_point(m[i], pts[i]);
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * kCount));
}

/// A peer's point transform over the same transforms and points, checked once against dqkit's.
template <class M, class P, class Make, class MakePoint, class Apply, class Read>
void TransformPointsPeer(benchmark::State& state, Make make, MakePoint make_point, Apply apply, Read read) {
  const auto q = random_transforms<float>(3);
  const auto pts = random_points<float>(4);
  std::vector<M> m;
  std::vector<P> p, out(kCount);
  for (std::size_t i = 0; i < kCount; ++i) m.push_back(make(q[i])), p.push_back(make_point(pts[i]));
  for (std::size_t i = 0; i < kCount; ++i)
    if (!(dq::norm(read(apply(m[i], p[i])) - q[i].transform_point(pts[i])) < 1e-4f)) {
      state.SkipWithError("the peer's point differs from dqkit's");
      break;
    }
  for (auto _ : state) {
    for (std::size_t i = 0; i < kCount; ++i) out[i] = apply(m[i], p[i]);
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * kCount));
}
void PointEigenIsometry(benchmark::State& s) {
  TransformPointsPeer<Eigen::Isometry3f, Eigen::Vector3f>(
      s, [](const auto& q) { return dq::eigen::to_isometry(q); }, [](const auto& v) { return Eigen::Vector3f(v.x, v.y, v.z); },
      [](const Eigen::Isometry3f& m, const Eigen::Vector3f& v) -> Eigen::Vector3f { return m * v; },
      [](const Eigen::Vector3f& v) { return dq::Vec3<float>{v.x(), v.y(), v.z()}; });
}
void PointGlmMat4(benchmark::State& s) {
  TransformPointsPeer<glm::mat4, glm::vec4>(
      s, [](const auto& q) { return dq::glm_interop::to_glm(dq::to_mat4(q)); }, [](const auto& v) { return glm::vec4(v.x, v.y, v.z, 1); },
      [](const glm::mat4& m, const glm::vec4& v) { return m * v; }, [](const glm::vec4& v) { return dq::Vec3<float>{v.x, v.y, v.z}; });
}
void PointGlmDualquat(benchmark::State& s) {
  TransformPointsPeer<glm::dualquat, glm::vec3>(
      s, [](const auto& q) { return dq::glm_interop::to_glm(q); }, [](const auto& v) { return glm::vec3(v.x, v.y, v.z); },
      [](const glm::dualquat& m, const glm::vec3& v) { return m * v; }, [](const glm::vec3& v) { return dq::Vec3<float>{v.x, v.y, v.z}; });
}

// ---- interpolation ---------------------------------------------------------------------------------
/// slerp over 1024 random pairs, the inputs converted once to the library's type by `make`; each
/// result, read back by `read`, is checked once against dqkit's slerp in double (every library
/// takes the shorter arc, so the rotations agree; q and −q are the same rotation).
template <class Q, class Make, class Slerp, class Read>
void SlerpWith(benchmark::State& state, Make make, Slerp slerp, Read read) {
  const auto a = random_transforms<float>(5), b = random_transforms<float>(6);
  std::vector<Q> qa, qb, out(kCount);
  for (std::size_t i = 0; i < kCount; ++i) {
    qa.push_back(make(a[i].real));
    qb.push_back(make(b[i].real));
  }
  for (auto _ : state) {
    for (std::size_t i = 0; i < kCount; ++i) out[i] = slerp(qa[i], qb[i], 0.3f);
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  for (std::size_t i = 0; i < kCount; ++i) {
    const dq::Quaternion<double> expected = dq::slerp(a[i].real.cast<double>(), b[i].real.cast<double>(), 0.3);
    if (!dq::approx_equal(read(out[i]).template cast<double>(), expected, 1e-5, dq::SignPolicy::same_rotation))
      return state.SkipWithError("a slerp differs from the reference");
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * kCount));
}
void SlerpDqkit(benchmark::State& s) {
  SlerpWith<dq::Quaternion<float>>(s, [](const auto& q) { return q; },
                                   [](const auto& x, const auto& y, float t) { return dq::slerp(x, y, t); }, [](const auto& q) { return q; });
}
void SlerpEigen(benchmark::State& s) {
  SlerpWith<Eigen::Quaternionf>(s, [](const auto& q) { return dq::eigen::to_eigen(q); },
                                [](const auto& x, const auto& y, float t) { return x.slerp(t, y); },
                                [](const Eigen::Quaternionf& q) { return dq::eigen::from_eigen(q); });
}
void SlerpGlm(benchmark::State& s) {
  SlerpWith<glm::quat>(s, [](const auto& q) { return dq::glm_interop::to_glm(q); },
                       [](const auto& x, const auto& y, float t) { return glm::slerp(x, y, t); },
                       [](const glm::quat& q) { return dq::glm_interop::from_glm(q); });
}
void SclerpDqkit(benchmark::State& state) {
  const auto a = random_transforms<float>(5), b = random_transforms<float>(6);
  std::vector<dq::DualQuaternion<float>> out(kCount);
  for (auto _ : state) {
    for (std::size_t i = 0; i < kCount; ++i) out[i] = dq::sclerp(a[i], b[i], 0.3f);
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * kCount));
}

}  // namespace

BENCHMARK(ComposeDualQuaternion<float>);
BENCHMARK(ComposeDqkitMat4<float>);
BENCHMARK(ComposeDqkitMat34<float>);
BENCHMARK(ComposeEigenIsometry<float>);
BENCHMARK(ComposeEigenMatrix4<float>);
BENCHMARK(ComposeGlmMat4<float>);
BENCHMARK(ComposeGlmDualquat<float>);
BENCHMARK(ComposeDualQuaternion<double>);
BENCHMARK(ComposeEigenIsometry<double>);
BENCHMARK(ComposeGlmMat4<double>);
BENCHMARK(ChainDualQuaternion<Chained::left>)->Name("ChainDualQuaternion");
BENCHMARK(ChainGlmDualquat<Chained::left>)->Name("ChainGlmDualquat");
BENCHMARK(ChainGlmMat4<Chained::left>)->Name("ChainGlmMat4");
BENCHMARK(ChainEigenMatrix4<Chained::left, Assign::plain>)->Name("ChainEigenMatrix4");
BENCHMARK(ChainEigenMatrix4<Chained::left, Assign::two_buffers>)->Name("ChainEigenMatrix4TwoBuffers");
BENCHMARK(ChainDualQuaternion<Chained::right>)->Name("PrependChainDualQuaternion");
BENCHMARK(ChainGlmDualquat<Chained::right>)->Name("PrependChainGlmDualquat");
BENCHMARK(ChainGlmMat4<Chained::right>)->Name("PrependChainGlmMat4");
BENCHMARK(ChainEigenMatrix4<Chained::right, Assign::plain>)->Name("PrependChainEigenMatrix4");
BENCHMARK(ChainEigenMatrix4<Chained::right, Assign::two_buffers>)->Name("PrependChainEigenMatrix4TwoBuffers");
BENCHMARK(PointDualQuaternion);
BENCHMARK(PointDualQuaternionSandwich);
BENCHMARK(PointMat34);
BENCHMARK(PointEigenIsometry);
BENCHMARK(PointGlmMat4);
BENCHMARK(PointGlmDualquat);
BENCHMARK(SlerpDqkit);
BENCHMARK(SlerpEigen);
BENCHMARK(SlerpGlm);
BENCHMARK(SclerpDqkit);
BENCHMARK_MAIN();

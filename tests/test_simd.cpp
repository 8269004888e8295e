// The run-time dispatched batch kernels (dq/simd/batch.hpp), every instruction set this CPU has,
// against the scalar types: bit for bit (the same operations in the same order, no FMA).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <utility>
#include <vector>

#include "dq/simd/batch.hpp"
#include "support.hpp"

namespace {

using namespace dq;
using simd::Target;

/// Eight random component arrays of n unit dual quaternions.
struct Batch {
  std::vector<float> c[8];
  explicit Batch(std::size_t n, unsigned seed) {
    test::Random rng(seed);
    for (auto& v : c) v.resize(n);
    for (std::size_t i = 0; i < n; ++i) set(i, rng.rigid<float>(5));
  }
  void set(std::size_t i, const DualQuaternion<float>& q) {
    const float v[8] = {q.real.w, q.real.x, q.real.y, q.real.z, q.dual.w, q.dual.x, q.dual.y, q.dual.z};
    for (int k = 0; k < 8; ++k) c[k][i] = v[k];
  }
  DualQuaternion<float> get(std::size_t i) const {
    return {c[0][i], c[1][i], c[2][i], c[3][i], c[4][i], c[5][i], c[6][i], c[7][i]};
  }
  simd::ConstRows rows() const {
    return {c[0].data(), c[1].data(), c[2].data(), c[3].data(), c[4].data(), c[5].data(), c[6].data(), c[7].data()};
  }
  simd::Rows rows() {
    return {c[0].data(), c[1].data(), c[2].data(), c[3].data(), c[4].data(), c[5].data(), c[6].data(), c[7].data()};
  }
};

bool same_bits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

/// Every target up to the CPU's best, restoring the best after.
template <class F>
void for_each_target(F f) {
  for (Target t : {Target::scalar, Target::sse2, Target::avx2, Target::avx512}) {
    if (static_cast<int>(t) > static_cast<int>(simd::best_target())) break;
    ASSERT_EQ(simd::use_target(t), t);
    SCOPED_TRACE(std::string(simd::to_string(t)));
    f(t);
  }
  simd::use_target(Target::avx512);
}

TEST(Simd, ComposeIsTheScalarProductBitForBit) {
  const std::size_t n = 1003;  // not a multiple of any width: the tails run too
  const Batch a(n, 1), b(n, 2);
  for_each_target([&](Target) {
    Batch out(n, 3);
    simd::compose(a.rows(), b.rows(), out.rows(), n);
    for (std::size_t i = 0; i < n; ++i) {
      const DualQuaternion<float> want = a.get(i) * b.get(i), got = out.get(i);
      const float* w = &want.real.w;
      const float* g = &got.real.w;
      for (int k = 0; k < 8; ++k) ASSERT_TRUE(same_bits(w[k], g[k])) << i << " component " << k;
    }
    // In place (out is a) is allowed.
    Batch in_place = a;
    simd::compose(std::as_const(in_place).rows(), b.rows(), in_place.rows(), n);
    for (std::size_t i = 0; i < n; ++i) ASSERT_EQ(in_place.get(i), a.get(i) * b.get(i));
  });
}

TEST(Simd, TransformPointsIsTheScalarTransformBitForBit) {
  const std::size_t n = 517;
  const Batch q(n, 4);
  std::vector<float> p[3], out[3];
  test::Random rng(5);
  for (auto& v : p) v.resize(n);
  for (auto& v : out) v.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3<float> x = rng.vec3<float>(10);
    p[0][i] = x.x, p[1][i] = x.y, p[2][i] = x.z;
  }
  for_each_target([&](Target) {
    simd::transform_points(q.rows(), {p[0].data(), p[1].data(), p[2].data()}, {out[0].data(), out[1].data(), out[2].data()}, n);
    for (std::size_t i = 0; i < n; ++i) {
      const Vec3<float> want = q.get(i).transform_point({p[0][i], p[1][i], p[2][i]});
      ASSERT_TRUE(same_bits(want.x, out[0][i]) && same_bits(want.y, out[1][i]) && same_bits(want.z, out[2][i])) << i;
    }
  });
}

TEST(Simd, BatchForwardKinematicsEqualsTheJobBitForBit) {
  const std::vector<int> parents{-1, 0, 1, 1, 3, 0, 5};
  const std::size_t joints = parents.size(), poses = 77;
  DualQuaternionSoAStorage<float> local(joints, poses), expected(joints, poses), got(joints, poses);
  test::Random rng(6);
  for (std::size_t j = 0; j < joints; ++j)
    for (std::size_t p = 0; p < poses; ++p) local.view().set(j, p, rng.rigid<float>(2));
  const ForwardKinematicsJob<float> reference{parents, local.view(), expected.view(), 0, poses};
  reference.run();
  for_each_target([&](Target) {
    const ForwardKinematicsJob<float> job{parents, local.view(), got.view(), 0, poses};
    simd::run(job);
    for (std::size_t j = 0; j < joints; ++j)
      for (std::size_t p = 0; p < poses; ++p) ASSERT_EQ(got.view().get(j, p), expected.view().get(j, p)) << j << " " << p;
  });
}

TEST(Simd, SlerpOverArraysHasNoFailureCaseAndFloatAccuracy) {
  // Random pairs plus the thesis' failure cases: equal endpoints, a few ulps apart, exactly and
  // nearly opposite, off the unit sphere. Reference: dq::slerp in long double. Bound: 16 float
  // ulps per component (about twenty operations of half an ulp each, and series truncated below
  // an ulp), far below what a wrong branch or a division by sin Ω would give.
  test::Random rng(8);
  std::vector<Quaternion<float>> a, b;
  for (int k = 0; k < 1000; ++k) a.push_back(rng.rotation<float>()), b.push_back(rng.rotation<float>());
  const Quaternion<float> q = rng.rotation<float>();
  const Quaternion<float> tiny = Quaternion<float>::from_axis_angle({0.3f, -0.2f, 0.9f}, 1e-6f);
  for (const Quaternion<float>& other : {q, q * tiny, -q, -(q * tiny), q * 1.001f, Quaternion<float>(q.x, -q.w, q.z, -q.y)}) {
    a.push_back(q);
    b.push_back(other);
  }
  const std::size_t n = a.size();
  std::vector<float> in[8], out[4];
  for (auto& v : in) v.resize(n);
  for (auto& v : out) v.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    in[0][i] = a[i].w, in[1][i] = a[i].x, in[2][i] = a[i].y, in[3][i] = a[i].z;
    in[4][i] = b[i].w, in[5][i] = b[i].x, in[6][i] = b[i].y, in[7][i] = b[i].z;
  }
  for (const float t : {0.0f, 0.3f, 0.5f, 1.0f, 1.5f}) {
    for_each_target([&](Target) {
      simd::slerp({in[0].data(), in[1].data(), in[2].data(), in[3].data()}, {in[4].data(), in[5].data(), in[6].data(), in[7].data()}, t,
                  {out[0].data(), out[1].data(), out[2].data(), out[3].data()}, n);
      for (std::size_t i = 0; i < n; ++i) {
        const Quaternion<long double> want = slerp(a[i].cast<long double>(), b[i].cast<long double>(), static_cast<long double>(t));
        const long double got[4] = {out[0][i], out[1][i], out[2][i], out[3][i]}, ref[4] = {want.w, want.x, want.y, want.z};
        for (int k = 0; k < 4; ++k)
          ASSERT_LE(std::abs(got[k] - ref[k]), 16 * std::numeric_limits<float>::epsilon()) << "t " << t << " pair " << i << " component " << k;
      }
    });
  }
}

TEST(Simd, DispatchReportsWhatTheCpuHas) {
  const Target best = simd::best_target();
  RecordProperty("best_target", std::string(simd::to_string(best)));
  EXPECT_EQ(simd::current_target(), best);
#if defined(__x86_64__)
  EXPECT_GE(static_cast<int>(best), static_cast<int>(Target::sse2));  // every x86-64 CPU has SSE2
  EXPECT_EQ(best == Target::avx512, static_cast<bool>(__builtin_cpu_supports("avx512f")));
#endif
  EXPECT_EQ(simd::use_target(Target::scalar), Target::scalar);
  EXPECT_EQ(simd::use_target(Target::avx512), best);
}

}  // namespace

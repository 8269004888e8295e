// The run-time dispatched batch kernels (dq/simd/batch.hpp), every instruction set this CPU has,
// against the scalar types: bit for bit (the same operations in the same order, no FMA), for every
// input and every n (tails, 0, in place); slerp and sclerp, evaluated differently, against the
// scalar functions in long double within documented ulp bounds, on their failure cases too.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <numbers>
#include <span>
#include <stdexcept>
#include <random>
#include <string>
#include <tuple>
#include <type_traits>
#include <utility>
#include <vector>

#include "dq/simd/batch.hpp"
#include "dq/util/component_arrays.hpp"
#include "interpolation_reference.hpp"
#include "simd_targets.hpp"
#include "support.hpp"

namespace {

using namespace dq;
using simd::Target;

/// Eight random component arrays of n unit dual quaternions of S.
template <class S>
struct BatchOf {
  std::vector<S> c[8];
  explicit BatchOf(std::size_t n, unsigned seed) {
    test::Random rng(seed);
    for (auto& v : c) v.resize(n);
    for (std::size_t i = 0; i < n; ++i) set(i, rng.rigid<S>(5));
  }
  explicit BatchOf(const std::vector<DualQuaternion<S>>& qs) {
    for (auto& v : c) v.resize(qs.size());
    for (std::size_t i = 0; i < qs.size(); ++i) set(i, qs[i]);
  }
  std::size_t size() const { return c[0].size(); }
  void set(std::size_t i, const DualQuaternion<S>& q) {
    const S v[8] = {q.real.w, q.real.x, q.real.y, q.real.z, q.dual.w, q.dual.x, q.dual.y, q.dual.z};
    for (int k = 0; k < 8; ++k) c[k][i] = v[k];
  }
  DualQuaternion<S> get(std::size_t i) const {
    return {c[0][i], c[1][i], c[2][i], c[3][i], c[4][i], c[5][i], c[6][i], c[7][i]};
  }
  detail::Row8<const S> rows() const { return detail::row_of<const S>(c, 0); }
  detail::Row8<S> rows() { return detail::row_of<S>(c, 0); }
};
using Batch = BatchOf<float>;

using test::for_each_target;
using test::same_bits;
template <class S>
bool same_bits(const DualQuaternion<S>& a, const DualQuaternion<S>& b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}
template <class S>
bool same_bits(const Vec3<S>& a, const Vec3<S>& b) {
  return same_bits(a.x, b.x) && same_bits(a.y, b.y) && same_bits(a.z, b.z);
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

/// simd::slerp over component arrays made from `a` and `b`, its results as quaternions.
std::vector<Quaternion<float>> batch_slerp(const std::vector<Quaternion<float>>& a, const std::vector<Quaternion<float>>& b, float t) {
  const std::size_t n = a.size();
  std::vector<float> in[8], out[4];
  for (auto& v : in) v.resize(n);
  for (auto& v : out) v.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    in[0][i] = a[i].w, in[1][i] = a[i].x, in[2][i] = a[i].y, in[3][i] = a[i].z;
    in[4][i] = b[i].w, in[5][i] = b[i].x, in[6][i] = b[i].y, in[7][i] = b[i].z;
  }
  simd::slerp({in[0].data(), in[1].data(), in[2].data(), in[3].data()}, {in[4].data(), in[5].data(), in[6].data(), in[7].data()}, t,
              {out[0].data(), out[1].data(), out[2].data(), out[3].data()}, n);
  std::vector<Quaternion<float>> q(n);
  for (std::size_t i = 0; i < n; ++i) q[i] = {out[0][i], out[1][i], out[2][i], out[3][i]};
  return q;
}

TEST(Simd, SlerpOverArraysHasNoFailureCaseAndFloatAccuracy) {
  // Random pairs plus the thesis' failure cases: equal endpoints, a few ulps apart, exactly and
  // nearly opposite, off the unit sphere (to 1e±9). Reference: dq::slerp in long double. Bound:
  // 16 float ulps per component (about twenty operations of half an ulp each, and series
  // truncated below an ulp), far below what a wrong branch or a division by sin Ω would give.
  test::Random rng(8);
  std::vector<Quaternion<float>> a, b;
  for (int k = 0; k < 1000; ++k) a.push_back(rng.rotation<float>()), b.push_back(rng.rotation<float>());
  const Quaternion<float> q = rng.rotation<float>();
  const Quaternion<float> tiny = Quaternion<float>::from_axis_angle({0.3f, -0.2f, 0.9f}, 1e-6f);
  for (const Quaternion<float>& other : {q, q * tiny, -q, -(q * tiny), q * 1.001f, Quaternion<float>(q.x, -q.w, q.z, -q.y)}) {
    a.push_back(q);
    b.push_back(other);
  }
  // Far from unit: norms whose product is 1e18 or 1e-18 (its square still a normal float).
  for (const float scale : {1e9f, 1e-9f}) {
    a.push_back(q * scale);
    b.push_back(rng.rotation<float>() * scale);
  }
  for (const float t : {0.0f, 0.3f, 0.5f, 1.0f, 1.5f}) {
    for_each_target([&](Target) {
      const std::vector<Quaternion<float>> out = batch_slerp(a, b, t);
      for (std::size_t i = 0; i < a.size(); ++i) {
        const Quaternion<long double> want = slerp(a[i].cast<long double>(), b[i].cast<long double>(), static_cast<long double>(t));
        const Quaternion<long double> got = out[i].cast<long double>();
        const long double g[4] = {got.w, got.x, got.y, got.z}, ref[4] = {want.w, want.x, want.y, want.z};
        for (int k = 0; k < 4; ++k)
          ASSERT_LE(std::abs(g[k] - ref[k]), 16 * std::numeric_limits<float>::epsilon()) << "t " << t << " pair " << i << " component " << k;
      }
    });
  }
}

TEST(Simd, SlerpTakesDqSlerpsArcAtExactTies) {
  // b = a·i = (−x, w, z, −y) and two more signed swaps of a's components: a · b is exactly 0 (its
  // products cancel in adjacent pairs), both arcs are equally short, and dq::slerp keeps b as
  // given. The batch kernel must take the same arc (it took the other one for about 1 pair in 140
  // when it decided from a normalized a, whose products no longer cancel exactly). Same arc:
  // within the kernel's 16 ulps of dq::slerp; the other arc is about 1 away.
  test::Random rng(81);
  std::vector<Quaternion<float>> a, b;
  for (int k = 0; k < 400; ++k) {
    const Quaternion<float> q = rng.rotation<float>();
    for (const Quaternion<float>& tie : {q * Quaternion<float>(0, 1, 0, 0), Quaternion<float>(-q.x, q.w, -q.z, q.y), Quaternion<float>(q.x, -q.w, -q.z, q.y)}) {
      a.push_back(q);
      b.push_back(tie);
      ASSERT_EQ(dot(a.back(), b.back()), 0.0f);
    }
  }
  for (const float t : {0.3f, 0.7f}) {
    for_each_target([&](Target) {
      const std::vector<Quaternion<float>> out = batch_slerp(a, b, t);
      for (std::size_t i = 0; i < a.size(); ++i) {
        const Quaternion<float> want = slerp(a[i], b[i], t);
        ASSERT_LE(test::max_abs_diff(out[i], want), 16 * std::numeric_limits<float>::epsilon()) << "t " << t << " pair " << i;
      }
    });
  }
}

// ---- inverse, directions, normalize, dlb, sclerp over arrays ---------------------------------------

/// Sizes that exercise the vector loop and the tails of every width (and none at all).
constexpr std::size_t kSizes[] = {0, 1, 3, 15, 16, 17, 1003};

/// Every k-th element of `qs` (from `offset`) replaced by the special inputs in turn, so that they
/// land in every lane position of every width, surrounded by ordinary lanes.
std::vector<DualQuaternion<float>> sprinkle(std::vector<DualQuaternion<float>> qs, const std::vector<DualQuaternion<float>>& special,
                                            std::size_t k = 5, std::size_t offset = 2) {
  for (std::size_t i = offset, s = 0; i < qs.size(); i += k, ++s) qs[i] = special[s % special.size()];
  return qs;
}

TEST(Simd, InverseIsInverseUnitBitForBit) {
  const Batch q(1003, 11), untouched(1003, 12);
  for_each_target([&](Target) {
    for (const std::size_t n : kSizes) {
      Batch out = untouched;
      simd::inverse(q.rows(), out.rows(), n);
      for (std::size_t i = 0; i < 1003; ++i)  // nothing past n written
        ASSERT_TRUE(same_bits(out.get(i), i < n ? q.get(i).inverse_unit() : untouched.get(i))) << "n " << n << " element " << i;
    }
    // In place; and the unit inverse indeed inverts: q q⁻¹ = identity to rounding.
    Batch in_place = q;
    simd::inverse(std::as_const(in_place).rows(), in_place.rows(), q.size());
    for (std::size_t i = 0; i < q.size(); ++i) {
      ASSERT_TRUE(same_bits(in_place.get(i), q.get(i).conjugate())) << i;
      ASSERT_TRUE(approx_equal(q.get(i) * in_place.get(i), DualQuaternion<float>::identity(), 64 * test::tol<float>(1))) << i;
    }
  });
}

TEST(Simd, TransformDirectionsIsTheScalarTransformBitForBit) {
  const std::size_t n = 517;
  const Batch q(n, 13);
  std::vector<float> v[3], out[3];
  test::Random rng(14);
  for (auto& x : v) x.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3<float> x = rng.vec3<float>(10);
    v[0][i] = x.x, v[1][i] = x.y, v[2][i] = x.z;
  }
  auto want = [&](std::size_t i) { return q.get(i).transform_direction({v[0][i], v[1][i], v[2][i]}); };
  for_each_target([&](Target) {
    for (const std::size_t m : {std::size_t{0}, std::size_t{7}, std::size_t{33}, n}) {
      for (auto& x : out) x.assign(n, -1.0f);
      simd::transform_directions(q.rows(), {v[0].data(), v[1].data(), v[2].data()}, {out[0].data(), out[1].data(), out[2].data()}, m);
      for (std::size_t i = 0; i < n; ++i) {
        const Vec3<float> got{out[0][i], out[1][i], out[2][i]};
        ASSERT_TRUE(same_bits(got, i < m ? want(i) : Vec3<float>{-1, -1, -1})) << "n " << m << " element " << i;
      }
    }
    // In place (out is v); the translation plays no part.
    std::vector<float> w[3] = {v[0], v[1], v[2]};
    simd::transform_directions(q.rows(), {w[0].data(), w[1].data(), w[2].data()}, {w[0].data(), w[1].data(), w[2].data()}, n);
    for (std::size_t i = 0; i < n; ++i) {
      ASSERT_TRUE(same_bits(Vec3<float>{w[0][i], w[1][i], w[2][i]}, want(i))) << i;
      ASSERT_TRUE(same_bits(want(i), q.get(i).real.rotate({v[0][i], v[1][i], v[2][i]}))) << i;
    }
  });
}

TEST(Simd, ToMatricesIsTheScalarConversionBitForBitAndARigidMotion) {
  const std::size_t n = 301;
  const Batch q(n, 15);
  std::vector<float> m[12];
  for_each_target([&](Target) {
    for (const std::size_t count : {std::size_t{0}, std::size_t{17}, n}) {
      for (auto& x : m) x.assign(n, -1.0f);
      std::array<float*, 12> out{};
      for (std::size_t k = 0; k < 12; ++k) out[k] = m[k].data();
      simd::to_matrices(q.rows(), out, count);
      for (std::size_t i = 0; i < n; ++i) {
        const Mat34<float> want = to_mat34(q.get(i));
        for (std::size_t k = 0; k < 12; ++k)
          ASSERT_TRUE(same_bits(m[k][i], i < count ? want.m[k] : -1.0f)) << "n " << count << " element " << i << " entry " << k;
      }
    }
  });
  // Independently of to_mat34: the matrix maps points as the dual quaternion does (column c, row r
  // at m[c · 3 + r]).
  test::Random rng(16);
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3<float> p = rng.vec3<float>(3), want = q.get(i).transform_point_sandwich(p);
    for (std::size_t r = 0; r < 3; ++r) {
      const float got = m[r][i] * p.x + m[3 + r][i] * p.y + m[6 + r][i] * p.z + m[9 + r][i];
      ASSERT_NEAR(got, (&want.x)[r], 1e-4f * (1 + std::abs((&want.x)[r]))) << i << " row " << r;
    }
  }
}

/// Inputs for each branch of DualQuaternion::normalized other than the common one.
std::vector<DualQuaternion<float>> inputs_for_every_branch_of_normalized() {
  const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
  const float tiny = std::numeric_limits<float>::denorm_min(), huge = std::numeric_limits<float>::max();
  const Quaternion<float> r = Quaternion<float>(0.5f, -0.5f, 0.5f, 0.5f), z(0, 0, 0, 0);
  return {
      {z, Quaternion<float>(1, 2, 3, 4)},                     // zero real part: the identity
      {z, z},                                                  // zero: the identity
      {z, Quaternion<float>(nan, 0, 0, 0)},                    // zero real part, NaN dual part: NaN kept
      {r * 1e-20f, Quaternion<float>(0, 1e-20f, 0, 0)},        // |q_r|² below the normal range: rescaled
      {r * (4 * tiny), Quaternion<float>(0, 3 * tiny, 0, 0)},  // denormal real part
      {r * 1e20f, Quaternion<float>(0, 1e20f, 0, 0)},          // |q_r|² overflows: rescaled
      {r * (huge / 2), Quaternion<float>(0, 1, 0, 0)},         // |q_r| itself near the top
      {Quaternion<float>(inf, 0, 0, 0), z},                    // non-finite in, non-finite out
      {Quaternion<float>(nan, 1, 0, 0), z},
      {r, Quaternion<float>(nan, 0, 0, 0)},
      {r, Quaternion<float>(0, inf, 0, 0)},
      {r, r * 3.0f},                                           // dual part along the real part: rebuilt
      {r * 2.0f, r * -1e6f + Quaternion<float>(0, 1e-3f, 0, 0)},
      {r * 0.7f, Quaternion<float>(0, 0, 0, 0)},              // no translation at all
  };
}

/// Random dual quaternions off the unit condition: the real part scaled, the dual part with a
/// component along it (drift, as long chains of float products give); every fourth one with a
/// dual part mostly along the real part (where normalized rebuilds it from the translation).
std::vector<DualQuaternion<float>> drifted(std::size_t n, unsigned seed) {
  test::Random rng(seed);
  std::vector<DualQuaternion<float>> qs;
  for (std::size_t i = 0; i < n; ++i) {
    const DualQuaternion<float> q = rng.rigid<float>(5);
    const float scale = rng.uniform(0.5f, 2.0f), along = rng.uniform(-0.1f, 0.1f);
    if (i % 4 == 0)
      qs.push_back({q.real * scale, q.dual * 1e-4f + q.real * (1000 * along)});
    else
      qs.push_back({q.real * scale, q.dual * scale + q.real * along});
  }
  return qs;
}

/// Whether DualQuaternion::normalized rebuilds q's dual part from the translation (|k| above every
/// component of d − r k), the branch the kernels select per lane.
bool rebuilds_dual_part(const DualQuaternion<float>& q) {
  const float n = q.real.norm();
  const Quaternion<float> r = q.real / n, d = q.dual / n;
  const float k = dot(r, d);
  const Quaternion<float> p = d - r * k;
  return std::abs(k) > std::max({std::abs(p.w), std::abs(p.x), std::abs(p.y), std::abs(p.z)});
}

TEST(Simd, NormalizeIsTheScalarNormalizationBitForBitInEveryLane) {
  // Every element equals DualQuaternion::normalized bit for bit, wherever its inputs fall in a
  // vector: drifted inputs, dual parts along the real part (the rebuilt branch, selected per lane),
  // and zero, tiny, huge and non-finite parts (blocks left to the scalar function).
  const Batch q(sprinkle(drifted(1003, 15), inputs_for_every_branch_of_normalized()));
  std::size_t rebuilt = 0;
  for (std::size_t i = 0; i < q.size(); ++i) rebuilt += rebuilds_dual_part(q.get(i));
  EXPECT_GT(rebuilt, 150u);
  for_each_target([&](Target) {
    for (const std::size_t n : kSizes) {
      Batch out(1003, 16);
      const Batch untouched = out;
      simd::normalize(q.rows(), out.rows(), n);
      for (std::size_t i = 0; i < 1003; ++i)
        ASSERT_TRUE(same_bits(out.get(i), i < n ? q.get(i).normalized() : untouched.get(i))) << "n " << n << " element " << i << " " << q.get(i);
    }
    Batch in_place = q;
    simd::normalize(std::as_const(in_place).rows(), in_place.rows(), q.size());
    for (std::size_t i = 0; i < q.size(); ++i) ASSERT_TRUE(same_bits(in_place.get(i), q.get(i).normalized())) << i;
  });
  // The documented results: a zero real part gives the identity (NaN where the dual part is NaN),
  // finite input is never NaN, and every finite element comes out unit.
  Batch out(1003, 16);
  simd::normalize(q.rows(), out.rows(), q.size());
  std::size_t zero_real = 0;
  for (std::size_t i = 0; i < q.size(); ++i) {
    const DualQuaternion<float> in = q.get(i), u = out.get(i);
    const float* c = &in.real.w;
    const bool finite = std::all_of(c, c + 8, [](float x) { return std::isfinite(x); });
    if (in.real == Quaternion<float>(0, 0, 0, 0)) {
      ++zero_real;
      if (std::isfinite(dot(in.dual, in.dual))) EXPECT_EQ(u, DualQuaternion<float>::identity()) << i;
      else EXPECT_TRUE(std::isnan(u.real.w) && std::isnan(u.dual.w)) << i;
    }
    if (finite) {
      EXPECT_FALSE(std::isnan(u.real.w) || std::isnan(u.dual.x)) << i;
      EXPECT_TRUE(u.is_unit(64 * test::tol<float>(4))) << i << " " << in << " → " << u;
    }
  }
  EXPECT_GT(zero_real, 20u);
  // Drifted inputs alone: no block leaves the lanes (on 16 lanes above, most blocks held a special
  // input and ran the scalar function), so the per-lane choice of the rebuilt dual part is tested.
  const Batch regular(drifted(1003, 19));
  std::size_t regular_rebuilt = 0;
  for (std::size_t i = 0; i < regular.size(); ++i) regular_rebuilt += rebuilds_dual_part(regular.get(i));
  EXPECT_GT(regular_rebuilt, 150u);
  for_each_target([&](Target) {
    Batch normalized(1003, 16);
    simd::normalize(regular.rows(), normalized.rows(), regular.size());
    for (std::size_t i = 0; i < regular.size(); ++i) ASSERT_TRUE(same_bits(normalized.get(i), regular.get(i).normalized())) << i;
  });
}

TEST(Simd, DlbIsTheScalarBlendBitForBit) {
  // Random unit pairs (half with b's real part on the other hemisphere, so the sign is aligned;
  // some blends have their dual part rebuilt by the normalization, selected per lane), then equal
  // and opposite inputs, zero real parts and NaN (blocks left to dq::dlb), a dual part along the
  // real part.
  test::Random rng(17);
  std::vector<DualQuaternion<float>> a, b;
  for (int i = 0; i < 1003; ++i) {
    a.push_back(rng.rigid<float>(5));
    b.push_back(i % 2 ? -rng.rigid<float>(5) : rng.rigid<float>(5));
  }
  const DualQuaternion<float> r = rng.rigid<float>(5), zero{Quaternion<float>(0, 0, 0, 0), Quaternion<float>(0, 0, 0, 0)};
  // The identity written with negative zeros, blended with a translation: at t = −0 the scalar
  // blend keeps the zeros negative (−0 + 0.5 · −0), and so must the lanes' t.
  const DualQuaternion<float> negative_zeros(1.0f, -0.0f, -0.0f, -0.0f, -0.0f, -0.0f, -0.0f, -0.0f), shift(1.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.5f, 0.0f, 0.0f);
  const std::vector<std::pair<DualQuaternion<float>, DualQuaternion<float>>> special{
      {r, r}, {r, -r}, {zero, zero}, {zero, r}, {{r.real, r.real * 2.0f}, {r.real, r.real * 2.0f}},
      {r, {r.real, Quaternion<float>(std::numeric_limits<float>::quiet_NaN(), 0, 0, 0)}}, {negative_zeros, shift}};
  for (std::size_t i = 3, s = 0; i < a.size(); i += 7, ++s) std::tie(a[i], b[i]) = special[s % special.size()];
  const Batch qa(a), qb(b);
  std::size_t rebuilt = 0;  // blends whose normalization rebuilds the dual part, per lane on the vectors
  for (std::size_t i = 0; i < a.size(); ++i) rebuilt += rebuilds_dual_part(a[i] * 0.5f + (dot(a[i].real, b[i].real) < 0 ? -b[i] : b[i]) * 0.5f);
  EXPECT_GT(rebuilt, 20u);
  for (const float t : {0.0f, -0.0f, 0.25f, 0.5f, 0.7f, 1.0f, -0.5f, 1.7f}) {
    for_each_target([&](Target) {
      for (const std::size_t n : kSizes) {
        Batch out(1003, 18);
        const Batch untouched = out;
        simd::dlb(qa.rows(), qb.rows(), t, out.rows(), n);
        for (std::size_t i = 0; i < 1003; ++i)
          ASSERT_TRUE(same_bits(out.get(i), i < n ? dlb(a[i], b[i], t) : untouched.get(i))) << "t " << t << " n " << n << " element " << i;
      }
      // In place: out is a, or out is b.
      Batch into_a = qa, into_b = qb;
      simd::dlb(std::as_const(into_a).rows(), qb.rows(), t, into_a.rows(), a.size());
      simd::dlb(qa.rows(), std::as_const(into_b).rows(), t, into_b.rows(), a.size());
      for (std::size_t i = 0; i < a.size(); ++i) {
        ASSERT_TRUE(same_bits(into_a.get(i), dlb(a[i], b[i], t))) << i;
        ASSERT_TRUE(same_bits(into_b.get(i), dlb(a[i], b[i], t))) << i;
      }
    });
  }
  // Random pairs alone: every block stays on the lanes.
  std::vector<DualQuaternion<float>> ra, rb;
  for (int i = 0; i < 1003; ++i) ra.push_back(rng.rigid<float>(5)), rb.push_back(i % 2 ? -rng.rigid<float>(5) : rng.rigid<float>(5));
  const Batch pa(ra), pb(rb);
  for (const float t : {0.3f, 0.5f}) {
    for_each_target([&](Target) {
      Batch out(1003, 18);
      simd::dlb(pa.rows(), pb.rows(), t, out.rows(), ra.size());
      for (std::size_t i = 0; i < ra.size(); ++i) ASSERT_TRUE(same_bits(out.get(i), dlb(ra[i], rb[i], t))) << "t " << t << " element " << i;
    });
  }
}

/// Pairs for sclerp: random unit dual quaternions, then the failure cases of the textbook formulas
/// (the thesis' slerp cases and their dual-quaternion analogues): identical endpoints, tiny
/// relative rotations (1e-6 and 1e-20 rad), b = −a and −(a·tiny) (antipodal: the same transform),
/// rotations π apart exactly and nearly (π − 1e-3, π − 1e-6), pure translations, equal rotations
/// with different translations, pure rotations, and translations of 1000 whose interpolation
/// passes near the origin.
struct ScrewPairs {
  std::vector<DualQuaternion<float>> a, b;
  ScrewPairs() {
    test::Random rng(19);
    for (int k = 0; k < 1000; ++k) a.push_back(rng.rigid<float>(5)), b.push_back(rng.rigid<float>(5));
    auto relative = [&](const Vec3<float>& axis, float angle, const Vec3<float>& t) {
      return DualQuaternion<float>::from_rotation_translation(Quaternion<float>::from_axis_angle(axis, angle), t);
    };
    for (int k = 0; k < 8; ++k) {
      const DualQuaternion<float> q = rng.rigid<float>(5);
      const Vec3<float> axis = rng.vec3<float>(1), t = rng.vec3<float>(2);
      const DualQuaternion<float> tiny = relative(axis, 1e-6f, t), tinier = relative(axis, 1e-20f, t);
      const DualQuaternion<float> half_turn = relative(axis, std::numbers::pi_v<float>, t);
      for (const DualQuaternion<float>& other :
           {q, q * tiny, q * tinier, -q, -(q * tiny), q * half_turn, q * relative(axis, std::numbers::pi_v<float> - 1e-3f, t),
            q * relative(axis, std::numbers::pi_v<float> - 1e-6f, t), q * DualQuaternion<float>::from_translation(t),
            q * DualQuaternion<float>::from_rotation(Quaternion<float>::from_axis_angle(axis, 2.0f))}) {
        a.push_back(q);
        b.push_back(other);
      }
      a.push_back(DualQuaternion<float>::from_translation(rng.vec3<float>(5)));
      b.push_back(DualQuaternion<float>::from_translation(rng.vec3<float>(5)));
      const Quaternion<float> r = rng.rotation<float>();
      a.push_back(DualQuaternion<float>::from_rotation_translation(r, {1000, 0, 0}));
      b.push_back(DualQuaternion<float>::from_rotation_translation(r * Quaternion<float>::from_axis_angle(axis, 0.5f), {-1000, 1, 0}));
    }
  }
};

using test::sclerp_reference;

TEST(Simd, SclerpOverArraysHasNoFailureCaseAndFloatAccuracy) {
  // Reference: dq::sclerp in long double. Bound: 8 float ulps (8 ε) in each real-part component,
  // and 8 ε (1 + |t_a| + |t_b|)/2 in each dual-part component (q_d = ½ t q_r: the translations'
  // scale; a result near the origin between translations of 1000 cannot be better than that).
  // The kernel's path is about 60 float operations deep (½ ulp each, mostly uncorrelated, and the
  // polynomials truncated below an ulp); measured on 16.8 million random pairs and t by
  // bench/interpolation_accuracy (relative rotations from 1e-25 rad to within 1e-8 of π, b and
  // −b, translations from 1e-3 to 1e3, screws about axes up to 1e3 from the origin): at most 3.1
  // ulps in the real part and 6.0 in the dual part, against 3.2 and 6.4 for dq::sclerp<float>
  // itself (the scalar target, held to the same bound here). A wrong branch, a division by a
  // vanishing sin Ω or a lost screw pitch gives errors of order one.
  const ScrewPairs pairs;
  const std::size_t n = pairs.a.size();
  const Batch qa(pairs.a), qb(pairs.b);
  const float eps = std::numeric_limits<float>::epsilon();
  for (const float t : {0.0f, 1e-6f, 0.3f, 0.5f, 0.999f, 1.0f}) {
    for_each_target([&](Target target) {
      Batch out(n, 20);
      simd::sclerp(qa.rows(), qb.rows(), t, out.rows(), n);
      double worst_real = 0, worst_dual = 0;
      for (std::size_t i = 0; i < n; ++i) {
        const DualQuaternion<float> got = out.get(i);
        const DualQuaternion<long double> wide = got.cast<long double>();
        const DualQuaternion<long double> want = sclerp_reference(pairs.a[i], pairs.b[i], t);
        const long double scale = (1 + norm(pairs.a[i].cast<long double>().translation()) + norm(pairs.b[i].cast<long double>().translation())) / 2;
        const long double g[8] = {wide.real.w, wide.real.x, wide.real.y, wide.real.z, wide.dual.w, wide.dual.x, wide.dual.y, wide.dual.z};
        const long double w[8] = {want.real.w, want.real.x, want.real.y, want.real.z, want.dual.w, want.dual.x, want.dual.y, want.dual.z};
        for (int k = 0; k < 8; ++k) {
          const long double err = std::abs(g[k] - w[k]) / (k < 4 ? 1 : scale) / static_cast<long double>(eps);
          (k < 4 ? worst_real : worst_dual) = std::max(k < 4 ? worst_real : worst_dual, static_cast<double>(err));
          ASSERT_LE(err, 8) << "t " << t << " pair " << i << " component " << k << ": " << got << " vs " << pairs.a[i] << ", " << pairs.b[i];
        }
        // Unit, never NaN.
        ASSERT_TRUE(got.is_unit(8 * eps)) << "t " << t << " pair " << i << ": " << got;
      }
      RecordProperty("worst_ulps_" + std::string(simd::to_string(target)) + "_t" + std::to_string(t), std::to_string(worst_real) + " " + std::to_string(worst_dual));
    });
  }
  // (t = 0 and t = 1 above: a and b, or −b, to the same bound.) Identical rotations give the
  // straight line between the translations, with the identity rotation exactly.
  for_each_target([&](Target) {
    Batch out(n, 21);
    simd::sclerp(qa.rows(), qb.rows(), 0.5f, out.rows(), n);
    for (std::size_t i = 1000; i < n; ++i)
      if (pairs.a[i].real == Quaternion<float>::identity() && pairs.b[i].real == Quaternion<float>::identity()) {
        ASSERT_EQ(out.get(i).real, Quaternion<float>::identity()) << i;
        const Vec3<float> mid = (pairs.a[i].translation() + pairs.b[i].translation()) * 0.5f;
        ASSERT_LE(test::max_abs_diff(out.get(i).translation(), mid), 8 * eps * (1 + norm(mid))) << i;
      }
  });
}

TEST(Simd, SclerpTailsInPlaceAndExtrapolation) {
  const ScrewPairs pairs;
  const Batch qa(pairs.a), qb(pairs.b);
  for_each_target([&](Target) {
    // n = 0 writes nothing, nor does any n past its n elements.
    Batch whole(qa.size(), 22);
    simd::sclerp(qa.rows(), qb.rows(), 0.4f, whole.rows(), qa.size());
    for (const std::size_t n : kSizes) {
      Batch out(qa.size(), 23);
      const Batch untouched = out;
      simd::sclerp(qa.rows(), qb.rows(), 0.4f, out.rows(), n);
      for (std::size_t i = 0; i < qa.size(); ++i) {
        if (i >= n) {
          ASSERT_TRUE(same_bits(out.get(i), untouched.get(i))) << n << " " << i;
          continue;
        }
        // The last n mod width elements ran the scalar function, the others the vector lanes, as
        // in the whole run or not: both within the bound above of the reference.
        ASSERT_TRUE(approx_equal(out.get(i), whole.get(i), 16 * std::numeric_limits<float>::epsilon() * (1 + norm(pairs.a[i].translation()) + norm(pairs.b[i].translation()))))
            << n << " " << i;
      }
    }
    // In place: out is a, or out is b.
    Batch into_a = qa, into_b = qb;
    simd::sclerp(std::as_const(into_a).rows(), qb.rows(), 0.4f, into_a.rows(), qa.size());
    simd::sclerp(qa.rows(), std::as_const(into_b).rows(), 0.4f, into_b.rows(), qa.size());
    for (std::size_t i = 0; i < qa.size(); ++i) {
      ASSERT_TRUE(same_bits(into_a.get(i), whole.get(i))) << i;
      ASSERT_TRUE(same_bits(into_b.get(i), whole.get(i))) << i;
    }
    // t outside [0, 1] runs dq::sclerp itself: bit for bit; a NaN t too (NaN out; the sign of a
    // NaN is not a result).
    for (const float t : {-0.5f, 1.5f, 3.0f}) {
      Batch out(qa.size(), 24);
      simd::sclerp(qa.rows(), qb.rows(), t, out.rows(), qa.size());
      for (std::size_t i = 0; i < qa.size(); ++i) ASSERT_TRUE(same_bits(out.get(i), sclerp(pairs.a[i], pairs.b[i], t))) << "t " << t << " " << i;
    }
    Batch out(qa.size(), 24);
    simd::sclerp(qa.rows(), qb.rows(), std::numeric_limits<float>::quiet_NaN(), out.rows(), qa.size());
    for (std::size_t i = 0; i < qa.size(); ++i) ASSERT_TRUE(std::isnan(out.get(i).real.w) && std::isnan(out.get(i).dual.x)) << i;
  });
}

/// Layout conversions of elements of C values of S (E: DualQuaternion, Quaternion or Vec3 of S,
/// float or double) on every target: every bit copied (random bit patterns: NaNs with payloads,
/// infinities, subnormals, signed zeros), element i's value c is array c's value i, for every n
/// (tails, 0), and nothing past n or outside the arrays written. `rows` makes the kernels' rows
/// from C array starts; `to` and `from` call the conversions.
template <class E, std::size_t C, class S, class Rows, class To, class From>
void check_layout_conversion(Rows rows, To to, From from) {
  static_assert(sizeof(E) == C * sizeof(S));
  using Bits = std::conditional_t<sizeof(S) == 4, std::uint32_t, std::uint64_t>;
  constexpr std::size_t kMax = 1003, kGuard = 16;
  // A NaN with a payload (not among the draws: asserted).
  const Bits sentinel = sizeof(S) == 4 ? Bits(0x7fc0dead) : Bits(0x7ff800000000deadull);
  std::mt19937_64 rng(31 + C);
  auto random_bits = [&] {
    std::vector<Bits> b(C * kMax);
    for (auto& x : b) x = static_cast<Bits>(rng());
    return b;
  };
  const std::vector<Bits> bits = random_bits();
  ASSERT_EQ(std::count(bits.begin(), bits.end(), sentinel), 0);
  std::vector<E> aos(kMax);
  std::memcpy(static_cast<void*>(aos.data()), bits.data(), C * kMax * sizeof(S));
  for_each_target([&](Target) {
    for (const std::size_t n : kSizes) {
      // Arrays of structures to component arrays: each array with guards before and after.
      std::vector<std::vector<Bits>> arrays(C, std::vector<Bits>(kMax + 2 * kGuard, sentinel));
      std::array<S*, C> starts;
      for (std::size_t c = 0; c < C; ++c) starts[c] = reinterpret_cast<S*>(arrays[c].data() + kGuard);
      to(std::span<const E>(aos.data(), n), rows(starts));
      for (std::size_t c = 0; c < C; ++c)
        for (std::size_t i = 0; i < kMax + 2 * kGuard; ++i) {
          const bool inside = i >= kGuard && i < kGuard + n;
          ASSERT_EQ(arrays[c][i], inside ? bits[C * (i - kGuard) + c] : sentinel) << "to_rows, n " << n << " array " << c << " index " << i;
        }
      // And back, into a span with elements before and after it.
      std::vector<Bits> back(C * (kMax + 2), sentinel);
      std::array<const S*, C> in;
      for (std::size_t c = 0; c < C; ++c) in[c] = starts[c];
      from(rows(in), std::span<E>(reinterpret_cast<E*>(back.data()) + 1, n));
      for (std::size_t k = 0; k < back.size(); ++k) {
        const bool inside = k >= C && k < C * (n + 1);
        ASSERT_EQ(back[k], inside ? bits[k - C] : sentinel) << "from_rows, n " << n << " float " << k;
      }
    }
  });
}

TEST(Simd, LayoutConversionsCopyEveryBitAndNothingElse) {
  check_layout_conversion<DualQuaternion<float>, 8, float>(
      []<class F>(const std::array<F*, 8>& a) { return detail::Row8<F>{a[0], a[1], a[2], a[3], a[4], a[5], a[6], a[7]}; },
      [](std::span<const DualQuaternion<float>> in, simd::Rows out) { simd::to_rows(in, out); },
      [](simd::ConstRows in, std::span<DualQuaternion<float>> out) { simd::from_rows(in, out); });
  check_layout_conversion<Quaternion<float>, 4, float>(
      []<class F>(const std::array<F*, 4>& a) { return simd::QuaternionRows<F>{a[0], a[1], a[2], a[3]}; },
      [](std::span<const Quaternion<float>> in, simd::QuaternionRows<float> out) { simd::to_rows(in, out); },
      [](simd::QuaternionRows<const float> in, std::span<Quaternion<float>> out) { simd::from_rows(in, out); });
  check_layout_conversion<Vec3<float>, 3, float>(
      []<class F>(const std::array<F*, 3>& a) { return a; },
      [](std::span<const Vec3<float>> in, std::array<float*, 3> out) { simd::to_rows(in, out); },
      [](std::array<const float*, 3> in, std::span<Vec3<float>> out) { simd::from_rows(in, out); });
  // In double: dual quaternions (records of eight doubles, transposed in squares) and points.
  check_layout_conversion<DualQuaternion<double>, 8, double>(
      []<class F>(const std::array<F*, 8>& a) { return detail::Row8<F>{a[0], a[1], a[2], a[3], a[4], a[5], a[6], a[7]}; },
      [](std::span<const DualQuaternion<double>> in, simd::RowsD out) { simd::to_rows(in, out); },
      [](simd::ConstRowsD in, std::span<DualQuaternion<double>> out) { simd::from_rows(in, out); });
  check_layout_conversion<Vec3<double>, 3, double>(
      []<class F>(const std::array<F*, 3>& a) { return a; },
      [](std::span<const Vec3<double>> in, std::array<double*, 3> out) { simd::to_rows(in, out); },
      [](std::array<const double*, 3> in, std::span<Vec3<double>> out) { simd::from_rows(in, out); });
}

TEST(Simd, LayoutConversionsFeedTheKernels) {
  // What the conversions are for: arrays of dual quaternions and points in, through the kernels,
  // and out again, equal to the scalar functions element by element.
  test::Random rng(41);
  std::vector<DualQuaternion<float>> q(517);
  std::vector<Vec3<float>> p(q.size());
  for (std::size_t i = 0; i < q.size(); ++i) q[i] = rng.rigid<float>(5), p[i] = rng.vec3<float>(3);
  for_each_target([&](Target) {
    ComponentArrays<float, 8> rows_q(q.size());
    ComponentArrays<float, 3> rows_p(p.size());
    simd::to_rows(q, simd::rows(rows_q));
    simd::to_rows(p, rows_p.data());
    simd::transform_points(simd::rows(std::as_const(rows_q)), std::as_const(rows_p).data(), rows_p.data(), p.size());
    std::vector<Vec3<float>> moved(p.size());
    simd::from_rows(std::as_const(rows_p).data(), moved);
    for (std::size_t i = 0; i < p.size(); ++i) ASSERT_TRUE(same_bits(moved[i], q[i].transform_point(p[i]))) << i;
  });
}

/// What the kernels compute for a point (Rigid) or direction: the scalar functions in float; in
/// double the formulas written out without SLP (tests/support.hpp), and where FMA is not enabled
/// the scalar functions too (checked in KernelsInDoubleAreTheScalarFormulasBitForBit).
template <class S>
Vec3<S> moved(const DualQuaternion<S>& q, const Vec3<S>& p, bool rigid) {
  if constexpr (std::is_same_v<S, double>)
    return rigid ? test::transform_point_reference(q, p) : test::transform_direction_reference(q, p);
  else
    return rigid ? q.transform_point(p) : q.transform_direction(p);
}

// One transform for a whole cloud of points (x, y, z one after another), in float and in double:
// each point bit for bit what the scalar formula gives, on every target, for counts around the
// vector widths, into another array (the point past it untouched) and in place.
template <class S>
void check_point_cloud() {
  test::Random rng(43);
  std::vector<Vec3<S>> cloud(1003);
  for (auto& p : cloud) p = rng.vec3<S>(10);
  const Vec3<S> guard{S(-0.0), std::numeric_limits<S>::infinity(), S(7)};
  // A random transform, and one with zeros of both signs (the broadcast must keep them: the signs
  // of zero results follow them; 0 + s would make them all +0), moving points with signed zeros.
  const DualQuaternion<S> random = rng.rigid<S>(5), signed_zeros(1, 0, S(-0.0), 0, 0, S(-0.0), 0, 0);
  for (std::size_t i = 0; i < 64; ++i) cloud[i] = {i % 2 ? S(0) : S(-0.0), i % 4 < 2 ? S(-0.0) : S(1), i % 8 < 4 ? S(0) : S(-0.0)};
  for (const DualQuaternion<S>& q : {random, signed_zeros})
  for_each_target([&](Target t) {
    for (const std::size_t n : {0u, 1u, 2u, 3u, 4u, 5u, 8u, 9u, 15u, 16u, 17u, 31u, 33u, 47u, 1003u}) {
      SCOPED_TRACE(std::string(simd::to_string(t)) + ", " + std::to_string(n) + " points of " + (sizeof(S) == 4 ? "float" : "double"));
      const std::span<const Vec3<S>> in(cloud.data(), n);
      for (const bool rigid : {true, false}) {
        const auto run = [&](std::span<const Vec3<S>> from, std::span<Vec3<S>> to) {
          rigid ? simd::transform_points(q, from, to) : simd::transform_directions(q, from, to);
        };
        std::vector<Vec3<S>> out(n + 1, guard);
        run(in, std::span(out).first(n));
        for (std::size_t i = 0; i < n; ++i) ASSERT_TRUE(same_bits(out[i], moved(q, in[i], rigid))) << (rigid ? "point " : "direction ") << i;
        ASSERT_TRUE(same_bits(out[n], guard)) << "written past the end";
        std::vector<Vec3<S>> same(in.begin(), in.end());
        same.push_back(guard);
        run(std::span(same).first(n), std::span(same).first(n));
        for (std::size_t i = 0; i < n; ++i) ASSERT_TRUE(same_bits(same[i], moved(q, in[i], rigid))) << "in place, " << i;
        ASSERT_TRUE(same_bits(same[n], guard)) << "in place, written past the end";
      }
    }
  });
}
TEST(Simd, OneTransformMovesAPointCloud) {
  check_point_cloud<float>();
  check_point_cloud<double>();
}

// The kernels in double (2, 4 or 8 lanes a vector) on every target and every n of kSizes (the
// tails, which run the scalar formula, too): compose, inverse, transform_points and
// transform_directions bit for bit the double formulas written out without SLP, nothing past n
// written; where FMA is not enabled, bit for bit the library's scalar functions as well (with FMA,
// GCC fuses parts of those where it inlines them: docs/design.md); and in place.
TEST(Simd, KernelsInDoubleAreTheScalarFormulasBitForBit) {
  constexpr std::size_t kMax = 1003;
  const BatchOf<double> a(kMax, 51), b(kMax, 52), untouched(kMax, 53);
  test::Random rng(54);
  std::vector<double> p[3];
  for (auto& v : p) v.resize(kMax);
  for (std::size_t i = 0; i < kMax; ++i) {
    const Vec3<double> x = rng.vec3<double>(10);
    p[0][i] = x.x, p[1][i] = x.y, p[2][i] = x.z;
  }
  const auto point = [&](const std::vector<double>* v, std::size_t i) { return Vec3<double>{v[0][i], v[1][i], v[2][i]}; };
  [[maybe_unused]] constexpr bool kScalarUnfused =
#if defined(__FMA__)
      false;
#else
      true;
#endif
  for_each_target([&](Target) {
    for (const std::size_t n : kSizes) {
      SCOPED_TRACE("n " + std::to_string(n));
      BatchOf<double> out = untouched;
      simd::compose(a.rows(), b.rows(), out.rows(), n);
      for (std::size_t i = 0; i < kMax; ++i) {
        ASSERT_TRUE(same_bits(out.get(i), i < n ? test::product_reference(a.get(i), b.get(i)) : untouched.get(i))) << "compose " << i;
        if (kScalarUnfused && i < n) {
          ASSERT_TRUE(same_bits(out.get(i), a.get(i) * b.get(i))) << "compose, scalar, " << i;
        }
      }
      out = untouched;
      simd::inverse(a.rows(), out.rows(), n);
      for (std::size_t i = 0; i < kMax; ++i)
        ASSERT_TRUE(same_bits(out.get(i), i < n ? a.get(i).inverse_unit() : untouched.get(i))) << "inverse " << i;
      for (const bool rigid : {true, false}) {
        std::vector<double> o[3];
        for (auto& v : o) v.assign(kMax, -1.0);
        const std::array<const double*, 3> from{p[0].data(), p[1].data(), p[2].data()};
        const std::array<double*, 3> to{o[0].data(), o[1].data(), o[2].data()};
        rigid ? simd::transform_points(a.rows(), from, to, n) : simd::transform_directions(a.rows(), from, to, n);
        for (std::size_t i = 0; i < kMax; ++i) {
          const Vec3<double> got = point(o, i);
          ASSERT_TRUE(same_bits(got, i < n ? moved(a.get(i), point(p, i), rigid) : Vec3<double>{-1, -1, -1}))
              << (rigid ? "point " : "direction ") << i;
          if (kScalarUnfused && i < n) {
            ASSERT_TRUE(same_bits(got, rigid ? a.get(i).transform_point(point(p, i)) : a.get(i).transform_direction(point(p, i))))
                << (rigid ? "point, scalar, " : "direction, scalar, ") << i;
          }
        }
      }
    }
    // In place: the output is an input.
    BatchOf<double> in_place = a;
    simd::compose(std::as_const(in_place).rows(), b.rows(), in_place.rows(), kMax);
    for (std::size_t i = 0; i < kMax; ++i) ASSERT_TRUE(same_bits(in_place.get(i), test::product_reference(a.get(i), b.get(i)))) << i;
    in_place = a;
    simd::inverse(std::as_const(in_place).rows(), in_place.rows(), kMax);
    for (std::size_t i = 0; i < kMax; ++i) ASSERT_TRUE(same_bits(in_place.get(i), a.get(i).conjugate())) << i;
    std::vector<double> w[3] = {p[0], p[1], p[2]};
    simd::transform_points(a.rows(), {w[0].data(), w[1].data(), w[2].data()}, {w[0].data(), w[1].data(), w[2].data()}, kMax);
    for (std::size_t i = 0; i < kMax; ++i) ASSERT_TRUE(same_bits(point(w, i), moved(a.get(i), point(p, i), true))) << i;
  });
}

// compose, inverse, transform_points and transform_directions over arrays of structures, in float
// and double, on every target: each element bit for bit what the scalar formula gives (the scalar
// functions in float; in double the formulas written out without SLP, tests/support.hpp), for
// counts around the vector widths, the element past the end untouched, in place too; and the
// preconditions (sizes, overlaps) refused.
template <class S>
DualQuaternion<S> composed(const DualQuaternion<S>& a, const DualQuaternion<S>& b) {
  if constexpr (std::is_same_v<S, double>)
    return test::product_reference(a, b);
  else
    return a * b;
}
template <class S>
void check_arrays_of_structures() {
  test::Random rng(61);
  constexpr std::size_t kMax = 1003;
  std::vector<DualQuaternion<S>> a(kMax), b(kMax);
  std::vector<Vec3<S>> p(kMax);
  for (std::size_t i = 0; i < kMax; ++i) a[i] = rng.rigid<S>(5), b[i] = rng.rigid<S>(5), p[i] = rng.vec3<S>(10);
  const DualQuaternion<S> guard(S(-0.0), std::numeric_limits<S>::infinity(), 7, 0, 0, 0, 0, 1);
  const Vec3<S> guard_point{S(-0.0), std::numeric_limits<S>::infinity(), 7};
  for_each_target([&](Target t) {
    for (const std::size_t n : {0u, 1u, 2u, 3u, 4u, 5u, 7u, 8u, 9u, 15u, 16u, 17u, 31u, 33u, 1003u}) {
      SCOPED_TRACE(std::string(simd::to_string(t)) + ", " + std::to_string(n) + " elements of " + (sizeof(S) == 4 ? "float" : "double"));
      const std::span<const DualQuaternion<S>> qa(a.data(), n), qb(b.data(), n);
      const std::span<const Vec3<S>> in(p.data(), n);
      std::vector<DualQuaternion<S>> out(n + 1, guard);
      simd::compose(qa, qb, std::span(out).first(n));
      for (std::size_t i = 0; i < n; ++i) ASSERT_TRUE(same_bits(out[i], composed(a[i], b[i]))) << "compose " << i;
      ASSERT_TRUE(same_bits(out[n], guard)) << "compose wrote past the end";
      simd::inverse(qa, std::span(out).first(n));
      for (std::size_t i = 0; i < n; ++i) ASSERT_TRUE(same_bits(out[i], a[i].inverse_unit())) << "inverse " << i;
      ASSERT_TRUE(same_bits(out[n], guard)) << "inverse wrote past the end";
      for (const bool rigid : {true, false}) {
        std::vector<Vec3<S>> moved_out(n + 1, guard_point);
        rigid ? simd::transform_points(qa, in, std::span(moved_out).first(n)) : simd::transform_directions(qa, in, std::span(moved_out).first(n));
        for (std::size_t i = 0; i < n; ++i) ASSERT_TRUE(same_bits(moved_out[i], moved(a[i], p[i], rigid))) << (rigid ? "point " : "direction ") << i;
        ASSERT_TRUE(same_bits(moved_out[n], guard_point)) << "wrote past the end";
        // In place: the points are the output.
        std::vector<Vec3<S>> same(in.begin(), in.end());
        rigid ? simd::transform_points(qa, same, same) : simd::transform_directions(qa, same, same);
        for (std::size_t i = 0; i < n; ++i) ASSERT_TRUE(same_bits(same[i], moved(a[i], p[i], rigid))) << "in place, " << i;
      }
      // In place: the product into a, the inverse into q.
      std::vector<DualQuaternion<S>> x(qa.begin(), qa.end());
      simd::compose(x, qb, x);
      for (std::size_t i = 0; i < n; ++i) ASSERT_TRUE(same_bits(x[i], composed(a[i], b[i]))) << "compose in place " << i;
      simd::inverse(x, x);
      for (std::size_t i = 0; i < n; ++i) ASSERT_TRUE(same_bits(x[i], composed(a[i], b[i]).inverse_unit())) << "inverse in place " << i;
    }
  });
}
struct Refused : std::runtime_error {
  using std::runtime_error::runtime_error;
};
TEST(Simd, ArraysOfStructuresTakeTheKernels) {
  check_arrays_of_structures<float>();
  check_arrays_of_structures<double>();
  // The preconditions, with a handler that throws (the default aborts), restored after.
  const PreconditionHandler previous = set_precondition_handler([](const PreconditionViolation& v) { throw Refused(v.message); });
  std::vector<DualQuaternion<double>> q(9, DualQuaternion<double>::identity());
  std::vector<Vec3<double>> v(9);
  const std::span<DualQuaternion<double>> all(q);
  EXPECT_THROW(simd::compose(all.first(8), all.first(8), std::span(q).subspan(1, 7)), Refused);  // sizes
  EXPECT_THROW(simd::compose(all.first(8), all.first(8), all.subspan(1)), Refused);               // out partly over a
  EXPECT_THROW(simd::inverse(all.first(8), all.subspan(1)), Refused);
  EXPECT_THROW(simd::transform_points(all.first(8), std::span(v).first(8), std::span(v).subspan(1)), Refused);
  EXPECT_THROW(simd::transform_directions(all.first(3), std::span(v).first(3), std::span(reinterpret_cast<Vec3<double>*>(q.data()), 3)),
               Refused);  // out over q
  EXPECT_THROW(simd::compose(all.first(8), all.subspan(1), all.first(8)), Refused);  // out is a, but partly over b
  const std::vector<DualQuaternion<double>> other(8, DualQuaternion<double>::identity());
  EXPECT_NO_THROW(simd::compose(all.first(8), other, all.first(8)));  // out is a exactly, apart from b
  set_precondition_handler(previous);
}

TEST(Simd, DispatchReportsWhatTheCpuHas) {
  const Target best = simd::best_target();
  RecordProperty("best_target", std::string(simd::to_string(best)));
  EXPECT_EQ(simd::current_target(), best);
#if defined(__x86_64__)
  EXPECT_GE(static_cast<int>(best), static_cast<int>(Target::sse2));  // every x86-64 CPU has SSE2
  EXPECT_EQ(best == Target::avx512, static_cast<bool>(__builtin_cpu_supports("avx512f")));
  EXPECT_EQ(best >= Target::avx2, static_cast<bool>(__builtin_cpu_supports("avx2")));
  EXPECT_EQ(best >= Target::sse42, static_cast<bool>(__builtin_cpu_supports("sse4.2")));
#endif
  {
    const simd::ScopedTarget scope(Target::scalar);
    EXPECT_EQ(simd::current_target(), Target::scalar);
  }
  EXPECT_EQ(simd::current_target(), best);  // restored
  // available_targets: scalar up to the best, each one accepted by use_target as itself.
  ASSERT_FALSE(simd::available_targets().empty());
  EXPECT_EQ(simd::available_targets().front(), Target::scalar);
  EXPECT_EQ(simd::available_targets().back(), best);
  for (const Target t : simd::available_targets()) {
    const simd::ScopedTarget scope(t);
    EXPECT_EQ(simd::current_target(), t) << simd::to_string(t);
  }
  // Each target at most the best: the SSE4.2 kernels, too, are what for_each_target tests.
  if (best >= Target::sse42) {
    EXPECT_EQ(simd::use_target(Target::sse42), Target::sse42);
  }
  EXPECT_EQ(simd::to_string(Target::sse42), "SSE4.2");
  EXPECT_EQ(simd::use_target(Target::scalar), Target::scalar);
  EXPECT_EQ(simd::use_target(Target::avx512), best);
}

}  // namespace

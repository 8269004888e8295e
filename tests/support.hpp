// Shared helpers for the tests: seeded random inputs and per-scalar tolerances.
#pragma once

#include <cmath>
#include <limits>
#include <random>
#include <type_traits>

#include "dq/dq.hpp"

// A reference formula's function attribute: compiled without GCC's SLP vectorizer, which in GCC 12
// fuses the Hamilton pattern into vfmaddsub when FMA is enabled, despite -ffp-contract=off
// (docs/design.md), so that a reference stays its formula. (Clang has neither the attribute nor
// the fusion.)
#if defined(__clang__)
#define DQKIT_TEST_NO_SLP
#else
#define DQKIT_TEST_NO_SLP gnu::optimize("no-tree-slp-vectorize")
#endif

namespace dq::test {

/// A deterministic generator; every test seeds its own so failures reproduce.
class Random {
 public:
  explicit Random(unsigned seed) : engine_(seed) {}

  template <class T>
  T uniform(T lo, T hi) {
    return static_cast<T>(std::uniform_real_distribution<double>(static_cast<double>(lo), static_cast<double>(hi))(engine_));
  }
  template <class T>
  Vec3<T> vec3(T range) {
    return {uniform<T>(-range, range), uniform<T>(-range, range), uniform<T>(-range, range)};
  }
  /// A rotation uniformly distributed on SO(3): a normalized 4D Gaussian sample.
  template <class T>
  Quaternion<T> rotation() {
    std::normal_distribution<double> g;
    // Normalized in T, so that long double inputs are unit to long-double precision.
    const Quaternion<T> q(static_cast<T>(g(engine_)), static_cast<T>(g(engine_)), static_cast<T>(g(engine_)),
                          static_cast<T>(g(engine_)));
    return q / std::sqrt(q.squared_norm());
  }
  template <class T>
  DualQuaternion<T> rigid(T range = T(10)) {
    return DualQuaternion<T>::from_rotation_translation(rotation<T>(), vec3<T>(range));
  }
  std::mt19937_64& engine() { return engine_; }

 private:
  std::mt19937_64 engine_;
};

/// A tolerance of `ulps` units of roundoff of T, for quantities of order one.
template <class T>
constexpr T tol(T ulps = T(16)) {
  return ulps * std::numeric_limits<T>::epsilon();
}

template <class T>
T max_abs_diff(const Vec3<T>& a, const Vec3<T>& b) {
  using std::abs;
  return std::max({abs(a.x - b.x), abs(a.y - b.y), abs(a.z - b.z)});
}
template <class T>
T max_abs_diff(const Quaternion<T>& a, const Quaternion<T>& b) {
  using std::abs;
  return std::max({abs(a.w - b.w), abs(a.x - b.x), abs(a.y - b.y), abs(a.z - b.z)});
}
template <class T>
T max_abs_diff(const DualQuaternion<T>& a, const DualQuaternion<T>& b) {
  return std::max(max_abs_diff(a.real, b.real), max_abs_diff(a.dual, b.dual));
}
template <class T, int R, int C>
T max_abs_diff(const Mat<T, R, C>& a, const Mat<T, R, C>& b) {
  using std::abs;
  T worst = 0;
  for (std::size_t i = 0; i < a.m.size(); ++i) worst = std::max(worst, abs(a.m[i] - b.m[i]));
  return worst;
}
/// Distance between rotations as quaternions, q ≡ −q.
template <class T>
T rotation_diff(const Quaternion<T>& a, const Quaternion<T>& b) {
  return std::min(max_abs_diff(a, b), max_abs_diff(a, -b));
}

/// |a − b| in the wider of the two types (so long double is not compared through double).
template <class A, class B>
auto abs_diff(const A& a, const B& b) {
  using C = std::common_type_t<A, B>;
  using std::abs;
  return abs(C(a) - C(b));
}
#define DQ_EXPECT_NEAR(a, b, tolerance) \
  EXPECT_LE(::dq::test::abs_diff((a), (b)), (tolerance)) << #a << " = " << (a) << " vs " << #b << " = " << (b)

using FloatTypes = ::testing::Types<float, double, long double>;

// The scalar double formulas that the batch kernels in double compute, written out in the order of
// operations of the library's scalar functions (DualQuaternion's product, transform_point,
// Quaternion::rotate) and compiled without SLP (DQKIT_TEST_NO_SLP): the formulas' bits in every
// build, where the library's scalar functions are fused by GCC in a build with FMA.

/// Three Hamilton products, each component's four products summed in pairs, then the dual part's sum.
[[gnu::noinline, DQKIT_TEST_NO_SLP]] inline Quaternion<double> hamilton_reference(const Quaternion<double>& a, const Quaternion<double>& b) {
  return {(a.w * b.w - a.x * b.x) - (a.y * b.y + a.z * b.z), (a.w * b.x + a.x * b.w) + (a.y * b.z - a.z * b.y),
          (a.w * b.y - a.x * b.z) + (a.y * b.w + a.z * b.x), (a.w * b.z + a.x * b.y) - (a.y * b.x - a.z * b.w)};
}
[[gnu::noinline, DQKIT_TEST_NO_SLP]] inline DualQuaternion<double> product_reference(const DualQuaternion<double>& a,
                                                                                      const DualQuaternion<double>& b) {
  const Quaternion<double> rd = hamilton_reference(a.real, b.dual), dr = hamilton_reference(a.dual, b.real);
  return {hamilton_reference(a.real, b.real), Quaternion<double>(rd.w + dr.w, rd.x + dr.x, rd.y + dr.y, rd.z + dr.z)};
}
[[gnu::noinline, DQKIT_TEST_NO_SLP]] inline Vec3<double> cross_reference(const Vec3<double>& a, const Vec3<double>& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
/// p + 2 [w c + r × c − w_d r] with c = r × p + d (DualQuaternion::transform_point).
[[gnu::noinline, DQKIT_TEST_NO_SLP]] inline Vec3<double> transform_point_reference(const DualQuaternion<double>& q, const Vec3<double>& p) {
  const Vec3<double> r = q.real.vec(), d = q.dual.vec();
  const Vec3<double> rp = cross_reference(r, p);
  const Vec3<double> c{rp.x + d.x, rp.y + d.y, rp.z + d.z};
  const Vec3<double> rc = cross_reference(r, c);
  const double w = q.real.w, wd = q.dual.w;
  return {p.x + ((c.x * w + rc.x) - r.x * wd) * 2.0, p.y + ((c.y * w + rc.y) - r.y * wd) * 2.0, p.z + ((c.z * w + rc.z) - r.z * wd) * 2.0};
}
/// v + w t + u × t with t = 2 u × v (Quaternion::rotate of the real part).
[[gnu::noinline, DQKIT_TEST_NO_SLP]] inline Vec3<double> transform_direction_reference(const DualQuaternion<double>& q, const Vec3<double>& v) {
  const Vec3<double> u = q.real.vec();
  const Vec3<double> uv = cross_reference(u, v);
  const Vec3<double> t{uv.x * 2.0, uv.y * 2.0, uv.z * 2.0};
  const Vec3<double> ut = cross_reference(u, t);
  const double w = q.real.w;
  return {(v.x + t.x * w) + ut.x, (v.y + t.y * w) + ut.y, (v.z + t.z * w) + ut.z};
}

}  // namespace dq::test

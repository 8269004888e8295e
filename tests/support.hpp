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

}  // namespace dq::test

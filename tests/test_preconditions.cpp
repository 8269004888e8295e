// The precondition policy (include/dq/util/assert.hpp): every violated precondition reaches the
// installed handler, with the default handler aborting, and a handler that returns leaves the
// outputs untouched.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "dq/anim/forward_kinematics.hpp"
#include "dq/anim/pose_blocks.hpp"
#include "dq/util/component_arrays.hpp"
#include "dq/dq.hpp"

namespace {

using namespace dq;

struct Violation : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Installs a handler that throws (so each violation is seen), restoring the default after.
class Preconditions : public ::testing::Test {
 protected:
  void SetUp() override {
    previous_ = set_precondition_handler([](const PreconditionViolation& v) {
      throw Violation(std::string(v.function) + ": " + v.message);
    });
  }
  void TearDown() override { set_precondition_handler(previous_); }

 private:
  PreconditionHandler previous_ = nullptr;
};

const DualQuaternion<double> kA = DualQuaternion<double>::from_translation({1, 0, 0});
const DualQuaternion<double> kB = DualQuaternion<double>::from_rotation(Quaternion<double>::from_axis_angle({0, 0, 1}, 1.0));

TEST_F(Preconditions, BlendsNeedOneWeightPerInput) {
  const std::vector<DualQuaternion<double>> qs{kA, kB};
  const std::vector<double> one{1.0}, two{0.25, 0.75};
  EXPECT_THROW((void)dlb(qs, one), Violation);
  EXPECT_THROW((void)dib(qs, one), Violation);
  EXPECT_NO_THROW((void)dlb(qs, two));
  const std::vector<Quaternion<double>> rs{kA.real, kB.real};
  EXPECT_THROW((void)average(rs, one), Violation);
  EXPECT_NO_THROW((void)average(rs));
  const std::array<Mat4<double>, 2> ms{to_mat4(kA), to_mat4(kB)};
  EXPECT_THROW((void)alexa_blend(ms, one), Violation);
}

TEST_F(Preconditions, SpanFunctionsTakeContainersWithoutNamingTheScalar) {
  // The range overloads deduce T from the elements and agree with the span versions.
  const std::array<DualQuaternion<float>, 2> qs{kA.cast<float>(), kB.cast<float>()};
  const std::array<float, 2> w{0.25f, 0.75f};
  EXPECT_EQ(dlb(qs, w), dlb<float>(qs, w));
  EXPECT_EQ(dib(qs, w).value, dib<float>(qs, w).value);
  const std::vector<Quaternion<double>> rs{kA.real, kB.real};
  EXPECT_EQ(average(rs), average<double>(rs));
}

TEST_F(Preconditions, ForwardKinematicsChecksSizesAndAliasing) {
  const std::vector<int> parents{-1, 0, 1};
  std::vector<DualQuaternion<double>> local(3, kA), model(3), short_model(2);
  EXPECT_THROW(local_to_model<DualQuaternion<double>>(parents, local, short_model), Violation);
  // Partly overlapping spans: model starts one element into local.
  std::vector<DualQuaternion<double>> both(4, kA);
  EXPECT_THROW(local_to_model<DualQuaternion<double>>(parents, std::span(both).first(3), std::span(both).subspan(1, 3)),
               Violation);
  // In place is allowed and gives the same result as separate arrays.
  local_to_model<DualQuaternion<double>>(parents, local, model);
  std::vector<DualQuaternion<double>> in_place = local;
  local_to_model<DualQuaternion<double>>(parents, in_place, in_place);
  EXPECT_EQ(in_place, model);
  EXPECT_NEAR(model[2].translation().x, 3.0, 1e-15);
  const std::vector<int> child_first{1, -1};
  std::vector<DualQuaternion<double>> two(2, kA), out(2);
  EXPECT_THROW(local_to_model<DualQuaternion<double>>(child_first, two, out), Violation);
}

TEST_F(Preconditions, JobsRefuseToRunWhenTheyDoNotValidate) {
  const std::vector<int> parents{-1, 0};
  DualQuaternionSoAStorage<float> local(2, 5), model(2, 5);
  ForwardKinematicsJob<float> job{parents, local.view(), model.view(), 0, 5};
  EXPECT_TRUE(job.validate().ok());
  EXPECT_NO_THROW(job.run());
  ForwardKinematicsJob<float> aliased{parents, model.view(), model.view(), 0, 5};
  EXPECT_FALSE(aliased.validate().ok());
  EXPECT_EQ(aliased.validate().error().message, "a model component array overlaps a local one");
  EXPECT_THROW(aliased.run(), Violation);
  job.pose_count = 1000;
  EXPECT_THROW(job.run(), Violation);
}

TEST(PreconditionsDefault, TheDefaultHandlerAbortsWithWhatAndWhere) {
  const std::vector<DualQuaternion<double>> qs{kA, kB};
  const std::vector<double> one{1.0};
  EXPECT_DEATH((void)dlb(qs, one), "dqkit: precondition violated in dlb: dlb needs one weight per dual quaternion");
}

TEST(PreconditionsDefault, AReturningHandlerLeavesOutputsUntouchedAndResultsNaN) {
  static int calls = 0;
  const PreconditionHandler previous = set_precondition_handler([](const PreconditionViolation&) { ++calls; });
  const std::vector<DualQuaternion<double>> qs{kA, kB};
  const std::vector<double> one{1.0};
  EXPECT_TRUE(std::isnan(dlb(qs, one).real.w));
  const std::vector<int> parents{-1, 0, 1};
  std::vector<DualQuaternion<double>> local(3, kA), model(2, kB);
  local_to_model<DualQuaternion<double>>(parents, local, model);
  EXPECT_EQ(model[0], kB);
  EXPECT_EQ(calls, 2);
  set_precondition_handler(previous);
}

/// The layout of every ComponentArrays: `count` arrays of n zeroed values, each on a cache line,
/// past the end of the one before, and no two a multiple of 4 KiB apart.
template <class T, std::size_t N>
void check_layout(const ComponentArrays<T, N>& a, std::size_t n, std::size_t count) {
  ASSERT_EQ(a.size(), n);
  ASSERT_EQ(a.count(), count);
  for (std::size_t k = 0; k < count; ++k) {
    SCOPED_TRACE(testing::Message() << "N " << N << " n " << n << " array " << k);
    ASSERT_EQ(a[k].size(), n);
    EXPECT_EQ(reinterpret_cast<std::uintptr_t>(a[k].data()) % 64, 0u);
    for (const T& v : a[k]) ASSERT_EQ(v, T(0));
    if (k > 0) {
      EXPECT_GE(a[k].data(), a[k - 1].data() + n);  // past the end of the one before
    }
    for (std::size_t l = 0; l < k; ++l) {  // no two a multiple of 4 KiB apart
      EXPECT_NE(static_cast<std::size_t>(a[k].data() - a[l].data()) * sizeof(T) % 4096, 0u) << "and array " << l;
    }
  }
}

template <class T, std::size_t N>
void check_component_arrays(std::size_t n) {
  ComponentArrays<T, N> a(n);
  check_layout(a, n, N);
  const std::array<T*, N> starts = a.data();
  for (std::size_t k = 0; k < N; ++k) {
    EXPECT_EQ(starts[k], a[k].data());
    EXPECT_EQ(std::as_const(a).data()[k], a[k].data());
  }
  for (std::size_t k = 0; k < N; ++k)  // every array writable over its whole length, values kept apart
    for (std::size_t i = 0; i < n; ++i) a[k][i] = T(k * n + i);
  for (std::size_t k = 0; k < N; ++k)
    for (std::size_t i = 0; i < n; i += 1 + n / 7) ASSERT_EQ(a[k][i], T(k * n + i));
  ComponentArrays<T, N> moved = std::move(a);
  EXPECT_EQ(moved.size(), n);
  EXPECT_EQ(moved[N - 1].data(), starts[N - 1]);
  EXPECT_EQ(a.size(), 0u);  // NOLINT(bugprone-use-after-move): documented state
  EXPECT_TRUE(a[0].empty());
  ComponentArrays<T, N> assigned(3);
  assigned = std::move(moved);
  EXPECT_EQ(assigned.size(), n);
  EXPECT_EQ(assigned[0].data(), starts[0]);
  EXPECT_EQ(moved.size(), 0u);  // NOLINT(bugprone-use-after-move): documented state
}

/// The largest size is addressable with its padding, and one more is refused.
template <class T, std::size_t N>
void check_size_limit() {
  using A = ComponentArrays<T, N>;
  std::size_t bytes = 0;
  EXPECT_FALSE(__builtin_mul_overflow(N * sizeof(T), A::max_size() + 3 * A::line, &bytes));
  EXPECT_THROW(A(A::max_size() + 1), std::length_error);
}

// A count given at run time (the skin's arrays): the same layout, and copies of their own.
TEST(ComponentArrays, ARunTimeCountIsAlignedApartAndSkewedAndCopiesAreDeep) {
  using A = ComponentArrays<float, std::dynamic_extent>;
  for (std::size_t n : {0u, 1u, 1000u, 1024u, 4096u})
    for (std::size_t count : {1u, 5u, 20u}) {
      SCOPED_TRACE(testing::Message() << "n " << n << " count " << count);
      A a(n, count);
      check_layout(a, n, count);
      for (std::size_t k = 0; k < count; ++k) {
        EXPECT_EQ(a[k].data(), a[0].data() + k * a.distance());
        for (std::size_t i = 0; i < n; ++i) a[k][i] = float(k * n + i);
      }
      A copy = a;
      A assigned(1, 1);
      assigned = a;
      for (const A* c : {&copy, &assigned}) {
        ASSERT_EQ(c->count(), count);
        ASSERT_EQ(c->size(), n);
        for (std::size_t k = 0; k < count; ++k) {
          EXPECT_NE((*c)[k].data(), a[k].data());
          EXPECT_TRUE(std::equal((*c)[k].begin(), (*c)[k].end(), a[k].begin()));
        }
      }
      if (n > 0) {
        copy[count - 1][n - 1] = -1;
        EXPECT_EQ(a[count - 1][n - 1], float((count - 1) * n + n - 1));
      }
    }
  EXPECT_THROW(A(A::max_size(3) + 1, 3), std::length_error);
}

TEST(ComponentArrays, AreAlignedZeroedApartAndSkewed) {
  // Points (3 arrays), 3x4 matrices (12), dual quaternions (8), at sizes of whole 4 KiB pages and
  // others, where plain vectors of 2^k floats would all lie a multiple of 4 KiB apart.
  for (std::size_t n : {0u, 1u, 15u, 16u, 1000u, 1024u, 4096u}) {
    check_component_arrays<float, 3>(n);
    check_component_arrays<float, 12>(n);
    check_component_arrays<double, 8>(n);
  }
  // 64 arrays (the most the odd spacing keeps apart) at every padded size from 0 to 4 KiB + lines.
  for (std::size_t n = 0; n <= 1100; n += 7) check_component_arrays<float, 64>(n);
  for (std::size_t n = 0; n <= 600; n += 5) check_component_arrays<double, 64>(n);
  check_size_limit<float, 3>();
  check_size_limit<float, 12>();
  check_size_limit<double, 8>();
  check_size_limit<float, 1>();
  EXPECT_THROW((DualQuaternionSoAStorage<float>(std::size_t{1} << 40, std::size_t{1} << 30)), std::length_error);
  EXPECT_THROW((DualQuaternionBlockStorage<float>(std::size_t{1} << 40, std::size_t{1} << 30)), std::length_error);
  EXPECT_THROW((DualQuaternionBlockStorage<float>(1, std::numeric_limits<std::size_t>::max())), std::length_error);
}

TEST(SoAStorage, IsAlignedPaddedAndSkewed) {
  // Component arrays start on 64-byte lines, the stride is whole lines, and no two arrays are a
  // multiple of 4 KiB apart (the aliasing that made the padded job 1.3–1.55× faster).
  for (std::size_t poses : {1u, 16u, 64u, 1024u}) {
    DualQuaternionSoAStorage<float> s(64, poses);
    const auto v = s.view();
    EXPECT_EQ(v.stride % 16, 0u);
    EXPECT_GE(v.stride, poses);
    const auto c = v.components();
    for (std::size_t i = 0; i < 8; ++i) {
      EXPECT_EQ(reinterpret_cast<std::uintptr_t>(c[i].data()) % 64, 0u);
      EXPECT_EQ(c[i].size(), 64 * v.stride);
      if (i > 0) {
        const auto bytes = static_cast<std::size_t>(c[i].data() - c[i - 1].data()) * sizeof(float);
        EXPECT_NE(bytes % 4096, 0u);
      }
    }
  }
}

}  // namespace

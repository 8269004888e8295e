// Running a test once per instruction set the CPU has, for the run-time dispatched kernels.
#pragma once

#include <gtest/gtest.h>

#include <cstring>
#include <string>

#include "dq/simd/batch.hpp"

namespace dq::test {

/// Calls f(target) for every instruction set this CPU has (simd::use_target; scalar first), and
/// restores the best after.
template <class F>
void for_each_target(F f) {
  for (simd::Target t : {simd::Target::scalar, simd::Target::sse2, simd::Target::sse4, simd::Target::avx2, simd::Target::avx512}) {
    if (static_cast<int>(t) > static_cast<int>(simd::best_target())) break;
    ASSERT_EQ(simd::use_target(t), t);
    SCOPED_TRACE(std::string(simd::to_string(t)));
    f(t);
  }
  simd::use_target(simd::Target::avx512);
}

inline bool same_bits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

}  // namespace dq::test

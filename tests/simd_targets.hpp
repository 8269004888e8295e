// Running a test once per instruction set the CPU has, for the run-time dispatched kernels.
#pragma once

#include <gtest/gtest.h>

#include <cstring>
#include <string>

#include "dq/simd/batch.hpp"

namespace dq::test {

/// Calls f(target) for every instruction set this CPU has (simd::ScopedTarget; scalar first), and
/// restores the target in use after.
template <class F>
void for_each_target(F f) {
  for (simd::Target t : simd::available_targets()) {
    const simd::ScopedTarget scope(t);
    ASSERT_EQ(simd::current_target(), t);
    SCOPED_TRACE(std::string(simd::to_string(t)));
    f(t);
  }
}

inline bool same_bits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }
inline bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

}  // namespace dq::test

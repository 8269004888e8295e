// The long double reference of dq::sclerp<float> and of the batch sclerp kernel, shared by their
// tests (tests/test_simd.cpp) and the accuracy measurement (bench/interpolation_accuracy.cpp).
#pragma once

#include "dq/dq.hpp"

namespace dq::test {

/// dq::sclerp in long double on the same float inputs, on the arc dq::sclerp<float> (and the
/// kernel) chooses: by the sign of the float relative rotation's w. Where that w is within
/// rounding of 0 (rotations π apart) long double could choose the other arc.
inline DualQuaternion<long double> sclerp_reference(const DualQuaternion<float>& a, const DualQuaternion<float>& b, float t) {
  const bool flip = (a.conjugate() * b).real.w < 0.0f;
  const DualQuaternion<long double> al = a.cast<long double>(), bl = (flip ? -b : b).cast<long double>();
  const bool long_way = (al.conjugate() * bl).real.w < 0.0L;  // the arc of bl as given (w within rounding of 0)
  return sclerp(al, bl, static_cast<long double>(t), long_way ? Path::longest : Path::shortest);
}

}  // namespace dq::test

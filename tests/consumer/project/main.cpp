// A consumer of the installed package: compose two transforms and move a point.
#include <dq/dq.hpp>
#ifndef DQKIT_CORE_ONLY
#include <dq/anim/skeleton.hpp>
#endif

#include <cmath>
#include <cstdio>

int main() {
  const auto turn = dq::DualQuaternion<double>::from_rotation(
      dq::Quaternion<double>::from_axis_angle({0, 0, 1}, std::numbers::pi / 2));
  const auto shift = dq::DualQuaternion<double>::from_translation({1, 0, 0});
  const dq::Vec3<double> p = (shift * turn).transform_point({1, 0, 0});
  std::printf("%g %g %g\n", p.x, p.y, p.z);
#ifndef DQKIT_CORE_ONLY  // the compiled part: a skeleton from the installed static library
  dq::RawSkeleton raw;
  raw.add("root", -1);
  raw.add("child", 0, shift);
  if (!dq::build_skeleton(raw)) return 1;
#endif
  return (std::abs(p.x - 1) < 1e-15 && std::abs(p.y - 1) < 1e-15) ? 0 : 1;
}

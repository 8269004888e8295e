// Fuzz target: random bit patterns into the math. The documented NaN policy (docs/reliability.md)
// is checked: for finite inputs of magnitude below 1e150 every result is finite (and unit where
// promised); a NaN input gives NaN or a documented fallback, never a crash, UB or a hang.
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "check.hpp"
#include "dq/dq.hpp"

namespace {
using dq::fuzz::check;
bool finite(const dq::Quaternion<double>& q) { return std::isfinite(q.w + q.x + q.y + q.z); }
bool finite(const dq::DualQuaternion<double>& q) { return finite(q.real) && finite(q.dual); }
bool tame(double v) { return std::isfinite(v) && std::abs(v) < 1e150; }
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::array<double, 18> v{};
  std::memcpy(v.data(), data, std::min(size, sizeof v));
  using namespace dq;
  const Quaternion<double> q(v[0], v[1], v[2], v[3]);
  const DualQuaternion<double> d(q, Quaternion<double>(v[4], v[5], v[6], v[7]));
  // Tame: finite, below 1e150, and real parts not so small that dual/|real| (the translation)
  // overflows: the policy promises finite results only where they are representable.
  const bool all_tame = [&] {
    for (double x : v)
      if (!tame(x)) return false;
    return q.norm() > 1e-100 && Quaternion<double>(v[8], v[9], v[10], v[11]).norm() > 1e-100;
  }();
  const double t = std::isfinite(v[16]) ? std::fmod(v[16], 4.0) : 0.5;

  // Normalization: always unit (or identity) for tame input.
  const Quaternion<double> u = q.normalized();
  const DualQuaternion<double> du = d.normalized();
  if (all_tame) {
    check(std::abs(u.norm() - 1) < 1e-12, "normalized quaternion is unit");
    check(finite(du) && du.is_unit(1e-9), "normalized dual quaternion is unit");
  }
  // Conversions of the unit values.
  for (EulerOrder o : all_euler_orders)
    for (EulerFrame f : {EulerFrame::intrinsic, EulerFrame::extrinsic}) {
      const EulerExtraction<double> e = to_euler(u, o, f);
      if (all_tame) check(std::isfinite(e.angles.a + e.angles.b + e.angles.c), "euler angles finite");
    }
  const AxisAngle<double> aa = u.to_axis_angle();
  const Screw<double> s = to_screw(du);
  const VrmlTransform<double> vr = to_vrml(du);
  const DualQuaternion<double> m = from_matrix(to_mat4(du));
  if (all_tame) {
    check(std::isfinite(aa.angle), "axis-angle finite");
    check(std::isfinite(s.angle + s.translation), "screw finite");
    check(std::isfinite(vr.angle + vr.translation.x), "vrml finite");
    check(finite(m), "matrix round trip finite");
  }
  // log/exp, sclerp, slerp, dlb between two tame unit transforms.
  const DualQuaternion<double> e = DualQuaternion<double>(Quaternion<double>(v[8], v[9], v[10], v[11]),
                                                          Quaternion<double>(v[12], v[13], v[14], v[15])).normalized();
  const DualQuaternion<double> c = du.real.w < 0 ? -du : du;
  const DualQuaternion<double> l = exp(log(c));
  const DualQuaternion<double> sc = sclerp(du, e, t);
  const Quaternion<double> sl = slerp(u, e.real, t);
  const std::array<DualQuaternion<double>, 2> qs{du, e};
  const std::array<double, 2> w{std::abs(std::fmod(v[17], 1.0)), 1.0};
  const DualQuaternion<double> b = dlb<double>(qs, w);
  if (all_tame) {
    // The screw of a transform whose rotation is within a few ulps of 2π is ill-conditioned (its
    // axis is undefined); dqkit stays finite there but the round trip loses accuracy.
    check(finite(l), "exp(log) finite");
    check(finite(sc) && sc.is_unit(1e-6), "sclerp unit");
    check(finite(sl) && std::abs(sl.norm() - 1) < 1e-12, "slerp unit");
    check(finite(b) && b.is_unit(1e-9), "dlb unit");
  }
  return 0;
}

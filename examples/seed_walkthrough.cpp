// The main demo: walks through the seed documents' worked examples with dqkit, printing each
// result beside what the seed says (and where a seed is wrong, what is right).
#include <cmath>
#include <cstdio>
#include <string>

#include "dq/dq.hpp"

using namespace dq;

namespace {

void heading(const char* title) { std::printf("\n== %s\n", title); }
/// The label padded to 44 columns, counted as UTF-8 code points (φ, ½, − take one column and two
/// or three bytes: printf's %-44s counts bytes and misaligned the values after them), combining
/// marks (U+0300–U+036F, as the bar of Q̄) taking none.
std::string padded(const char* label) {
  std::string s = label;
  std::size_t columns = 0;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const auto c = static_cast<unsigned char>(s[i]);
    const bool combining = c == 0xCC || (c == 0xCD && i + 1 < s.size() && static_cast<unsigned char>(s[i + 1]) < 0xB0);
    columns += (c & 0xC0) != 0x80 && !combining;
  }
  if (columns < 44) s.append(44 - columns, ' ');
  return s;
}
void print(const char* label, const Vec3<double>& v) { std::printf("  %s (%.6f, %.6f, %.6f)\n", padded(label).c_str(), v.x, v.y, v.z); }
void print(const char* label, const Quaternion<double>& q) {
  std::printf("  %s (w %.6f, x %.6f, y %.6f, z %.6f)\n", padded(label).c_str(), q.w, q.x, q.y, q.z);
}
void print(const char* label, double v) { std::printf("  %s %.12g\n", padded(label).c_str(), v); }

}  // namespace

int main() {
  std::printf("dqkit: the seeds' worked examples\n");

  heading("Dual numbers differentiate (Kenwright §5.2): f(a + εb) = f(a) + ε b f'(a)");
  {
    auto f = [](auto x) { return x * x * x + sin(x); };  // f' = 3x² + cos x
    const Dual<double> y = f(Dual<double>::variable(0.5));
    print("f(0.5) = 0.125 + sin 0.5", y.real);
    print("f'(0.5) by dual numbers", y.dual);
    print("f'(0.5) = 0.75 + cos 0.5 (analytic)", 0.75 + std::cos(0.5));
    const HyperDual<double> h = f(HyperDual<double>::variable(0.5));
    print("f''(0.5) by hyper-dual numbers", h.e12);
    print("f''(0.5) = 3 − sin 0.5 (analytic)", 3 - std::sin(0.5));
  }

  heading("Dual quaternions: rotate, then translate (Q = r + ε ½ t r)");
  {
    const Quaternion<double> r = Quaternion<double>::from_axis_angle({0, 0, 1}, pi_v<double> / 2);
    const DualQuaternion<double> q = DualQuaternion<double>::from_rotation_translation(r, {1, 2, 3});
    print("90° about z, then (1, 2, 3): point (1, 0, 0) ->", q.transform_point({1, 0, 0}));
    print("the same as Q (1 + εp) Q̄ taken literally", q.transform_point_sandwich({1, 0, 0}));
    print("translation 2 q_d q_r*", q.translation());
    const Dual<double> n = q.norm();
    std::printf("  %s %.3g + ε %.3g\n", padded("dual norm |Q| (unit: 1 + ε0)").c_str(), n.real, n.dual);
  }

  heading("Kenwright's SimpleTest: compose three transforms, compare with 4x4 matrices");
  {
    // Quaternion.CreateFromYawPitchRoll(yaw, pitch, roll) in XNA is intrinsic YXZ (yaw about Y,
    // pitch about X, roll about Z) in our column-vector convention.
    auto ypr = [](double yaw, double pitch, double roll) { return from_euler(EulerOrder::YXZ, EulerFrame::intrinsic, yaw, pitch, roll); };
    const auto dq0 = DualQuaternion<double>::from_rotation_translation(ypr(1, 2, 3), {10, 30, 90});
    const auto dq1 = DualQuaternion<double>::from_rotation_translation(ypr(-1, 3, 2), {30, 40, 190});
    const auto dq2 = DualQuaternion<double>::from_rotation_translation(ypr(2, 3, 1.5), {5, 20, 66});
    // The listing multiplies "left to right" (dq0 applied first); in dqkit that is dq2 * dq1 * dq0.
    const DualQuaternion<double> all = dq2 * dq1 * dq0;
    const Mat4<double> m = to_mat4(dq2) * to_mat4(dq1) * to_mat4(dq0);
    const Vec3<double> p{1, 2, 3};
    print("dual quaternions: p = (1, 2, 3) ->", all.transform_point(p));
    print("4x4 matrices:     p = (1, 2, 3) ->", transform_point(m, p));
  }

  heading("Gimbal lock (Arends §2): Rx(φ) Ry(π/2) Rz(ψ) depends only on φ + ψ");
  {
    const double half_pi = pi_v<double> / 2;
    const Quaternion<double> a = from_euler(EulerOrder::XYZ, EulerFrame::intrinsic, 0.2, half_pi, 0.5);
    const Quaternion<double> b = from_euler(EulerOrder::XYZ, EulerFrame::intrinsic, 0.6, half_pi, 0.1);
    print("φ = 0.2, ψ = 0.5", a);
    print("φ = 0.6, ψ = 0.1 (same φ + ψ): the same", b);
    const EulerExtraction<double> e = to_euler(a, EulerOrder::XYZ, EulerFrame::intrinsic);
    std::printf("  %s (%.6f, %.6f, %.6f), singular = %s\n", padded("extracted (third angle set to 0)").c_str(), e.angles.a, e.angles.b, e.angles.c,
                e.singular ? "yes" : "no");
  }

  heading("SLERP's failure cases (Arends §6): equal endpoints and sin Ω ≈ 0");
  {
    const Quaternion<double> x(0, 1, 0, 0);
    const double omega = pi_v<double> / 2;  // the thesis plugs in the rotation's 90°
    const Quaternion<double> naive = x * (std::sin(0.5 * omega) / std::sin(omega)) + x * (std::sin(0.5 * omega) / std::sin(omega));
    print("thesis: slerp(x, x, ½) with Ω = 90°", naive);
    print("  its norm (should be 1)", naive.norm());
    print("dqkit slerp(x, x, ½)", slerp(x, x, 0.5));
    const Quaternion<double> y = Quaternion<double>(1, 1e-9, 0, 0).normalized();
    print("dqkit slerp(1, 1e-9 away, ½): norm", slerp(Quaternion<double>::identity(), y, 0.5).norm());
  }

  heading("VRML (§2.5): a Transform to a dual quaternion and back, for any input");
  {
    const VrmlTransform<double> node{{0, 1, 0}, pi_v<double> / 180, {1, 2, 3}, {}};  // rotation 0 1 0 1°
    const VrmlTransform<double> back = to_vrml(from_vrml(node));
    std::printf("  %s rotation %g %g %g %.9f, translation %g %g %g\n", padded("1° about y (the tutorial returned no rotation)").c_str(),
                back.axis.x, back.axis.y, back.axis.z, back.angle, back.translation.x, back.translation.y, back.translation.z);
  }

  heading("The 3D slider puzzle (§2.6): a piece turns 90° about an axis off the origin");
  {
    // A piece at (2.1, 0, 2.1) on the cube's +z face turns over the edge onto the +x face. As the
    // tutorial builds it: translate by −2.1 · transVec, rotate by 90° · value, translate back.
    const Vec3<double> trans_vec{1, 0, 0}, rot_vec{0, 1, 0};
    const auto piece = DualQuaternion<double>::from_translation({2.1, 0, 2.1});
    const auto rel_a = DualQuaternion<double>::from_translation(trans_vec * -2.1);
    for (double value : {0.0, 0.5, 1.0}) {
      const auto rel_b = from_vrml(VrmlTransform<double>{rot_vec, pi_v<double> / 2 * value, trans_vec * 2.1, {}});
      const DualQuaternion<double> pose = rel_b * rel_a * piece;
      std::printf("  value %.1f: centre (%.4f, %.4f, %.4f)\n", value, pose.translation().x, pose.translation().y, pose.translation().z);
    }
    const Screw<double> s = to_screw(from_vrml(VrmlTransform<double>{rot_vec, pi_v<double> / 2, trans_vec * 2.1, {}}) * rel_a);
    std::printf("  as a screw: angle %.6f about direction (%g, %g, %g) through (%g, %g, %g), slide %g\n", s.angle, s.axis.direction.x,
                s.axis.direction.y, s.axis.direction.z, s.axis.closest_point_to_origin().x, s.axis.closest_point_to_origin().y,
                s.axis.closest_point_to_origin().z, s.translation);
  }

  heading("Hyper-dual quaternions (Arends ch. 5): the same point, at several times the cost");
  {
    const Quaternion<double> r = Quaternion<double>::from_axis_angle({1, 1, 0}, 0.8);
    const Vec3<double> t{1, -2, 0.5}, p{0.3, 0.4, 0.5};
    print("hyper-dual quaternion", HyperDualQuaternion<double>::from_rotation_translation(r, t).transform_point(p));
    print("dual quaternion", DualQuaternion<double>::from_rotation_translation(r, t).transform_point(p));
  }

  heading("Screw linear interpolation: constant speed along one screw");
  {
    const auto a = DualQuaternion<double>::identity();
    const auto b = DualQuaternion<double>::from_rotation_translation(Quaternion<double>::from_axis_angle({0, 0, 1}, pi_v<double> / 2), {0, 0, 2});
    for (double t : {0.0, 0.25, 0.5, 0.75, 1.0}) {
      const DualQuaternion<double> m = sclerp(a, b, t);
      std::printf("  t = %.2f: angle %.4f rad, translation (%.4f, %.4f, %.4f)\n", t, m.real.to_axis_angle().angle, m.translation().x,
                  m.translation().y, m.translation().z);
    }
  }
  std::printf("\nAll examples ran. See docs/ for the conventions and the measured tables.\n");
  return 0;
}

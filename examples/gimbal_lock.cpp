// Gimbal lock made visible. A motion passes near Euler XYZ's singularity (the middle angle at
// π/2). Interpolating the Euler angles loses a degree of freedom there; quaternions and dual
// quaternions keep all three. Prints a table of both paths and the distance to the singularity.
#include <cmath>
#include <cstdio>

#include "dq/dq.hpp"

using namespace dq;

int main() {
  const double half_pi = pi_v<double> / 2;
  const EulerOrder order = EulerOrder::XYZ;
  const EulerFrame frame = EulerFrame::intrinsic;

  // The thesis' derivation, numerically: with the middle angle at π/2 only φ + ψ matters.
  std::printf("Rx(φ) Ry(π/2) Rz(ψ) for φ + ψ = 1:\n");
  for (double phi : {0.0, 0.25, 0.5, 1.0}) {
    const Quaternion<double> q = from_euler(order, frame, phi, half_pi, 1.0 - phi).canonical();
    std::printf("  φ = %.2f, ψ = %.2f -> q = (%.6f, %.6f, %.6f, %.6f)\n", phi, 1.0 - phi, q.w, q.x, q.y, q.z);
  }

  // Two keys near the singularity whose first and third angles nearly cancel: close rotations with
  // very different Euler triples. Interpolating the angles swings far away and back.
  const EulerAngles<double> k0{1.0, half_pi - 0.05, -1.0}, k1{-1.0, half_pi - 0.05, 1.0};
  const Quaternion<double> q0 = from_euler(order, frame, k0), q1 = from_euler(order, frame, k1);
  const double total = angular_distance(q0, q1);
  std::printf("\nInterpolating two keys near gimbal lock (total rotation %.4f rad):\n", total);
  std::printf("  %5s  %22s  %22s  %18s\n", "t", "Euler path angle from k0", "slerp path angle from k0", "Euler singularity");
  double euler_length = 0;
  Quaternion<double> previous = q0;
  for (int i = 0; i <= 10; ++i) {
    const double t = i / 10.0;
    const Quaternion<double> e = euler_interpolate(order, frame, k0, k1, t);
    const Quaternion<double> s = slerp(q0, q1, t);
    euler_length += angular_distance(previous, e);
    previous = e;
    std::printf("  %5.2f  %22.6f  %22.6f  %18.6f\n", t, angular_distance(q0, e), angular_distance(q0, s),
                euler_singularity_distance(e, order, frame));
  }
  std::printf("  Euler path length %.4f rad vs geodesic %.4f rad (a %.0f%% detour)\n", euler_length, total,
              100 * (euler_length / total - 1));

  // A dual quaternion carries the same rotation plus a translation through the same motion.
  const auto d0 = DualQuaternion<double>::from_rotation_translation(q0, {0, 0, 0});
  const auto d1 = DualQuaternion<double>::from_rotation_translation(q1, {1, 0, 0});
  const DualQuaternion<double> mid = sclerp(d0, d1, 0.5);
  std::printf("\nsclerp midpoint: rotation angle from k0 %.6f (= half of %.6f), translation (%.4f, %.4f, %.4f)\n",
              angular_distance(q0, mid.real), total, mid.translation().x, mid.translation().y, mid.translation().z);
  return 0;
}

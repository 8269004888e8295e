// The README's code examples, line for line (CTest `readme_examples_are_current` checks that every
// line of the README's C++ blocks stands here in order), compiled and run with their results
// checked.
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

// ---- README: Example -------------------------------------------------------------------------------
#include <dq/dq.hpp>
using namespace dq;

static int algebra_example() {
  // Rotate 90° about z, then translate by (1, 2, 3).
  const auto q = DualQuaternion<double>::from_rotation_translation(
      Quaternion<double>::from_axis_angle({0, 0, 1}, pi_v<double> / 2), {1, 2, 3});
  Vec3<double> p = q.transform_point({1, 0, 0});                 // (1, 3, 3)

  // Compose like matrices (B first), interpolate along the screw, blend, convert.
  const auto b = DualQuaternion<double>::from_translation({0, 0, 5});
  DualQuaternion<double> halfway = sclerp(q, q * b, 0.5);        // constant-speed screw motion
  Mat4<double> m = to_mat4(q * b);                               // column-major, column vectors
  EulerExtraction<double> e = to_euler(q.real, EulerOrder::ZYX, EulerFrame::intrinsic);
  Screw<double> s = to_screw(q);                                 // axis, angle, slide

  // The same generic code differentiates, exactly: f'(0.3) with f(x) = sin(x) eˣ.
  auto f = [](auto x) { return sin(x) * exp(x); };
  double derivative = f(Dual<double>::variable(0.3)).dual;

  // What the comments promise.
  const bool ok = std::abs(p.x - 1) < 1e-15 && std::abs(p.y - 3) < 1e-15 && std::abs(p.z - 3) < 1e-15 &&
                  std::abs(halfway.translation().x - (q * DualQuaternion<double>::from_translation({0, 0, 2.5})).translation().x) < 1e-12 &&
                  std::abs(m(2, 3) - 8) < 1e-15 && std::abs(e.angles.a - pi_v<double> / 2) < 1e-15 && std::abs(s.angle - pi_v<double> / 2) < 1e-15 &&
                  std::abs(derivative - (std::cos(0.3) + std::sin(0.3)) * std::exp(0.3)) < 1e-15;
  std::printf("algebra example: %s\n", ok ? "ok" : "WRONG");
  return ok ? 0 : 1;
}

// ---- README: A character in a few lines ---------------------------------------------------------------
#include <dq/anim/animation.hpp>
#include <dq/anim/forward_kinematics.hpp>
#include <dq/io/bvh.hpp>

static int character_example(const std::string& path) {
  dq::Expected<dq::BvhFile> bvh = dq::read_bvh_file(path);  // e.g. CMU 01_01.bvh
  if (!bvh) { std::puts(bvh.error().message.c_str()); return 1; }   // "01_01.bvh:12: expected ..."
  dq::Skeleton skeleton = *dq::bvh_skeleton(*bvh);
  dq::Animation anim = dq::bvh_animation(*bvh, skeleton);
  std::vector<dq::DualQuaternion<double>> local(skeleton.size()), model(skeleton.size());
  dq::sample<double>(anim, 1.25, dq::Interpolation::screw, dq::WrapMode::loop, local);  // any time
  dq::local_to_model<dq::DualQuaternion<double>>(skeleton, local, model);               // world transforms

  const Vec3<double> head = model[static_cast<std::size_t>(skeleton.find("Head"))].translation();
  std::printf("character example: the head at 1.25 s is at (%.3f, %.3f, %.3f)\n", head.x, head.y, head.z);
  return std::isfinite(head.x) ? 0 : 1;
}

// ---- README: Many at once -----------------------------------------------------------------------------
#include <dq/simd/batch.hpp>

static int batch_example() {
  const std::size_t n = 1000;
  std::vector<dq::DualQuaternion<float>> a(n), b(n);                // filled by the caller
  for (std::size_t i = 0; i < n; ++i) {
    a[i] = dq::DualQuaternion<float>::from_rotation_translation(Quaternion<float>::from_axis_angle({0, 0, 1}, 0.001f * float(i)), {1, 2, 3});
    b[i] = dq::DualQuaternion<float>::from_translation({float(i), 0, 0});
  }
  const std::vector<dq::DualQuaternion<float>> a0 = a;
  dq::ComponentArrays<float, 8> ra(n), rb(n);                       // eight aligned arrays each
  dq::simd::to_rows(a, dq::simd::rows(ra));
  dq::simd::to_rows(b, dq::simd::rows(rb));
  dq::simd::compose(dq::simd::rows(ra), dq::simd::rows(rb), dq::simd::rows(ra), n);  // a[i] · b[i], in place
  dq::simd::from_rows(dq::simd::rows(ra), a);                       // the scalar product's bits
  const std::vector<dq::DualQuaternion<float>> a1 = a;

  dq::simd::compose(a, b, a);                                       // the same on the vectors themselves
  const std::size_t m = 37;
  std::vector<dq::Vec3<double>> cloud(m);                           // a point cloud (x, y, z each)
  for (std::size_t i = 0; i < m; ++i) cloud[i] = {double(i), 1, -2};
  const std::vector<dq::Vec3<double>> cloud0 = cloud;
  dq::simd::transform_points(a[0].cast<double>(), cloud, cloud);    // moved in place by a[0], in double

  bool ok = true;
  for (std::size_t i = 0; i < n; ++i) ok = ok && a1[i] == a0[i] * b[i] && a[i] == a1[i] * b[i];
  for (std::size_t i = 0; i < m; ++i) ok = ok && cloud[i] == a[0].cast<double>().transform_point(cloud0[i]);
  std::printf("batch example: %s\n", ok ? "ok" : "WRONG");
  return ok ? 0 : 1;
}

int main(int argc, char** argv) {
  const int a = algebra_example();
  const int b = argc > 1 ? character_example(argv[1]) : 0;
  return a | b | batch_example();
}

// Whether a peer's result is the transform dqkit computes: the benchmarks check once, outside the
// timing, that every variant of a case computes the same thing. Each library's transform is read
// as a 4x4 matrix in double: dqkit's dual quaternions and matrices, Eigen's Matrix4 and Isometry3,
// GLM's mat4 and dualquat.
#pragma once

#include <Eigen/Geometry>
#include <cmath>
#include <glm/gtx/dual_quaternion.hpp>

#include "dq/convert/matrix.hpp"
#include "dq/interop/glm.hpp"

namespace dq::bench {

/// Any matrix read element by element through `at(r, c)`; rows past its last are (0, 0, 0, 1).
template <int Rows, class At>
Mat4<double> read_mat4(At at) {
  Mat4<double> out = Mat4<double>::identity();
  for (int r = 0; r < Rows; ++r)
    for (int c = 0; c < 4; ++c) out(r, c) = double(at(r, c));
  return out;
}
template <class T>
Mat4<double> as_mat4(const DualQuaternion<T>& x) { return to_mat4(x.template cast<double>()); }
template <class T>
Mat4<double> as_mat4(const Mat4<T>& x) { return read_mat4<4>([&](int r, int c) { return x(r, c); }); }
template <class T>
Mat4<double> as_mat4(const Mat34<T>& x) { return read_mat4<3>([&](int r, int c) { return x(r, c); }); }
template <class T>
Mat4<double> as_mat4(const glm::tdualquat<T>& x) { return as_mat4(glm_interop::from_glm(x)); }
template <class T>
Mat4<double> as_mat4(const glm::mat<4, 4, T>& x) { return read_mat4<4>([&](int r, int c) { return x[c][r]; }); }
template <class T>
Mat4<double> as_mat4(const Eigen::Matrix<T, 4, 4>& x) { return read_mat4<4>([&](int r, int c) { return x(r, c); }); }
template <class T>
Mat4<double> as_mat4(const Eigen::Transform<T, 3, Eigen::Isometry>& x) { return as_mat4(Eigen::Matrix<T, 4, 4>(x.matrix())); }

/// Whether `got` is the rigid transform `expected`: every rotation entry within `tolerance`, every
/// translation entry within `tolerance` · (1 + |expected's translation|), since a float translation
/// of length 100 is rounded a hundred times coarser than one of length 1.
template <class A, class B>
bool same_transform(const A& got, const B& expected, double tolerance) {
  const Mat4<double> g = as_mat4(got), e = as_mat4(expected);
  const double translation_scale = 1 + std::hypot(e(0, 3), e(1, 3), e(2, 3));
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) {
      const double limit = (c == 3 && r < 3) ? tolerance * translation_scale : tolerance;
      if (!(std::abs(g(r, c) - e(r, c)) <= limit)) return false;  // NaN fails too
    }
  return true;
}

}  // namespace dq::bench

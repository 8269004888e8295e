// Conversions to and from GLM (header-only; include only where GLM is available).
//
// glm::quat's four-argument constructor is (w, x, y, z) by default; these functions use the named
// members, so they are right whatever GLM_FORCE_QUAT_DATA_XYZW says. glm::dualquat stores
// (real, dual) with the same ½ t r convention as dqkit, and glm::mat4 is column-major with
// column vectors, so no convention changes at this boundary. GLM's own dual-quaternion
// `normalize` only divides by |q_r| and does not restore q_r · q_d = 0; use dqkit's.
#pragma once

#include <glm/gtc/quaternion.hpp>
#include <glm/gtx/dual_quaternion.hpp>
#include <glm/mat4x4.hpp>

#include "dq/convert/matrix.hpp"
#include "dq/core/dual_quaternion.hpp"

namespace dq::glm_interop {

template <class T, glm::qualifier Q = glm::defaultp>
glm::qua<T, Q> to_glm(const Quaternion<T>& q) {
  glm::qua<T, Q> g;
  g.w = q.w;
  g.x = q.x;
  g.y = q.y;
  g.z = q.z;
  return g;
}
template <class T, glm::qualifier Q>
Quaternion<T> from_glm(const glm::qua<T, Q>& q) {
  return {q.w, q.x, q.y, q.z};
}
template <class T, glm::qualifier Q = glm::defaultp>
glm::tdualquat<T, Q> to_glm(const DualQuaternion<T>& q) {
  return glm::tdualquat<T, Q>(to_glm<T, Q>(q.real), to_glm<T, Q>(q.dual));
}
template <class T, glm::qualifier Q>
DualQuaternion<T> from_glm(const glm::tdualquat<T, Q>& q) {
  return {from_glm(q.real), from_glm(q.dual)};
}
template <class T, glm::qualifier Q = glm::defaultp>
glm::mat<4, 4, T, Q> to_glm(const Mat4<T>& m) {
  glm::mat<4, 4, T, Q> g;
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) g[c][r] = m(r, c);  // g[column][row]
  return g;
}
template <class T, glm::qualifier Q>
Mat4<T> from_glm(const glm::mat<4, 4, T, Q>& g) {
  Mat4<T> m;
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) m(r, c) = g[c][r];
  return m;
}

}  // namespace dq::glm_interop

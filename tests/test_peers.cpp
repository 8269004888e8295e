// Cross-checks against the peers users compare with: Eigen and GLM, inside the same test.
// Convention differences found are asserted here and documented in docs/conventions.md.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtx/dual_quaternion.hpp>

#include "dq/interop/eigen.hpp"
#include "dq/interop/glm.hpp"
#include "support.hpp"

namespace {

using namespace dq;
using dq::test::max_abs_diff;
using dq::test::Random;

TEST(Eigen, QuaternionProductAndMatrix) {
  Random rng(91);
  for (int n = 0; n < 2000; ++n) {
    const Quaternion<double> a = rng.rotation<double>(), b = rng.rotation<double>();
    const Quaternion<double> ours = a * b;
    const Quaternion<double> theirs = eigen::from_eigen(eigen::to_eigen(a) * eigen::to_eigen(b));
    EXPECT_LE(max_abs_diff(ours, theirs), 1e-15);
    const Eigen::Matrix3d m = eigen::to_eigen(a).toRotationMatrix();
    const Mat3<double> mine = a.to_matrix();
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(mine(r, c), m(r, c), 1e-15);
    const Vec3<double> v = rng.vec3<double>(2);
    EXPECT_LE(max_abs_diff(a.rotate(v), eigen::from_eigen(Eigen::Vector3d(eigen::to_eigen(a) * eigen::to_eigen(v)))), 1e-14);
    // Eigen's FromTwoVectors.
    const Vec3<double> u = rng.vec3<double>(2), w = rng.vec3<double>(2);
    const Quaternion<double> e2 = eigen::from_eigen(Eigen::Quaterniond::FromTwoVectors(eigen::to_eigen(u), eigen::to_eigen(w)));
    EXPECT_LE(dq::test::rotation_diff(Quaternion<double>::from_two_vectors(u, w), e2), 1e-13);
    // slerp-free quantities: angular distance equals Eigen's angularDistance.
    EXPECT_NEAR(angular_distance(a, b), eigen::to_eigen(a).angularDistance(eigen::to_eigen(b)), 1e-13);
  }
}

TEST(Eigen, EulerAnglesAgreeWithEigen) {
  // Eigen's eulerAngles(a0, a1, a2) returns intrinsic angles: R = R_a0 R_a1 R_a2, with the first
  // angle in [0, π]; compare rotations (not triples), and our triple against Eigen's matrix.
  Random rng(92);
  for (EulerOrder order : all_euler_orders) {
    const auto ax = euler_axes(order);
    for (int n = 0; n < 300; ++n) {
      const Quaternion<double> q = rng.rotation<double>();
      const Eigen::Matrix3d m = eigen::to_eigen(q).toRotationMatrix();
      const Eigen::Vector3d e = m.eulerAngles(ax[0], ax[1], ax[2]);
      const Quaternion<double> from_eigen_angles = from_euler(order, EulerFrame::intrinsic, e[0], e[1], e[2]);
      EXPECT_LE(dq::test::rotation_diff(from_eigen_angles, q), 1e-12) << to_string(order);
      const EulerAngles<double> ours = to_euler(q, order, EulerFrame::intrinsic).angles;
      const Eigen::Matrix3d rebuilt = (Eigen::AngleAxisd(ours.a, Eigen::Vector3d::Unit(ax[0])) *
                                       Eigen::AngleAxisd(ours.b, Eigen::Vector3d::Unit(ax[1])) *
                                       Eigen::AngleAxisd(ours.c, Eigen::Vector3d::Unit(ax[2])))
                                          .toRotationMatrix();
      EXPECT_LE((rebuilt - m).cwiseAbs().maxCoeff(), 1e-13) << to_string(order);
    }
  }
}

TEST(Eigen, IsometryAndMatrix4) {
  Random rng(93);
  for (int n = 0; n < 1000; ++n) {
    const DualQuaternion<double> q = rng.rigid<double>(), r = rng.rigid<double>();
    const Eigen::Isometry3d iq = eigen::to_isometry(q), ir = eigen::to_isometry(r);
    const Vec3<double> p = rng.vec3<double>(5);
    EXPECT_LE(max_abs_diff(q.transform_point(p), eigen::from_eigen(Eigen::Vector3d(iq * eigen::to_eigen(p)))), 1e-13);
    EXPECT_LE(max_abs_diff((q * r).transform_point(p), eigen::from_eigen(Eigen::Vector3d((iq * ir) * eigen::to_eigen(p)))), 1e-12);
    EXPECT_TRUE(approx_equal(eigen::from_isometry(iq), q, 1e-13, SignPolicy::same_rotation));
    const Eigen::Matrix4d m = eigen::to_eigen(to_mat4(q));
    EXPECT_LE((m - iq.matrix()).cwiseAbs().maxCoeff(), 1e-14);
    EXPECT_EQ(eigen::from_eigen(m), to_mat4(q));
  }
}

TEST(Glm, QuaternionAndDualQuaternion) {
  Random rng(94);
  for (int n = 0; n < 2000; ++n) {
    const Quaternion<double> a = rng.rotation<double>(), b = rng.rotation<double>();
    EXPECT_LE(max_abs_diff(glm_interop::from_glm(glm_interop::to_glm(a) * glm_interop::to_glm(b)), a * b), 1e-15);
    // GLM's dualquat(orientation, translation) is our from_rotation_translation (same ½ t r).
    const Vec3<double> t = rng.vec3<double>(10);
    const glm::ddualquat g(glm_interop::to_glm(a), glm::dvec3(t.x, t.y, t.z));
    const DualQuaternion<double> mine = DualQuaternion<double>::from_rotation_translation(a, t);
    EXPECT_LE(max_abs_diff(glm_interop::from_glm(g), mine), 1e-14);
    // Products agree.
    const DualQuaternion<double> other = rng.rigid<double>();
    EXPECT_LE(max_abs_diff(glm_interop::from_glm(g * glm_interop::to_glm(other)), mine * other), 1e-13);
    // Point transform: GLM's dualquat * vec3.
    const Vec3<double> p = rng.vec3<double>(5);
    const glm::dvec3 gp = g * glm::dvec3(p.x, p.y, p.z);
    EXPECT_LE(max_abs_diff(Vec3<double>{gp.x, gp.y, gp.z}, mine.transform_point(p)), 1e-13);
    // glm::mat4_cast: GLM indexes [column][row]; the rotation block equals ours.
    const glm::dmat4 gm = glm::mat4_cast(glm_interop::to_glm(a));
    const Mat3<double> mr = a.to_matrix();
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(gm[c][r], mr(r, c), 1e-15);
  }
}

TEST(Glm, GlmNormalizeLeavesTheDualPartNonOrthogonal) {
  // The convention difference worth knowing: glm::normalize(dualquat) divides by |q_r| only.
  Random rng(95);
  const DualQuaternion<double> q = rng.rigid<double>();
  DualQuaternion<double> drifted = q * 1.5;
  drifted.dual = drifted.dual + drifted.real * 0.05;
  const DualQuaternion<double> by_glm = glm_interop::from_glm(glm::normalize(glm_interop::to_glm(drifted)));
  EXPECT_GT(std::abs(dot(by_glm.real, by_glm.dual)), 1e-3);
  EXPECT_LT(std::abs(dot(drifted.normalized().real, drifted.normalized().dual)), 1e-15);
}

}  // namespace

// Hyper-dual quaternions (Arends thesis ch. 5): the rigid transform of a point, against dual
// quaternions, and the thesis' own formula shown to be wrong where it is.
#include <gtest/gtest.h>

#include <limits>

#include "support.hpp"

namespace {

using namespace dq;
using dq::test::max_abs_diff;

TEST(HyperDualQuaternion, TransformOfAPointEqualsTheDualQuaternionOne) {
  dq::test::Random rng(51);
  for (int n = 0; n < 2000; ++n) {
    const Quaternion<double> r = rng.rotation<double>();
    const Vec3<double> t = rng.vec3<double>(10), p = rng.vec3<double>(10);
    const auto h = HyperDualQuaternion<double>::from_rotation_translation(r, t);
    const auto q = DualQuaternion<double>::from_rotation_translation(r, t);
    EXPECT_LE(max_abs_diff(h.transform_point(p), q.transform_point(p)), 1e-13);
    // The same operations on the same values: bit-identical, except where GCC's vectorizer fuses
    // multiply-adds in one inlined copy and not the other, which it does with FMA enabled even
    // under -ffp-contract=off (docs/design.md): then within a few ulps of the result.
#if defined(__FMA__)
    const double same = 8 * std::numeric_limits<double>::epsilon() * (1 + norm(p) + norm(t));
#else
    const double same = 0.0;
#endif
    EXPECT_LE(max_abs_diff(h.transform_point(p), HyperDualQuaternion<double>::from_dual_quaternion(q).transform_point(p)), same);
  }
}

TEST(HyperDualQuaternion, ProductMatchesHyperDualNumberRule) {
  // With real (w-only) quaternion coefficients the product must reduce to the hyper-dual product.
  auto real_q = [](double v) { return Quaternion<double>(v, 0, 0, 0); };
  const HyperDualQuaternion<double> a{real_q(2), real_q(3), real_q(5), real_q(7)};
  const HyperDualQuaternion<double> b{real_q(11), real_q(13), real_q(17), real_q(19)};
  const HyperDual<double> ha(2, 3, 5, 7), hb(11, 13, 17, 19);
  const auto p = a * b;
  const auto hp = ha * hb;
  EXPECT_EQ(p.a.w, hp.real);
  EXPECT_EQ(p.b.w, hp.e1);
  EXPECT_EQ(p.c.w, hp.e2);
  EXPECT_EQ(p.d.w, hp.e12);
}

TEST(HyperDualQuaternion, ThesisDualPartHalfTIsOnlyRightWithoutRotation) {
  // The thesis writes q = (cos θ/2, n sin θ/2) + ε1ε2 (0, T/2). Taken literally, that is not
  // "rotate, then translate by T" once there is a rotation.
  const Quaternion<double> r = Quaternion<double>::from_axis_angle(Vec3<double>{0, 0, 1}, 1.0);
  const Vec3<double> t{1, 2, 3}, p{0.5, -1, 2};
  const Quaternion<double> zero(0, 0, 0, 0);
  const HyperDualQuaternion<double> thesis{r, zero, zero, Quaternion<double>::pure(t * 0.5)};
  const Vec3<double> expected = r.rotate(p) + t;
  EXPECT_GT(max_abs_diff(thesis.transform_point(p), expected), 0.1);
  EXPECT_LE(max_abs_diff(HyperDualQuaternion<double>::from_rotation_translation(r, t).transform_point(p), expected), 1e-14);
  // Without rotation it is right.
  const HyperDualQuaternion<double> pure{Quaternion<double>::identity(), zero, zero, Quaternion<double>::pure(t * 0.5)};
  EXPECT_LE(max_abs_diff(pure.transform_point(p), p + t), 1e-15);
}

TEST(HyperDualQuaternion, InducedConjugateWouldCancelTheTranslation) {
  // Why the thesis' conjugate flips the sign of the ε1ε2 part: conjugating ε1 and ε2 separately
  // (which keeps ε1ε2) loses the translation.
  const auto h = HyperDualQuaternion<double>::from_rotation_translation(Quaternion<double>::identity(), Vec3<double>{1, 2, 3});
  HyperDualQuaternion<double> induced = h.conjugate();
  induced.d = h.d.conjugate();
  const auto out = (h * HyperDualQuaternion<double>::point(Vec3<double>{0, 0, 0}) * induced).d.vec();
  EXPECT_EQ(out, (Vec3<double>{0, 0, 0}));
  EXPECT_EQ(h.transform_point(Vec3<double>{0, 0, 0}), (Vec3<double>{1, 2, 3}));
}

}  // namespace

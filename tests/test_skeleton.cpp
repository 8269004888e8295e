// Skeletons: the builder's validation (each invalid field), forward kinematics with dual
// quaternions against 4x4 matrices, partial updates, the batch job, and the biped rig.
#include <gtest/gtest.h>

#include <limits>
#include <utility>
#include <vector>

#include "dq/anim/animation.hpp"
#include "dq/anim/biped.hpp"
#include "dq/anim/forward_kinematics.hpp"
#include "dq/simd/batch.hpp"
#include "support.hpp"

namespace {

using namespace dq;
using dq::test::max_abs_diff;

RawSkeleton small_tree() {
  RawSkeleton raw;
  // Deliberately out of order: children listed before parents.
  raw.add("hand", 2, DualQuaternion<double>::from_translation({0, 0, 1}));
  raw.add("root", -1);
  raw.add("arm", 1, DualQuaternion<double>::from_translation({1, 0, 0}));
  raw.add("leg", 1, DualQuaternion<double>::from_translation({0, -1, 0}));
  raw.add("foot", 3, DualQuaternion<double>::from_translation({0, -1, 0}));
  return raw;
}

TEST(SkeletonBuilder, OrdersParentsBeforeChildrenWithContiguousSubtrees) {
  const Expected<Skeleton> s = build_skeleton(small_tree());
  ASSERT_TRUE(s) << s.error().message;
  ASSERT_EQ(s->size(), 5u);
  for (std::size_t j = 0; j < s->size(); ++j) EXPECT_LT(s->parents()[j], static_cast<int>(j));
  EXPECT_EQ(s->names()[0], "root");
  const int arm = s->find("arm"), leg = s->find("leg");
  EXPECT_EQ(s->subtree_end(static_cast<std::size_t>(arm)) - static_cast<std::size_t>(arm), 2u);  // arm, hand
  EXPECT_EQ(s->subtree_end(static_cast<std::size_t>(leg)) - static_cast<std::size_t>(leg), 2u);  // leg, foot
  EXPECT_EQ(s->subtree_end(0), 5u);
  EXPECT_EQ(s->find("nobody"), -1);
}

TEST(SkeletonBuilder, EveryInvalidFieldIsNamed) {
  auto error_of = [](RawSkeleton raw) {
    const Expected<Skeleton> s = build_skeleton(raw);
    EXPECT_FALSE(s);
    return s ? std::string() : s.error().message;
  };
  {
    RawSkeleton r = small_tree();
    r.joints[3].name = "";
    EXPECT_NE(error_of(r).find("joint 3: empty name"), std::string::npos);
  }
  {
    RawSkeleton r = small_tree();
    r.joints[4].name = "arm";
    EXPECT_NE(error_of(r).find("joint 4 'arm': duplicate name"), std::string::npos);
  }
  {
    RawSkeleton r = small_tree();
    r.joints[0].parent = 17;
    EXPECT_NE(error_of(r).find("'hand': parent index 17 out of range"), std::string::npos);
  }
  {
    RawSkeleton r = small_tree();
    r.joints[2].parent = 2;
    EXPECT_NE(error_of(r).find("'arm': parent index 2"), std::string::npos);
  }
  {
    RawSkeleton r = small_tree();
    r.joints[2].parent = 0;  // arm <- hand <- arm: a cycle
    EXPECT_NE(error_of(r).find("cycle"), std::string::npos);
  }
  {
    RawSkeleton r = small_tree();
    r.joints[1].rest.dual.x = std::numeric_limits<double>::quiet_NaN();
    EXPECT_NE(error_of(r).find("'root': rest transform is not finite"), std::string::npos);
  }
  {
    RawSkeleton r = small_tree();
    r.joints[4].rest = r.joints[4].rest * 2.0;
    EXPECT_NE(error_of(r).find("'foot': rest transform is not a unit"), std::string::npos);
  }
  EXPECT_TRUE(build_skeleton(RawSkeleton{}));  // empty is valid
}

TEST(ForwardKinematics, DualQuaternionsEqualMatrices) {
  const Biped& biped = Biped::instance();
  dq::test::Random rng(301);
  std::vector<double> q(Biped::dofs);
  std::vector<DualQuaternion<double>> local(Biped::links), model(Biped::links);
  std::vector<Mat4<double>> mlocal(Biped::links), mmodel(Biped::links);
  for (int n = 0; n < 200; ++n) {
    for (auto& v : q) v = rng.uniform(-1.0, 1.0);
    biped.pose(q, local);
    for (std::size_t j = 0; j < local.size(); ++j) mlocal[j] = to_mat4(local[j]);
    local_to_model<DualQuaternion<double>>(biped.skeleton(), local, model);
    local_to_model(biped.skeleton(), mlocal, mmodel);  // the container overload: the type deduced
    for (std::size_t j = 0; j < model.size(); ++j) EXPECT_LE(max_abs_diff(to_mat4(model[j]), mmodel[j]), 1e-14);
  }
}

TEST(ForwardKinematics, SubtreeUpdateEqualsFullUpdate) {
  const Biped& biped = Biped::instance();
  dq::test::Random rng(302);
  std::vector<double> q(Biped::dofs);
  for (auto& v : q) v = rng.uniform(-1.0, 1.0);
  std::vector<DualQuaternion<double>> local(Biped::links), model(Biped::links), full(Biped::links);
  biped.pose(q, local);
  local_to_model<DualQuaternion<double>>(biped.skeleton(), local, model);
  const std::size_t arm = static_cast<std::size_t>(biped.skeleton().find("left_upper_arm"));
  local[arm] = local[arm] * DualQuaternion<double>::from_rotation(Quaternion<double>::from_axis_angle({0, 0, 1}, 0.5));
  const std::vector<DualQuaternion<double>> before = model;
  update_subtree<DualQuaternion<double>>(biped.skeleton(), arm, local, model);
  local_to_model<DualQuaternion<double>>(biped.skeleton(), local, full);
  for (std::size_t j = 0; j < model.size(); ++j) {
    EXPECT_EQ(model[j], full[j]) << j;
    const bool in_subtree = j >= arm && j < biped.skeleton().subtree_end(arm);
    if (!in_subtree) {
      EXPECT_EQ(model[j], before[j]) << j;  // untouched outside the subtree
    }
  }
}

TEST(ForwardKinematics, BatchJobEqualsPerPoseAndValidates) {
  const Biped& biped = Biped::instance();
  const std::size_t poses = 37, joints = Biped::links;
  dq::test::Random rng(303);
  DualQuaternionSoAStorage<float> local_store(joints, poses), model_store(joints, poses);
  auto local = local_store.view(), model = model_store.view();
  std::vector<std::vector<DualQuaternion<double>>> expected(poses, std::vector<DualQuaternion<double>>(joints));
  std::vector<double> q(Biped::dofs);
  for (std::size_t p = 0; p < poses; ++p) {
    for (auto& v : q) v = rng.uniform(-1.0, 1.0);
    std::vector<DualQuaternion<double>> l(joints);
    biped.pose(q, l);
    for (std::size_t j = 0; j < joints; ++j)
      local.set(j, p, l[j].cast<float>());
    local_to_model<DualQuaternion<double>>(biped.skeleton(), l, expected[p]);
  }
  ForwardKinematicsJob<float> job{biped.skeleton().parents(), local, model, 0, poses};
  ASSERT_TRUE(job.validate());
  for (unsigned threads : {1u, 2u, 4u}) {
    ASSERT_TRUE(simd::run_parallel(job, threads, 4));
    for (std::size_t p = 0; p < poses; ++p)
      for (std::size_t j = 0; j < joints; ++j) {
        const DualQuaternion<float> m = model.get(j, p);
        const Vec3<double> t = m.translation().cast<double>();
        EXPECT_LE(max_abs_diff(t, expected[p][j].translation()), 2e-6);
      }
  }
  // Each invalid field is reported.
  ForwardKinematicsJob<float> bad = job;
  bad.pose_count = local.stride + 1;  // the stride is padded past `poses`
  EXPECT_FALSE(bad.validate());
  bad = job;
  bad.model.rw = bad.model.rw.subspan(0, 3);
  EXPECT_FALSE(bad.validate());
  bad = job;
  bad.model.stride = 1;
  EXPECT_NE(bad.validate().error().message.find("strides differ"), std::string::npos);
  const std::vector<int> wrong_order{1, -1};
  bad = job;
  bad.parents = wrong_order;
  EXPECT_FALSE(bad.validate());
}

TEST(Biped, SixteenLinksThirtySixDofsWithinLimits) {
  const Biped& biped = Biped::instance();
  EXPECT_EQ(biped.skeleton().size(), 16u);
  EXPECT_EQ(biped.dof_table().size(), 36u);
  std::size_t translations = 0;
  for (const BipedDof& d : biped.dof_table()) {
    EXPECT_GE(d.joint, 0);
    EXPECT_LT(d.lower, d.upper) << d.name;
    translations += d.kind == DofKind::translation;
  }
  EXPECT_EQ(translations, 3u);
  // The rest pose: feet on the ground below the pelvis, symmetric left/right.
  std::vector<double> zero(Biped::dofs, 0.0);
  std::vector<DualQuaternion<double>> local(Biped::links), model(Biped::links);
  biped.pose(zero, local);
  local_to_model<DualQuaternion<double>>(biped.skeleton(), local, model);
  const Vec3<double> lf = model[static_cast<std::size_t>(biped.skeleton().find("left_foot"))].translation();
  const Vec3<double> rf = model[static_cast<std::size_t>(biped.skeleton().find("right_foot"))].translation();
  EXPECT_NEAR(lf.y, 0.07, 1e-12);
  EXPECT_NEAR(lf.x, -rf.x, 1e-15);
  // Clamping respects every limit.
  std::vector<double> wild(Biped::dofs, 100.0);
  const auto c = biped.clamp(wild);
  for (std::size_t i = 0; i < Biped::dofs; ++i) EXPECT_EQ(c[i], biped.dof_table()[i].upper);
  // A knee DOF bends about x only.
  std::vector<double> bend(Biped::dofs, 0.0);
  for (std::size_t i = 0; i < Biped::dofs; ++i)
    if (biped.dof_table()[i].name == "left_knee") bend[i] = 1.0;
  biped.pose(bend, local);
  const auto knee = local[static_cast<std::size_t>(biped.skeleton().find("left_shin"))].real.to_axis_angle();
  EXPECT_NEAR(knee.angle, 1.0, 1e-15);
  EXPECT_LE(max_abs_diff(knee.axis, Vec3<double>{1, 0, 0}), 1e-15);
}

TEST(Animation, SamplingModesClampAndLoop) {
  Animation anim;
  anim.frame_time = 0.5;
  anim.frame_count = 3;
  anim.joint_count = 1;
  const auto r = [](double a) { return Quaternion<double>::from_axis_angle({0, 0, 1}, a); };
  anim.locals = {DualQuaternion<double>::from_rotation_translation(r(0), {0, 0, 0}),
                 DualQuaternion<double>::from_rotation_translation(r(1), {1, 0, 0}),
                 DualQuaternion<double>::from_rotation_translation(r(2), {2, 0, 0})};
  std::array<DualQuaternion<double>, 1> out;
  for (Interpolation mode : {Interpolation::screw, Interpolation::dual_quaternion_linear, Interpolation::decoupled, Interpolation::matrix}) {
    sample<double>(anim, 0.5, mode, WrapMode::clamp, out);
    EXPECT_TRUE(approx_equal(out[0], anim.locals[1], 1e-12, SignPolicy::same_rotation));  // on a key
    sample<double>(anim, 0.75, mode, WrapMode::clamp, out);
    EXPECT_NEAR(out[0].real.to_axis_angle().angle, 1.5, 1e-9);  // halfway (symmetric for every mode)
    EXPECT_TRUE(out[0].is_unit(1e-12));
    sample<double>(anim, 99.0, mode, WrapMode::clamp, out);
    EXPECT_TRUE(approx_equal(out[0], anim.locals[2], 1e-12, SignPolicy::same_rotation));
    sample<double>(anim, -3.0, mode, WrapMode::clamp, out);
    EXPECT_TRUE(approx_equal(out[0], anim.locals[0], 1e-12, SignPolicy::same_rotation));
    sample<double>(anim, 1.5 + 0.5 * 3, mode, WrapMode::loop, out);  // period 1.5 s: frame 0 again
    EXPECT_TRUE(approx_equal(out[0], anim.locals[0], 1e-12, SignPolicy::same_rotation));
  }
  // The container overload deduces the scalar type and samples the same.
  std::vector<DualQuaternion<double>> deduced(1);
  sample(anim, 0.8, Interpolation::screw, WrapMode::clamp, deduced);
  sample<double>(anim, 0.8, Interpolation::screw, WrapMode::clamp, out);
  EXPECT_EQ(deduced[0], out[0]);
  // Times at and beyond the ends of double: ±∞ clamps like any time past an end, also where
  // time ÷ frame_time overflows; NaN, and ∞ in a loop (no phase), give NaN, never frame 0.
  const double inf = std::numeric_limits<double>::infinity();
  sample<double>(anim, inf, Interpolation::screw, WrapMode::clamp, out);
  EXPECT_EQ(out[0], anim.locals[2]);
  sample<double>(anim, -inf, Interpolation::screw, WrapMode::clamp, out);
  EXPECT_EQ(out[0], anim.locals[0]);
  Animation fast = anim;
  fast.frame_time = 1e-300;
  sample<double>(fast, 1e10, Interpolation::screw, WrapMode::clamp, out);  // 1e310 frames: ∞
  EXPECT_EQ(out[0], anim.locals[2]);
  for (const auto& [time, wrap] : {std::pair{std::numeric_limits<double>::quiet_NaN(), WrapMode::clamp},
                                   std::pair{std::numeric_limits<double>::quiet_NaN(), WrapMode::loop}, std::pair{inf, WrapMode::loop},
                                   std::pair{-inf, WrapMode::loop}}) {
    out[0] = DualQuaternion<double>::identity();
    sample<double>(anim, time, Interpolation::screw, wrap, out);
    EXPECT_TRUE(std::isnan(out[0].real.w) && std::isnan(out[0].dual.z)) << time << " " << static_cast<int>(wrap);
  }
  // Screw vs decoupled differ between keys where rotation and translation both change.
  std::array<DualQuaternion<double>, 1> a, b;
  sample<double>(anim, 0.25, Interpolation::screw, WrapMode::clamp, a);
  sample<double>(anim, 0.25, Interpolation::decoupled, WrapMode::clamp, b);
  EXPECT_GT(max_abs_diff(a[0].translation(), b[0].translation()), 1e-3);
}

}  // namespace

// BVH: the CMU files from Debian's assimp-testmodels parsed and put through forward kinematics,
// checked against an independent computation with Eigen; exact round trips; rotation-order
// conversion; malformed input rejected with the right line.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "dq/anim/forward_kinematics.hpp"
#include "dq/io/bvh.hpp"
#include "models.hpp"
#include "support.hpp"

namespace {

using namespace dq;
const std::filesystem::path kModels = dq::test::assimp_models();

/// Independent forward kinematics: Eigen affine transforms built from the channel angles.
std::vector<Eigen::Affine3d> eigen_fk(const BvhFile& bvh, std::size_t frame) {
  std::vector<Eigen::Affine3d> world(bvh.joints.size());
  const auto values = bvh.frame(frame);
  for (std::size_t i = 0; i < bvh.joints.size(); ++i) {
    const BvhJoint& j = bvh.joints[i];
    Eigen::Vector3d t(j.offset.x, j.offset.y, j.offset.z);
    Eigen::Matrix3d r = Eigen::Matrix3d::Identity();
    for (std::size_t k = 0; k < j.channels.size(); ++k) {
      const double v = values[j.first_channel + k];
      switch (j.channels[k]) {
        case BvhChannel::Xposition: t.x() += v; break;
        case BvhChannel::Yposition: t.y() += v; break;
        case BvhChannel::Zposition: t.z() += v; break;
        case BvhChannel::Xrotation: r = r * Eigen::AngleAxisd(v * M_PI / 180, Eigen::Vector3d::UnitX()).toRotationMatrix(); break;
        case BvhChannel::Yrotation: r = r * Eigen::AngleAxisd(v * M_PI / 180, Eigen::Vector3d::UnitY()).toRotationMatrix(); break;
        case BvhChannel::Zrotation: r = r * Eigen::AngleAxisd(v * M_PI / 180, Eigen::Vector3d::UnitZ()).toRotationMatrix(); break;
      }
    }
    Eigen::Affine3d local = Eigen::Affine3d::Identity();
    local.linear() = r;
    local.translation() = t;
    world[i] = j.parent < 0 ? local : world[static_cast<std::size_t>(j.parent)] * local;
  }
  return world;
}

class CmuFiles : public ::testing::TestWithParam<const char*> {};

TEST_P(CmuFiles, ForwardKinematicsMatchesEigen) {
  DQKIT_REQUIRE_MODELS();
  const Expected<BvhFile> bvh = read_bvh_file(kModels / "BVH" / GetParam());
  ASSERT_TRUE(bvh) << bvh.error().message;
  ASSERT_GT(bvh->frame_count, 10u);
  const Expected<Skeleton> skeleton = bvh_skeleton(*bvh);
  ASSERT_TRUE(skeleton) << skeleton.error().message;
  const Animation anim = bvh_animation(*bvh, *skeleton);
  std::vector<DualQuaternion<double>> model(skeleton->size());
  double scale = 1;
  for (std::size_t f : {std::size_t{0}, std::size_t{1}, bvh->frame_count / 2, bvh->frame_count - 1}) {
    local_to_model<DualQuaternion<double>>(*skeleton, anim.frame(f), model);
    const auto expected = eigen_fk(*bvh, f);
    for (std::size_t j = 0; j < model.size(); ++j) scale = std::max(scale, expected[j].translation().norm());
    for (std::size_t j = 0; j < model.size(); ++j) {
      const std::size_t raw = static_cast<std::size_t>(skeleton->raw_indices()[j]);
      const Vec3<double> p = model[j].translation();
      const Eigen::Vector3d e = expected[raw].translation();
      EXPECT_LE((Eigen::Vector3d(p.x, p.y, p.z) - e).norm(), 1e-9 * scale) << skeleton->names()[j] << " frame " << f;
      const Mat3<double> r = model[j].real.to_matrix();
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) EXPECT_NEAR(r(a, b), expected[raw].linear()(a, b), 1e-9);
    }
  }
}

TEST_P(CmuFiles, RoundTripIsExact) {
  DQKIT_REQUIRE_MODELS();
  const Expected<BvhFile> a = read_bvh_file(kModels / "BVH" / GetParam());
  ASSERT_TRUE(a) << a.error().message;
  const std::string text = write_bvh(*a).value();
  const Expected<BvhFile> b = read_bvh(text, "written");
  ASSERT_TRUE(b) << b.error().message;
  ASSERT_EQ(a->joints.size(), b->joints.size());
  for (std::size_t i = 0; i < a->joints.size(); ++i) {
    EXPECT_EQ(a->joints[i].name, b->joints[i].name);
    EXPECT_EQ(a->joints[i].parent, b->joints[i].parent);
    EXPECT_EQ(a->joints[i].offset, b->joints[i].offset);
    EXPECT_EQ(a->joints[i].channels, b->joints[i].channels);
    EXPECT_EQ(a->joints[i].end_site, b->joints[i].end_site);
  }
  EXPECT_EQ(a->frame_count, b->frame_count);
  EXPECT_EQ(a->frame_time, b->frame_time);
  EXPECT_EQ(a->motion, b->motion);  // bit for bit
  EXPECT_EQ(write_bvh(*b).value(), text);   // and the text is a fixed point
}

TEST_P(CmuFiles, RotationOrderConversionKeepsEveryTransform) {
  DQKIT_REQUIRE_MODELS();
  const Expected<BvhFile> a = read_bvh_file(kModels / "BVH" / GetParam());
  ASSERT_TRUE(a);
  for (EulerOrder order : {EulerOrder::ZXY, EulerOrder::XYZ, EulerOrder::YZX}) {
    const BvhFile b = *with_rotation_order(*a, order);
    const Expected<BvhFile> reread = read_bvh(write_bvh(b).value(), "converted");
    ASSERT_TRUE(reread) << reread.error().message;
    for (std::size_t f = 0; f < a->frame_count; f += 97)
      for (std::size_t j = 0; j < a->joints.size(); ++j) {
        const auto x = bvh_local_transform(*a, j, f), y = bvh_local_transform(*reread, j, f);
        EXPECT_TRUE(approx_equal(x, y, 1e-12, SignPolicy::same_rotation)) << a->joints[j].name << " frame " << f;
      }
  }
}

INSTANTIATE_TEST_SUITE_P(Bvh, CmuFiles, ::testing::Values("01_01.bvh", "01_03.bvh", "Boxing_Toes.bvh"));

TEST(Bvh, WhitespaceLineEndingsAndSixChannelJointsAnywhere) {
  const std::string text =
      "HIERARCHY\r\nROOT  Hips {\r\n\tOFFSET 0 0 0\r\n CHANNELS 3 Xrotation Yrotation Zrotation\r\n"
      "  JOINT Left Arm\r\n  {\r\n OFFSET 1 2 3\r\n CHANNELS 6 Zrotation Xposition Yposition Zposition Xrotation Yrotation\r\n"
      "   End Site\r\n   {\r\n OFFSET 0 0 1\r\n }\r\n }\r\n}\r\nMOTION\r\nFrames: 2\rFrame Time: 0.04\r"
      "1 2 3 90 0.5 0.25 0.125 4 5\r\n\r\n-1 -2 -3 0 0 0 0 0 0\n";
  const Expected<BvhFile> b = read_bvh(text, "mixed");
  ASSERT_TRUE(b) << b.error().message;
  ASSERT_EQ(b->joints.size(), 3u);
  EXPECT_EQ(b->joints[1].name, "Left Arm");
  EXPECT_EQ(b->joints[2].name, "Left Arm_End");
  EXPECT_TRUE(b->joints[2].end_site);
  EXPECT_EQ(b->channel_count(), 9u);
  // Joint 1, frame 0: translate(offset + (0.5, 0.25, 0.125)) · Rz(90°) Rx(4°) Ry(5°).
  const DualQuaternion<double> local = bvh_local_transform(*b, 1, 0);
  EXPECT_LE(dq::test::max_abs_diff(local.translation(), Vec3<double>{1.5, 2.25, 3.125}), 1e-15);
  const Quaternion<double> expected = from_euler(EulerOrder::ZXY, EulerFrame::intrinsic, pi_v<double> / 2, 4 * pi_v<double> / 180,
                                                 5 * pi_v<double> / 180);
  EXPECT_LE(dq::test::rotation_diff(local.real, expected), 1e-15);
}

struct Malformed {
  const char* text;
  const char* expected;  // substring of the error, including the line
};

TEST(Bvh, MalformedInputIsRejectedWithTheRightLine) {
  DQKIT_REQUIRE_MODELS();
  const std::string head = "HIERARCHY\nROOT A\n{\nOFFSET 0 0 0\nCHANNELS 3 Zrotation Xrotation Yrotation\n}\n";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"", "x:1: expected 'HIERARCHY', found end of file"},
      {"HIERARCHY\nJOINT A", "x:2: expected 'ROOT', found 'JOINT'"},
      {"HIERARCHY\nROOT\n{", "x:2: expected a joint name after 'ROOT'"},
      {"HIERARCHY\nROOT A { {\n", "x:2: a joint name may not contain '{' or '}'"},  // found by fuzzing
      {"HIERARCHY\nROOT A\n{\nOFFSET 0 zero 0", "x:4: expected a finite number, found 'zero'"},
      {"HIERARCHY\nROOT A\n{\nOFFSET 0 nan 0", "x:4: expected a finite number, found 'nan'"},
      {"HIERARCHY\nROOT A\n{\nOFFSET 0 0 0\nCHANNELS 7", "x:5: expected a channel count from 0 to 6, found '7'"},
      {"HIERARCHY\nROOT A\n{\nOFFSET 0 0 0\nCHANNELS 1 Wrotation", "x:5: expected a channel name"},
      {"HIERARCHY\nROOT A\n{\nOFFSET 0 0 0\nCHANNELS 2 Xrotation Xrotation", "x:5: channel repeated"},
      {"HIERARCHY\nROOT A\n{\nOFFSET 0 0 0\nCHANNELS 0\nJUNK", "x:6: expected 'JOINT', 'End Site' or '}', found 'JUNK'"},
      {"HIERARCHY\nROOT A\n{\nOFFSET 0 0 0\nCHANNELS 0\n", "x:6: expected 'JOINT', 'End Site' or '}', found end of file"},
      {head + "MOTION\nFrames: x", "x:8: expected a frame count, found 'x'"},
      {head + "MOTION\nFrames: 1\nFrame Time: -1", "x:9: expected a positive frame time"},
      {head + "MOTION\nFrames: 2\nFrame Time: 0.1\n1 2 3\n4 5\n", "x:11: frame 1 has 2 values, expected 3"},
      {head + "MOTION\nFrames: 2\nFrame Time: 0.1\n1 2 3\n", "expected 2 frames, found 1"},
      {head + "MOTION\nFrames: 1\nFrame Time: 0.1\n1 2 3\n4 5\n", "x:11: expected end of file after 1 frame, found '4'"},
      {head + "MOTION\nFrames: 1\nFrame Time: 0.1\n1 inf 3\n", "x:10: expected a finite number in frame 0, found 'inf'"},
      {head + "MOTION\nFrames: 99999999999999999999\n", "x:8: expected a frame count"},
  };
  for (const auto& [text, expected] : cases) {
    const Expected<BvhFile> b = read_bvh(text, "x");
    ASSERT_FALSE(b) << text;
    EXPECT_NE(b.error().message.find(expected), std::string::npos) << "got: " << b.error().message << "\nwanted: " << expected;
  }
}

TEST(Bvh, ExtraFramesAreIgnoredWithAWarning) {
  DQKIT_REQUIRE_MODELS();
  // Boxing_Toes.bvh declares 3069 frames and has 3070 frame lines.
  const Expected<BvhFile> b = read_bvh_file(kModels / "BVH" / "Boxing_Toes.bvh");
  ASSERT_TRUE(b) << b.error().message;
  EXPECT_EQ(b->frame_count, 3069u);
  ASSERT_EQ(b->warnings.size(), 1u);
  EXPECT_NE(b->warnings[0].find("Boxing_Toes.bvh:3199: 1 frame line(s) beyond the 3069 declared"), std::string::npos) << b->warnings[0];
}

TEST(Bvh, DeepNestingAndHugeFrameCountsDoNotHurt) {
  // 100000 nested joints: parsed iteratively (no stack overflow), then rejected past the limit.
  std::string deep = "HIERARCHY\nROOT A\n{\nOFFSET 0 0 0\nCHANNELS 0\n";
  for (int i = 0; i < 100000; ++i) deep += "JOINT j" + std::to_string(i) + "\n{\nOFFSET 0 0 0\nCHANNELS 0\n";
  const Expected<BvhFile> b = read_bvh(deep, "deep");
  ASSERT_FALSE(b);
  EXPECT_NE(b.error().message.find("more than 65536 joints"), std::string::npos);
  // A header that promises 60 million frames, with none: no huge allocation, a clear error.
  const Expected<BvhFile> c = read_bvh("HIERARCHY\nROOT A\n{\nOFFSET 0 0 0\nCHANNELS 1 Xrotation\n}\nMOTION\nFrames: 60000000\nFrame Time: 0.1\n", "big");
  ASSERT_FALSE(c);
  EXPECT_NE(c.error().message.find("expected 60000000 frames, found 0"), std::string::npos);
}

TEST(Bvh, MissingFileIsAClearError) {
  const Expected<BvhFile> b = read_bvh_file("/nonexistent/walk.bvh");
  ASSERT_FALSE(b);
  EXPECT_NE(b.error().message.find("/nonexistent/walk.bvh: cannot open"), std::string::npos);
}

}  // namespace

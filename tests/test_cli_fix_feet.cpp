// `dqkit fix-feet`, run as a user runs it: the written BVH has the same hierarchy and channels,
// every channel outside the legs is the input's to the last digit, the feet no longer slide, and
// the input is never overwritten.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <string>
#include <unistd.h>

#include "dq/ik/motion_capture.hpp"
#include "models.hpp"

namespace {

namespace fs = std::filesystem;
using namespace dq;

int run(const std::string& args) {
  const std::string command = std::string(DQKIT_CLI) + " " + args + " 2>/dev/null";
  return std::system(command.c_str());
}

TEST(CliFixFeet, WritesACaptureWithoutSlidingAndKeepsTheRest) {
  DQKIT_REQUIRE_MODELS();
  const fs::path dir = fs::temp_directory_path() / ("dqkit_fix_feet_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const fs::path input = dir / "walk.bvh", output = dir / "fixed.bvh";
  fs::copy_file(test::assimp_models() / "BVH" / "01_01.bvh", input);
  ASSERT_EQ(run("fix-feet " + input.string() + " -o " + output.string()), 0);
  const Expected<BvhFile> before = read_bvh_file(input), after = read_bvh_file(output);
  ASSERT_TRUE(before && after);
  ASSERT_EQ(after->joints.size(), before->joints.size());
  ASSERT_EQ(after->channel_count(), before->channel_count());
  ASSERT_EQ(after->frame_count, before->frame_count);
  // The library, run on the same file, says which channels are the legs'; all others are equal
  // to the last digit (BVH numbers are written shortest round-trip).
  BvhFile copy = *before;
  const Expected<FixFeetReport> report = fix_foot_sliding(copy);
  ASSERT_TRUE(report);
  EXPECT_EQ(after->motion, copy.motion);
  std::size_t kept = 0;
  for (std::size_t j = 0; j < before->joints.size(); ++j) {
    const BvhJoint& b = before->joints[j];
    bool leg = false;
    for (const std::string& name : report->leg_joints) leg = leg || name == b.name;
    if (leg) continue;
    for (std::size_t k = 0; k < b.channels.size(); ++k)
      for (std::size_t f = 0; f < before->frame_count; ++f, ++kept)
        ASSERT_EQ(after->frame(f)[b.first_channel + k], before->frame(f)[b.first_channel + k]) << b.name;
  }
  EXPECT_GT(kept, 0u);
  // Never onto its input, and not over an existing file without --force.
  EXPECT_NE(run("fix-feet " + input.string() + " -o " + input.string() + " --force"), 0);
  EXPECT_NE(run("fix-feet " + input.string() + " -o " + output.string()), 0);
  EXPECT_EQ(read_bvh_file(input)->motion, before->motion);
  // Unknown foot names are an error with exit code 1.
  EXPECT_NE(run("fix-feet " + input.string() + " -o " + (dir / "x.bvh").string() + " --feet NoSuchToe"), 0);
  EXPECT_FALSE(fs::exists(dir / "x.bvh"));
  // --feet takes one value: the arguments after it stay arguments (it swallowed the input and -o).
  EXPECT_EQ(run("fix-feet --feet LeftToeBase,RightToeBase " + input.string() + " -o " + (dir / "y.bvh").string()), 0);
  EXPECT_EQ(read_bvh_file(dir / "y.bvh")->motion, after->motion);  // the feet found by name are these two
  // A foot named twice, or an output that is not .bvh, is refused before anything is written.
  EXPECT_NE(run("fix-feet " + input.string() + " -o " + (dir / "z.bvh").string() + " --feet LeftToeBase,LeftToeBase"), 0);
  EXPECT_NE(run("fix-feet " + input.string() + " -o " + (dir / "z.txt").string()), 0);
  EXPECT_FALSE(fs::exists(dir / "z.bvh") || fs::exists(dir / "z.txt"));
  fs::remove_all(dir);
}

}  // namespace

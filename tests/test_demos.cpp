// The demo programs run headless (dqkit-puzzle, dqkit-viewports, dqkit-biped), their frames read
// back: the expected objects in the expected places, found by projecting positions computed here
// (from the seeds' formulas, or the puzzle's state) with the demos' cameras (window_pictures.hpp).
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include "window_pictures.hpp"

namespace {

using namespace dq;
using namespace dq::test;
namespace fs = std::filesystem;

fs::path run(const std::string& program, const std::string& args, const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("dqkit_test_demos_" + name);
  fs::remove_all(dir);
  const std::string command = program + " --headless --out " + dir.string() + " " + args + " > /dev/null";
  EXPECT_EQ(std::system(command.c_str()), 0) << command;
  return dir;
}

fs::path frame(const fs::path& dir, int f) {
  char name[32];
  std::snprintf(name, sizeof name, "frame_%04d.png", f);
  return dir / name;
}

TEST(Demos, PuzzleFramesShowTheScrambledAndTheSolvedState) {
  const fs::path dir = run(DQKIT_PUZZLE, "--frames 3 --width 480 --height 360 --seed 3 --scramble 8 --solve --export-x3d " +
                                             (fs::temp_directory_path() / "dqkit_test_demos.x3d").string(),
                           "puzzle");
  demo::Puzzle scrambled;
  scrambled.scramble(3, 8);
  ASSERT_FALSE(scrambled.solved());
  expect_pieces(load(frame(dir, 0)), scrambled);
  expect_pieces(load(frame(dir, 2)), demo::Puzzle{});
  // The middle frame differs from both (a move in progress or done).
  EXPECT_NE(load(frame(dir, 1)).rgba, load(frame(dir, 0)).rgba);
  fs::remove_all(dir);
}

TEST(Demos, PuzzleRejectsAnUnreachableDepth) {
  const std::string command = std::string(DQKIT_PUZZLE) + " --headless --frames 1 --out " +
                              (fs::temp_directory_path() / "dqkit_test_demos_unsolvable").string() +
                              " --seed 3 --scramble 12 --solve --max-depth 2 2> /dev/null > /dev/null";
  EXPECT_NE(std::system(command.c_str()), 0);
}

TEST(Demos, ViewportsMoveTheVectorAsTheThesis) {
  const fs::path dir = run(DQKIT_VIEWPORTS, "--frames 60 --width 500 --height 500", "viewports");
  for (int f : {0, 25, 59}) expect_viewport_tips(load(frame(dir, f)), f);
  fs::remove_all(dir);
}

TEST(Demos, BipedReachesTheTargetWithBothSolvers) {
  const int frames = 20;
  const fs::path dir = run(DQKIT_BIPED, "--frames " + std::to_string(frames) + " --width 800 --height 400 --fps 30", "biped");
  for (int f : {5, frames - 1}) expect_biped_target(load(frame(dir, f)), f, 30);
  fs::remove_all(dir);
}

}  // namespace

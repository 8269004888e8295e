// The demo programs run headless (dqkit-puzzle, dqkit-viewports, dqkit-biped), their frames read
// back: the expected objects in the expected places, found by projecting positions computed here
// (from the seeds' formulas, or the puzzle's state) with the demos' cameras.
#include <gtest/gtest.h>
#include <stb_image.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <numbers>
#include <string>

#include "dq/demo/scenes.hpp"

namespace {

using namespace dq;
namespace fs = std::filesystem;

struct Png {
  int width = 0, height = 0;
  std::vector<unsigned char> rgba;
  std::array<int, 3> at(double x, double y) const {
    const int ix = std::clamp(int(x), 0, width - 1), iy = std::clamp(int(y), 0, height - 1);
    const unsigned char* p = &rgba[(std::size_t(iy) * std::size_t(width) + std::size_t(ix)) * 4];
    return {p[0], p[1], p[2]};
  }
};

Png load(const fs::path& path) {
  Png png;
  int n = 0;
  unsigned char* data = stbi_load(path.c_str(), &png.width, &png.height, &n, 4);
  if (!data) {
    ADD_FAILURE() << "cannot read " << path;
    return png;
  }
  png.rgba.assign(data, data + std::size_t(png.width) * std::size_t(png.height) * 4);
  stbi_image_free(data);
  return png;
}

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

/// The face colour (0..5) nearest in chromaticity to a pixel.
int nearest_face(const std::array<int, 3>& c) {
  const double s = c[0] + c[1] + c[2] + 1e-9;
  int best = -1;
  double best_d = 1e9;
  for (int f = 0; f < 6; ++f) {
    const render::Color k = demo::face_color(f);
    const double ks = double(k.r) + double(k.g) + double(k.b);
    const double d = std::hypot(c[0] / s - double(k.r) / ks, c[1] / s - double(k.g) / ks, c[2] / s - double(k.b) / ks);
    if (d < best_d) best_d = d, best = f;
  }
  return best;
}

/// Every piece whose picture side faces the camera shows its home face's colour at a corner of
/// that side (away from its number), where the state puts it.
void expect_pieces(const Png& png, const demo::Puzzle& puzzle) {
  const render::Camera camera = demo::puzzle_camera(double(png.width) / png.height);
  int checked = 0;
  for (int piece = 0; piece < demo::puzzle_pieces; ++piece) {
    const Vec3<double> centre = demo::slot_center(puzzle.slot_of(piece)), normal = demo::slot_normal(puzzle.slot_of(piece));
    if (dot(normal, normalized(camera.eye() - centre)) < 0.3) continue;
    const auto pose = puzzle.pose(piece);
    for (const Vec3<double>& corner : {Vec3<double>{0.21, 1.4, 1.4}, Vec3<double>{0.21, -1.4, -1.4}}) {
      const auto p = render::project(camera, png.width, png.height, pose.transform_point(corner));
      EXPECT_EQ(nearest_face(png.at(p.x, p.y)), piece / 4) << "piece " << piece << " at " << p.x << ", " << p.y;
      ++checked;
    }
  }
  EXPECT_GE(checked, 12);
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
  const int size = 500, frames = 60;
  const fs::path dir = run(DQKIT_VIEWPORTS, "--frames " + std::to_string(frames) + " --width 500 --height 500", "viewports");
  for (int f : {0, 25, 59}) {
    const Png png = load(frame(dir, f));
    // The thesis' animate(), f times: 1° per frame about z, 0.01 up per frame, SLERP t 0.0175.
    const double a = f * std::numbers::pi / 180, up = 0.01 * f, t = 0.0175 * f;
    const Vec3<double> tip{-0.9 * std::sin(a), up + 0.9 * std::cos(a), 0};
    const Vec3<double> slerp_tip{0.9 * std::cos(t * std::numbers::pi / 2), 0.9 * std::sin(t * std::numbers::pi / 2), 0};
    const std::pair<int, int> corner[4] = {{0, 0}, {0, size / 2}, {size / 2, 0}, {size / 2, size / 2}};  // UL, LL, UR, LR
    for (int m = 0; m < demo::method_count; ++m) {
      const auto method = static_cast<demo::Method>(m);
      const render::Camera camera = demo::viewports_camera(1.0);
      const auto p = render::project(camera, size / 2, size / 2, method == demo::Method::quaternion_slerp ? slerp_tip : tip);
      const auto c = png.at(corner[m].first + p.x, corner[m].second + p.y);
      const render::Color k = demo::method_color(method);
      EXPECT_NEAR(c[0], k.r * 255, 40) << demo::method_name(method) << " frame " << f;
      EXPECT_NEAR(c[1], k.g * 255, 40) << demo::method_name(method) << " frame " << f;
      EXPECT_NEAR(c[2], k.b * 255, 40) << demo::method_name(method) << " frame " << f;
    }
  }
  fs::remove_all(dir);
}

TEST(Demos, BipedReachesTheTargetWithBothSolvers) {
  const int width = 800, height = 400, frames = 20;
  const fs::path dir = run(DQKIT_BIPED, "--frames " + std::to_string(frames) + " --width 800 --height 400 --fps 30", "biped");
  for (int f : {5, frames - 1}) {
    const Png png = load(frame(dir, f));
    const Vec3<double> target = demo::biped_target(f / 30.0).translation();
    const render::Camera camera = demo::BipedDemo::camera(double(width / 2) / height);
    const auto p = render::project(camera, width / 2, height, target);
    for (int side = 0; side < 2; ++side) {
      const double x = side * width / 2 + p.x;
      // The computed effector (green) on the ideal target (red, a larger square round it).
      const auto centre = png.at(x, p.y), ring = png.at(x + 6, p.y + 6);
      EXPECT_GT(centre[1], centre[0] + 60) << "side " << side << " frame " << f;
      EXPECT_GT(ring[0], ring[1] + 100) << "side " << side << " frame " << f;
    }
  }
  fs::remove_all(dir);
}

}  // namespace

// The demo programs in their windows (the renderer's GLFW window with Dear ImGui over it) on a
// virtual X server (xvfb-run), driven by keys and clicks from xdotool; each picture is captured
// from the X server (xwd, window_session.sh) and checked for the expected objects where the demos'
// cameras project them (window_pictures.hpp). Also `dqkit render --window`'s mouse orbit. Skipped
// where xvfb-run, xdotool, xwd or ImageMagick is missing (Debian xvfb, xdotool, x11-apps,
// imagemagick: scripts/deps.sh).
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <string>

#include "window_pictures.hpp"

namespace {

using namespace dq;
using namespace dq::test;
namespace fs = std::filesystem;

bool have_tools() {
  return std::system("{ command -v xvfb-run && command -v xdotool && command -v xwd && command -v convert; } > /dev/null 2>&1") == 0;
}

/// Runs `program args` on a new virtual X server, its window (named `window`, a regular
/// expression) driven through the steps of window_session.sh; the captures are in the returned
/// directory.
fs::path session(const std::string& id, const std::string& window, const std::string& program, const std::string& args,
                 const std::string& steps) {
  const fs::path dir = fs::temp_directory_path() / ("dqkit_test_demo_windows_" + id);
  fs::remove_all(dir);
  const std::string command = "timeout 60 xvfb-run -a -s '-screen 0 1280x1024x24' bash " DQKIT_WINDOW_SESSION " " +
                              dir.string() + " '" + window + "' '" + steps + "' -- " + program + " " + args;
  EXPECT_EQ(std::system(command.c_str()), 0) << command;
  return dir;
}

/// The share of dark pixels (all channels below 60) in a rectangle: Dear ImGui's panels (its
/// default dark style) over pictures that have no dark areas of that size.
double dark_share(const Png& png, int x0, int y0, int x1, int y1) {
  int dark = 0;
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) {
      const auto c = png.at(x, y);
      dark += c[0] < 60 && c[1] < 60 && c[2] < 60;
    }
  return double(dark) / ((x1 - x0) * (y1 - y0));
}

TEST(DemoWindows, PuzzleMovesTheClickedPieceUndoesSolvesScramblesAndTurns) {
  if (!have_tools()) GTEST_SKIP() << "needs xvfb-run, xdotool, xwd and ImageMagick's convert";
  const int width = 800, height = 600;
  const render::Camera camera = demo::puzzle_camera(double(width) / height);
  // A short scramble that leaves the hole on a side facing the camera, with a piece next to it
  // facing the camera too (right of the ImGui panel, which is 158 pixels wide).
  std::uint64_t seed = 0;
  int piece = -1;
  demo::Puzzle start;
  for (std::uint64_t s = 1; s < 200 && piece < 0; ++s) {
    demo::Puzzle p;
    p.scramble(s, 3);
    if (p.solved() || dot(demo::slot_normal(p.hole()), normalized(camera.eye() - demo::slot_center(p.hole()))) < 0.3) continue;
    for (int candidate : p.movable()) {
      const auto c = render::project(camera, width, height, demo::slot_center(p.slot_of(candidate)));
      if (faces_camera(p, candidate, camera) && c.x > 200) seed = s, piece = candidate, start = p;
    }
  }
  ASSERT_GE(piece, 0);
  const Vec3<double> centre = demo::slot_center(start.slot_of(piece)) + demo::slot_normal(start.slot_of(piece)) * 0.2;
  const auto click = render::project(camera, width, height, centre);
  const fs::path dir = session("puzzle", "dqkit-puzzle", DQKIT_PUZZLE,
                               "--seed " + std::to_string(seed) + " --scramble 3 --width 800 --height 600",
                               "shot start; click " + std::to_string(int(click.x)) + " " + std::to_string(int(click.y)) +
                                   "; change moved; key u; change undone; key space; change solved; key s; change scrambled;"
                                   " drag 480 560 440 580; change turned");

  const Png shown = load(dir / "start.png");
  ASSERT_EQ(shown.width, width);
  ASSERT_EQ(shown.height, height);
  expect_pieces(shown, start);
  EXPECT_GT(dark_share(shown, 12, 165, 150, 225), 0.5) << "the ImGui panel's text at the upper left";

  // The clicked piece moved into the hole: every visible piece where the new state puts it, and
  // the piece's colour now where the hole was.
  demo::Puzzle moved = start;
  ASSERT_TRUE(moved.move(piece));
  const Png after = load(dir / "moved.png");
  expect_pieces(after, moved);
  for (const Vec3<double>& corner : piece_corners(moved, piece)) {
    const auto p = render::project(camera, width, height, corner);
    EXPECT_NE(shown.at(p.x, p.y), after.at(p.x, p.y)) << "the hole's place at " << p.x << ", " << p.y;
  }
  // U undoes the move; Space solves (animated), S scrambles from there with seed --seed + 1.
  expect_pieces(load(dir / "undone.png"), start);
  const auto solution = demo::solve(start, 18);
  ASSERT_TRUE(solution.has_value());
  demo::Puzzle played = start;
  for (int p : *solution) played.move(p);
  ASSERT_TRUE(played.solved());
  expect_pieces(load(dir / "solved.png"), played);
  played.scramble(seed + 1, 20);
  ASSERT_FALSE(played.solved());
  expect_pieces(load(dir / "scrambled.png"), played);
  // A drag below the cube (40 pixels left, 20 down) turns the camera as render::orbit says.
  render::Camera turned = camera;
  turned.yaw += 40 * render::orbit_radians_per_pixel;
  turned.pitch += 20 * render::orbit_radians_per_pixel;
  expect_pieces(load(dir / "turned.png"), played, turned);
  if (HasFailure()) std::cout << "the captures are in " << dir.string() << "\n";
  else fs::remove_all(dir);
}

TEST(DemoWindows, ViewportsPauseRestartAndStepThroughTheThesisMotion) {
  if (!have_tools()) GTEST_SKIP() << "needs xvfb-run, xdotool, xwd and ImageMagick's convert";
  // Space pauses (the picture stays still), R goes back to frame 0, N steps one frame: 30 steps.
  std::string steps = "key space; shot paused; key r; change first; key";
  for (int i = 0; i < 30; ++i) steps += " n";
  const fs::path dir = session("viewports", "dqkit-viewports", DQKIT_VIEWPORTS, "--width 600 --height 600", steps + "; change stepped");
  const Png first = load(dir / "first.png"), stepped = load(dir / "stepped.png");
  ASSERT_EQ(first.width, 600);
  expect_viewport_tips(first, 0);
  expect_viewport_tips(stepped, 30);
  // The ImGui panel between the upper two viewports, where the vectors never go.
  EXPECT_GT(dark_share(stepped, 270, 70, 330, 140), 0.5);
  if (HasFailure()) std::cout << "the captures are in " << dir.string() << "\n";
  else fs::remove_all(dir);
}

TEST(DemoWindows, BipedFollowsTheTargetFrameByFrame) {
  if (!have_tools()) GTEST_SKIP() << "needs xvfb-run, xdotool, xwd and ImageMagick's convert";
  const int frame = 12;
  std::string steps = "key space; shot paused; key r; change first; key";
  for (int i = 0; i < frame; ++i) steps += " n";
  const fs::path dir = session("biped", "dqkit-biped", DQKIT_BIPED, "--width 1000 --height 600 --fps 30", steps + "; change stepped");
  const Png first = load(dir / "first.png"), stepped = load(dir / "stepped.png");
  ASSERT_EQ(first.width, 1000);
  expect_biped_target(first, 0, 30);
  expect_biped_target(stepped, frame, 30);
  // The targets of frames 0 and 12 are apart on screen, so the pictures show different frames.
  const render::Camera camera = demo::BipedDemo::camera(500.0 / 600);
  const auto a = render::project(camera, 500, 600, demo::biped_target(0).translation());
  const auto b = render::project(camera, 500, 600, demo::biped_target(frame / 30.0).translation());
  EXPECT_GT(std::hypot(a.x - b.x, a.y - b.y), 10);
  // The ImGui panel between the two figures.
  EXPECT_GT(dark_share(stepped, 440, 110, 560, 200), 0.5);
  if (HasFailure()) std::cout << "the captures are in " << dir.string() << "\n";
  else fs::remove_all(dir);
}

#if defined(DQKIT_CLI)
/// The pixels that are not the white background: their bounding box and count.
struct Silhouette {
  int x0 = 1 << 30, y0 = 1 << 30, x1 = -1, y1 = -1, count = 0;
};
Silhouette silhouette(const Png& png) {
  Silhouette s;
  for (int y = 0; y < png.height; ++y)
    for (int x = 0; x < png.width; ++x) {
      const auto c = png.at(x, y);
      if (c[0] > 245 && c[1] > 245 && c[2] > 245) continue;
      s.x0 = std::min(s.x0, x), s.x1 = std::max(s.x1, x), s.y0 = std::min(s.y0, y), s.y1 = std::max(s.y1, y), ++s.count;
    }
  return s;
}

void expect_same_silhouette(const Png& window, const Png& headless, const char* what) {
  const Silhouette a = silhouette(window), b = silhouette(headless);
  ASSERT_GT(b.count, 1000) << what;
  EXPECT_NEAR(a.x0, b.x0, 2) << what;
  EXPECT_NEAR(a.x1, b.x1, 2) << what;
  EXPECT_NEAR(a.y0, b.y0, 2) << what;
  EXPECT_NEAR(a.y1, b.y1, 2) << what;
  EXPECT_NEAR(a.count, b.count, 0.03 * b.count) << what;
}

// dqkit render --window: a drag turns the camera by render::orbit_radians_per_pixel per pixel (the
// window then shows what the headless renderer draws from that camera), the wheel brings it nearer.
TEST(RenderWindow, DragTurnsTheCameraAndTheWheelBringsItNearer) {
  if (!have_tools()) GTEST_SKIP() << "needs xvfb-run, xdotool, xwd and ImageMagick's convert";
  const std::string model = std::string(DQKIT_ASSIMP_MODELS) + "/X/Testwuson.X";
  if (!fs::exists(model)) GTEST_SKIP() << model << " (Debian assimp-testmodels) is missing";
  const std::string args = "render " + model + " --method dqs --width 400 --height 300";
  const fs::path dir = session("render", "dqkit render .*/X/Testwuson.X", DQKIT_CLI, args + " --window",
                               "shot start; drag 150 150 250 150; change turned; wheel 3; change nearer");
  const double turned_yaw = 35 - 100 * render::orbit_radians_per_pixel * 180 / std::numbers::pi;  // degrees
  const std::pair<std::string, std::string> cameras[] = {{"start", "35,20"}, {"turned", std::to_string(turned_yaw) + ",20"}};
  for (const auto& [name, camera] : cameras) {
    const fs::path png = dir / (name + "_headless.png");
    const std::string command = std::string(DQKIT_CLI) + " " + args + " --camera " + camera + " --out " + png.string() + " > /dev/null";
    ASSERT_EQ(std::system(command.c_str()), 0) << command;
    expect_same_silhouette(load(dir / (name + ".png")), load(png), name.c_str());
  }
  const Silhouette turned = silhouette(load(dir / "turned.png")), nearer = silhouette(load(dir / "nearer.png"));
  EXPECT_GT(nearer.count, 1.3 * turned.count);
  EXPECT_GT(nearer.y1 - nearer.y0, turned.y1 - turned.y0);
  if (HasFailure()) std::cout << "the captures are in " << dir.string() << "\n";
  else fs::remove_all(dir);
}
#endif

}  // namespace

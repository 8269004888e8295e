// The demo programs run headless (dqkit-puzzle, dqkit-viewports, dqkit-biped), their frames read
// back: the expected objects in the expected places, found by projecting positions computed here
// (from the seeds' formulas, or the puzzle's state) with the demos' cameras (window_pictures.hpp).
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <numbers>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "cli.hpp"
#include "dq/render/text.hpp"
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
  const fs::path x3d = fs::temp_directory_path() / "dqkit_test_demos.x3d";
  fs::remove(x3d);  // an existing file is replaced only with --force
  const fs::path dir = run(DQKIT_PUZZLE, "--frames 3 --width 480 --height 360 --seed 3 --scramble 8 --solve --export-x3d " + x3d.string(), "puzzle");
  EXPECT_TRUE(fs::exists(x3d));
  fs::remove(x3d);
  demo::Puzzle scrambled;
  scrambled.scramble(3, 8);
  ASSERT_FALSE(scrambled.solved());
  expect_pieces(load(frame(dir, 0)), scrambled);
  expect_pieces(load(frame(dir, 2)), demo::Puzzle{});
  // The middle frame differs from both (a move in progress or done).
  EXPECT_NE(load(frame(dir, 1)).rgba, load(frame(dir, 0)).rgba);
  fs::remove_all(dir);
}

TEST(Demos, OptionsOutOfRangeAreErrors) {
  // NaN passes CLI11's own ranges; a negative seed would wrap into an unsigned one; a scramble's
  // moves are kept, so its length is bounded.
  const fs::path err = fs::temp_directory_path() / "dqkit_test_demos_err.txt";
  for (const auto& [program, args, expected] :
       {std::tuple{std::string(DQKIT_BIPED), std::string("--fps nan"), std::string("'nan' is not a finite number")},
        std::tuple{std::string(DQKIT_BIPED), std::string("--fps 0"), std::string("'0' is out of range (0, 1000]")},
        std::tuple{std::string(DQKIT_PUZZLE), std::string("--seed -1"), std::string("'-1' is not a whole number")},
        std::tuple{std::string(DQKIT_PUZZLE), std::string("--scramble 1000001"), std::string("'1000001' is more than 1000000")}}) {
    const std::string command = program + " --headless --frames 1 --out " + (fs::temp_directory_path() / "dqkit_test_demos_err").string() +
                                " " + args + " > /dev/null 2> " + err.string();
    EXPECT_NE(std::system(command.c_str()), 0) << command;
    const std::string text = read_file(err);
    EXPECT_NE(text.find(expected), std::string::npos) << command << ": " << text;
  }
  fs::remove(err);
}

TEST(Demos, PuzzleRejectsAnUnreachableDepth) {
  const std::string command = std::string(DQKIT_PUZZLE) + " --headless --frames 1 --out " +
                              (fs::temp_directory_path() / "dqkit_test_demos_unsolvable").string() +
                              " --seed 3 --scramble 12 --solve --max-depth 2 2> /dev/null > /dev/null";
  EXPECT_NE(std::system(command.c_str()), 0);
}

/// Every point of the dark label strokes of `views` lies inside its own viewport horizontally.
void expect_labels_inside(const std::vector<demo::View>& views, const char* what) {
  for (std::size_t i = 0; i < views.size(); ++i) {
    const demo::View& v = views[i];
    for (const render::Lines& lines : v.scene.lines) {
      if (!(lines.color.r < 0.2f && lines.color.g < 0.2f && lines.color.b < 0.2f)) continue;  // the labels' near-black
      for (const Vec3<float>& p : lines.points) {
        const render::Projected q = render::project(v.camera, v.viewport.width, v.viewport.height, {p.x, p.y, p.z});
        ASSERT_GE(q.x, 0) << what << " view " << i;
        ASSERT_LE(q.x, v.viewport.width) << what << " view " << i << ": a label runs into the next view";
      }
    }
  }
}

TEST(Demos, LabelsFitNarrowViews) {
  // Text sized by the view's height alone ran past its view's right edge in narrow views
  // (viewports at 300 x 1200, the biped at 800 x 800): it is made smaller there instead.
  const std::array<double, demo::method_count> ns{12.5, 30.25, 45.5, 99.75};
  for (const auto& [w, h] : {std::pair{300, 1200}, std::pair{500, 500}, std::pair{1600, 200}})
    expect_labels_inside(demo::viewports_views(demo::ViewportsState{}, &ns, w, h), "viewports");
  demo::BipedDemo biped;
  biped.step(0.0);
  for (const auto& [w, h] : {std::pair{800, 800}, std::pair{400, 1000}, std::pair{1000, 600}}) expect_labels_inside(biped.views(w, h), "biped");
}

/// The world directions of a label's reading direction and of its up, as drawn: the affine map
/// taking the label set in the plane (x right, y up) to its drawn strokes, fitted to all points
/// (normal equations, Cramer's rule).
std::pair<Vec3<double>, Vec3<double>> drawn_axes(const std::string& label, const std::vector<Vec3<double>>& drawn) {
  std::vector<Vec3<float>> flat;
  render::add_text(flat, label, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 1.5);
  EXPECT_EQ(flat.size(), drawn.size()) << label;
  if (flat.size() != drawn.size()) return {};
  double m[3][3] = {};  // sums of b bᵀ, b = (1, x, y)
  Vec3<double> rhs[3] = {};
  for (std::size_t i = 0; i < flat.size(); ++i) {
    const double b[3] = {1, flat[i].x, flat[i].y};
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) m[r][c] += b[r] * b[c];
      rhs[r] = rhs[r] + drawn[i] * b[r];
    }
  }
  const auto det = [](const double (&a)[3][3]) {
    return a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
           a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
  };
  const auto solve_column = [&](int column) {  // the coefficient of basis function `column`, per coordinate
    Vec3<double> out;
    for (int k = 0; k < 3; ++k) {
      double a[3][3];
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) a[r][c] = c == column ? (k == 0 ? rhs[r].x : k == 1 ? rhs[r].y : rhs[r].z) : m[r][c];
      (k == 0 ? out.x : k == 1 ? out.y : out.z) = det(a) / det(m);
    }
    return out;
  };
  return {solve_column(1), solve_column(2)};
}

TEST(Demos, PuzzleNumbersReadUprightFromACameraInFrontOfTheirFace) {
  // They were drawn along each piece's local y with local z up, which put those of the +x face
  // sideways and those of the top face upside down. Fitted from the drawn strokes, each number's
  // reading direction and its up must read on the screen of a camera in front of its face better
  // than the text turned or mirrored would: the default camera for the +x, +y and +z faces, the
  // one opposite for −x and −z, the one below for −y.
  const demo::Puzzle solved;
  for (int piece = 0; piece < demo::puzzle_pieces; ++piece) {
    const int face = piece / 4;  // +x, −x, +y, −y, +z, −z
    const double yaw = face == 1 || face == 5 ? 0.6 + std::numbers::pi : 0.6, pitch = face == 3 ? -0.45 : 0.45;
    const render::Camera camera = demo::puzzle_camera(800.0 / 600, yaw, pitch);
    const DualQuaternion<double> pose = solved.pose(piece);
    const Vec3<double> normal = pose.real.rotate({1, 0, 0}), centre = pose.transform_point({demo::piece_thickness / 2, 0, 0});
    ASSERT_GT(dot(normal, camera.eye() - centre), 0) << "piece " << piece << " faces away from its camera";
    const demo::View v = demo::puzzle_view(solved, std::nullopt, camera, {0, 0, 800, 600});
    std::vector<Vec3<double>> mine;  // the strokes on this piece's outer side, in the order drawn
    for (const render::Lines& lines : v.scene.lines)
      if (lines.color.r < 0.2f && lines.color.g < 0.2f && lines.color.b < 0.2f)
        for (const Vec3<float>& p : lines.points) {
          const Vec3<double> q{p.x, p.y, p.z};
          if (std::abs(dot(q - centre, normal)) < 0.05 && norm(q - centre) < 2) mine.push_back(q);
        }
    const auto [right, up] = drawn_axes((piece < 10 ? "0" : "") + std::to_string(piece), mine);
    // How well a reading direction and an up read on screen: the first's unit screen direction
    // along the screen's x plus the second's against its y (rows grow downwards). The drawn pair
    // must beat the seven other ways to lay the text on the face (turned, mirrored).
    const auto direction = [&](const Vec3<double>& d) {
      const render::Projected a = render::project(camera, 800, 600, centre), b = render::project(camera, 800, 600, centre + d);
      const double dx = b.x - a.x, dy = b.y - a.y, n = std::hypot(dx, dy);
      return std::pair{dx / n, dy / n};
    };
    const auto score = [&](const Vec3<double>& r, const Vec3<double>& u) { return direction(r).first - direction(u).second; };
    const double drawn = score(right, up);
    const std::pair<Vec3<double>, Vec3<double>> others[7] = {{up, -right},  {-right, -up}, {-up, right}, {-right, up},
                                                             {up, right},   {right, -up},  {-up, -right}};
    for (const auto& [r, u] : others) EXPECT_GT(drawn, score(r, u) + 0.05) << "piece " << piece << ": its number is turned or mirrored";
  }
}

TEST(Demos, FramesOfAnEarlierRunAreReplacedOnlyWithForce) {
  const fs::path dir = fs::temp_directory_path() / "dqkit_test_demos_force";
  fs::remove_all(dir);
  const std::string base = std::string(DQKIT_VIEWPORTS) + " --headless --width 64 --height 64 --out " + dir.string();
  ASSERT_EQ(std::system((base + " --frames 4 > /dev/null").c_str()), 0);
  EXPECT_NE(std::system((base + " --frames 2 > /dev/null 2>&1").c_str()), 0);  // refused: frames 0-3 are there
  EXPECT_TRUE(fs::exists(frame(dir, 3)));
  ASSERT_EQ(std::system((base + " --frames 2 --force > /dev/null").c_str()), 0);
  EXPECT_TRUE(fs::exists(frame(dir, 1)));
  EXPECT_FALSE(fs::exists(frame(dir, 2)));  // none of the earlier, longer run left behind
  EXPECT_FALSE(fs::exists(frame(dir, 3)));
  fs::remove_all(dir);
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

// What the demo programs' pictures must show, for their headless frames (test_demos) and their
// windows captured from the X server (test_demo_windows): the expected objects where the demos'
// cameras project positions computed here from the seeds' formulas or the puzzle's state.
#pragma once

#include <gtest/gtest.h>
#include <stb_image.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <optional>
#include <vector>

#include "dq/demo/scenes.hpp"

namespace dq::test {

struct Png {
  int width = 0, height = 0;
  std::vector<unsigned char> rgba;
  std::array<int, 3> at(double x, double y) const {
    const int ix = std::clamp(int(x), 0, width - 1), iy = std::clamp(int(y), 0, height - 1);
    const unsigned char* p = &rgba[(std::size_t(iy) * std::size_t(width) + std::size_t(ix)) * 4];
    return {p[0], p[1], p[2]};
  }
};

inline Png load(const std::filesystem::path& path) {
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

/// The face colour (0..5) nearest in chromaticity to a pixel.
inline int nearest_face(const std::array<int, 3>& c) {
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

/// Whether a piece's picture side faces the camera clearly enough to be checked.
inline bool faces_camera(const demo::Puzzle& puzzle, int piece, const render::Camera& camera) {
  const Vec3<double> centre = demo::slot_center(puzzle.slot_of(piece)), normal = demo::slot_normal(puzzle.slot_of(piece));
  return dot(normal, normalized(camera.eye() - centre)) >= 0.3;
}

/// Two points of a piece's picture side, near opposite corners (away from its number).
inline std::array<Vec3<double>, 2> piece_corners(const demo::Puzzle& puzzle, int piece) {
  const auto pose = puzzle.pose(piece);
  return {pose.transform_point({0.21, 1.4, 1.4}), pose.transform_point({0.21, -1.4, -1.4})};
}

/// Every piece whose picture side faces the camera shows its home face's colour at two corners of
/// that side, where the state puts it. The puzzle's default camera by default.
inline void expect_pieces(const Png& png, const demo::Puzzle& puzzle, std::optional<render::Camera> seen_from = {}) {
  const render::Camera camera = seen_from.value_or(demo::puzzle_camera(double(png.width) / png.height));
  int checked = 0;
  for (int piece = 0; piece < demo::puzzle_pieces; ++piece) {
    if (!faces_camera(puzzle, piece, camera)) continue;
    for (const Vec3<double>& corner : piece_corners(puzzle, piece)) {
      const auto p = render::project(camera, png.width, png.height, corner);
      EXPECT_EQ(nearest_face(png.at(p.x, p.y)), piece / 4) << "piece " << piece << " at " << p.x << ", " << p.y;
      ++checked;
    }
  }
  EXPECT_GE(checked, 12);
}

/// The four viewports (size × size, 2 × 2) at frame `frame` of the thesis' animate(): each
/// method's vector tip, computed here from the thesis' formulas, in its viewport in its colour.
inline void expect_viewport_tips(const Png& png, int frame) {
  const int size = png.width;
  ASSERT_EQ(png.height, size);
  // The thesis' animate(), f times: 1° per frame about z, 0.01 up per frame, SLERP t 0.0175.
  const double a = frame * std::numbers::pi / 180, up = 0.01 * frame, t = 0.0175 * frame;
  ASSERT_LE(up, 1) << "the formulas here hold before the first turn of the up-and-down motion";
  const Vec3<double> tip{-0.9 * std::sin(a), up + 0.9 * std::cos(a), 0};
  const Vec3<double> slerp_tip{0.9 * std::cos(t * std::numbers::pi / 2), 0.9 * std::sin(t * std::numbers::pi / 2), 0};
  const std::pair<int, int> corner[4] = {{0, 0}, {0, size / 2}, {size / 2, 0}, {size / 2, size / 2}};  // UL, LL, UR, LR
  for (int m = 0; m < demo::method_count; ++m) {
    const auto method = static_cast<demo::Method>(m);
    const render::Camera camera = demo::viewports_camera(1.0);
    const auto p = render::project(camera, size / 2, size / 2, method == demo::Method::quaternion_slerp ? slerp_tip : tip);
    const auto c = png.at(corner[m].first + p.x, corner[m].second + p.y);
    const render::Color k = demo::method_color(method);
    EXPECT_NEAR(c[0], k.r * 255, 40) << demo::method_name(method) << " frame " << frame;
    EXPECT_NEAR(c[1], k.g * 255, 40) << demo::method_name(method) << " frame " << frame;
    EXPECT_NEAR(c[2], k.b * 255, 40) << demo::method_name(method) << " frame " << frame;
  }
}

/// The biped's two views (dual quaternions | matrices) at frame `frame` at `fps`: in each, the
/// computed effector (green) inside the ideal target (red, a larger square round it), where the
/// target computed here projects.
inline void expect_biped_target(const Png& png, int frame, double fps) {
  const Vec3<double> target = demo::biped_target(frame / fps).translation();
  const render::Camera camera = demo::BipedDemo::camera(double(png.width / 2) / png.height);
  const auto p = render::project(camera, png.width / 2, png.height, target);
  for (int side = 0; side < 2; ++side) {
    const double x = side * png.width / 2 + p.x;
    const auto centre = png.at(x, p.y), ring = png.at(x + 6, p.y + 6);
    EXPECT_GT(centre[1], centre[0] + 60) << "side " << side << " frame " << frame;
    EXPECT_GT(ring[0], ring[1] + 100) << "side " << side << " frame " << frame;
  }
}

}  // namespace dq::test

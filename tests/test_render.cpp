// The renderer, headless: what the images show. A cube seen from a known camera must cover the
// pixels of its projection computed here with GLM (lookAt, perspective), in the viewport asked
// for; lines on top show through; the PNG holds the pixels read back.
#include <gtest/gtest.h>

#include <stb_image.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <tuple>
#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "dq/render/render.hpp"
#include "dq/render/text.hpp"

namespace dq::render {
namespace {

Mesh cube(double half) {
  Mesh m;
  for (int i = 0; i < 8; ++i) m.positions.push_back({float(i & 1 ? half : -half), float(i & 2 ? half : -half), float(i & 4 ? half : -half)});
  // Two triangles per face, outward.
  m.triangles = {0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4, 2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5, 3, 7, 5};
  m.color = {0.2f, 0.4f, 0.8f, 1};
  return m;
}

struct Point2 {
  double x, y;
};

/// The pixel of a world point, computed with GLM from the documented camera convention.
Point2 glm_project(const Camera& c, int width, int height, glm::dvec3 p) {
  const glm::dvec3 target(c.target.x, c.target.y, c.target.z);
  const glm::dvec3 eye = target + c.distance * glm::dvec3(std::cos(c.pitch) * std::sin(c.yaw), std::sin(c.pitch), std::cos(c.pitch) * std::cos(c.yaw));
  const glm::dmat4 m = glm::perspective(c.fov_y, double(width) / height, c.near_plane, c.far_plane) * glm::lookAt(eye, target, glm::dvec3(0, 1, 0));
  const glm::dvec4 clip = m * glm::dvec4(p, 1);
  return {(clip.x / clip.w + 1) / 2 * width, (1 - clip.y / clip.w) / 2 * height};
}

/// Area and perimeter of the convex hull of points (monotone chain).
std::pair<double, double> hull_area_perimeter(std::vector<Point2> p) {
  std::sort(p.begin(), p.end(), [](Point2 a, Point2 b) { return a.x < b.x || (a.x == b.x && a.y < b.y); });
  auto turn = [](Point2 o, Point2 a, Point2 b) { return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x); };
  std::vector<Point2> h(2 * p.size());
  std::size_t k = 0;
  for (std::size_t i = 0; i < p.size(); h[k++] = p[i++])
    while (k >= 2 && turn(h[k - 2], h[k - 1], p[i]) <= 0) --k;
  for (std::size_t i = p.size() - 1, t = k + 1; i > 0; h[k++] = p[--i])
    while (k >= t && turn(h[k - 2], h[k - 1], p[i - 1]) <= 0) --k;
  h.resize(k - 1);
  double area = 0, perimeter = 0;
  for (std::size_t i = 0; i < h.size(); ++i) {
    const Point2 a = h[i], b = h[(i + 1) % h.size()];
    area += a.x * b.y - b.x * a.y;
    perimeter += std::hypot(b.x - a.x, b.y - a.y);
  }
  return {std::abs(area) / 2, perimeter};
}

bool is_background(const Image& im, int x, int y) {
  const auto p = im.pixel(x, y);
  return p[0] == 255 && p[1] == 255 && p[2] == 255;
}

struct Coverage {
  int x0 = 1 << 30, y0 = 1 << 30, x1 = -1, y1 = -1;
  long count = 0;
};
Coverage coverage(const Image& im, int x_from, int x_to) {
  Coverage c;
  for (int y = 0; y < im.height; ++y)
    for (int x = x_from; x < x_to; ++x)
      if (!is_background(im, x, y)) c.x0 = std::min(c.x0, x), c.x1 = std::max(c.x1, x), c.y0 = std::min(c.y0, y), c.y1 = std::max(c.y1, y), ++c.count;
  return c;
}

Renderer make(int w, int h) {
  Expected<Renderer> r = Renderer::create({w, h, 1, {1, 1, 1, 1}});
  if (!r) ADD_FAILURE() << "no headless OpenGL: " << r.error().message;
  return std::move(*r);
}

TEST(Render, CubeCoversItsProjection) {
  Renderer r = make(320, 240);
  Camera cam;
  cam.yaw = 0.5, cam.pitch = 0.4, cam.distance = 6, cam.fov_y = 0.8, cam.near_plane = 0.1, cam.far_plane = 20;
  Scene scene;
  scene.meshes.push_back(cube(1));
  r.draw(scene, cam);
  const Image im = r.read();
  std::vector<Point2> corners;
  double x0 = 1e9, x1 = -1e9, y0 = 1e9, y1 = -1e9;
  for (const auto& p : scene.meshes[0].positions) {
    const Point2 q = glm_project(cam, 320, 240, {p.x, p.y, p.z});
    corners.push_back(q);
    x0 = std::min(x0, q.x), x1 = std::max(x1, q.x), y0 = std::min(y0, q.y), y1 = std::max(y1, q.y);
  }
  const Coverage c = coverage(im, 0, 320);
  // A pixel is covered when its centre (x + ½, y + ½) is inside the silhouette.
  EXPECT_NEAR(c.x0, std::round(x0), 1);
  EXPECT_NEAR(c.x1 + 1, std::round(x1), 1);
  EXPECT_NEAR(c.y0, std::round(y0), 1);
  EXPECT_NEAR(c.y1 + 1, std::round(y1), 1);
  // Covered pixels differ from the hull's area by at most the pixels its boundary crosses.
  const auto [area, perimeter] = hull_area_perimeter(corners);
  EXPECT_NEAR(double(c.count), area, perimeter);
  EXPECT_GT(area, 2000);  // the cube is not a speck
  // The renderer's own projection agrees with GLM's.
  const Projected p = project(cam, 320, 240, {1, 1, 1});
  const Point2 q = glm_project(cam, 320, 240, {1, 1, 1});
  EXPECT_NEAR(p.x, q.x, 1e-9);
  EXPECT_NEAR(p.y, q.y, 1e-9);
}

TEST(Render, ViewportsAndFraming) {
  Renderer r = make(400, 200);
  Scene scene;
  scene.meshes.push_back(cube(0.5));
  const std::vector<Viewport> cols = columns(400, 200, 2);
  ASSERT_EQ(cols.size(), 2u);
  // Framing: the bounding sphere fits the right viewport, so the silhouette is inside it.
  const Camera cam = Camera::framing(scene.bounds(), 1.0, 0.3, 0.2);
  r.draw(scene, cam, cols[1]);
  const Image im = r.read();
  EXPECT_EQ(coverage(im, 0, 200).count, 0) << "the left viewport stays empty";
  const Coverage c = coverage(im, 200, 400);
  ASSERT_GT(c.count, 0);
  EXPECT_GT(c.x0, 200);
  EXPECT_LT(c.x1, 399);
  EXPECT_GT(c.y0, 0);
  EXPECT_LT(c.y1, 199);
  // The target (the cube's centre) projects to the viewport's centre.
  const Point2 centre = glm_project(cam, 200, 200, {0, 0, 0});
  EXPECT_NEAR(centre.x, 100, 1e-9);
  EXPECT_NEAR(centre.y, 100, 1e-9);
}

TEST(Render, CaptionsLandWhereTheViewPutsThoseCoordinates) {
  // overlay_point(u, v) must project to the pixel that normalized device coordinates (u, v) name,
  // for any camera and aspect; a caption too long for its view is shrunk to end before u = 0.95.
  for (const auto& [yaw, pitch, aspect] : {std::tuple{0.6, 0.35, 1.0}, std::tuple{-2.0, -1.2, 3.0}, std::tuple{3.0, 1.4, 0.4}}) {
    Camera camera;
    camera.target = {1, -2, 0.5}, camera.distance = 7, camera.yaw = yaw, camera.pitch = pitch;
    const int h = 300, w = static_cast<int>(h * aspect);
    for (const auto& [u, v] : {std::pair{-0.95, 0.9}, std::pair{0.0, 0.0}, std::pair{0.5, -0.7}}) {
      const Projected p = project(camera, w, h, overlay_point(camera, aspect, u, v));
      EXPECT_NEAR(p.x, (u + 1) / 2 * w, 1e-6 * w) << yaw;
      EXPECT_NEAR(p.y, (1 - v) / 2 * h, 1e-6 * h) << yaw;
    }
    Lines caption;
    add_overlay_text(caption, camera, aspect, "A CAPTION FAR TOO LONG FOR ANY VIEW OF THIS SIZE", -0.95, 0.8, 0.2);
    ASSERT_FALSE(caption.points.empty());
    double right = -1e9;
    for (const Vec3<float>& q : caption.points) right = std::max(right, project(camera, w, h, {double(q.x), double(q.y), double(q.z)}).x);
    EXPECT_LE(right, (0.95 + 1) / 2 * w + 1e-6 * w);
    EXPECT_GT(right, 0.8 * w);  // shrunk to fit, not to nothing
  }
}

TEST(Render, LinesOnTopShowThroughAndPngKeepsThePixels) {
  Renderer r = make(160, 120);
  Scene scene;
  scene.meshes.push_back(cube(1));
  Camera cam;
  cam.yaw = 0, cam.pitch = 0, cam.distance = 5, cam.near_plane = 0.1, cam.far_plane = 20;
  // A vertical segment through the cube's centre: hidden by the cube unless drawn on top.
  scene.lines.push_back({{{0, -0.5f, 0}, {0, 0.5f, 0}}, {1, 0, 0, 1}, true});
  r.draw(scene, cam);
  const Image im = r.read();
  const Point2 mid = glm_project(cam, 160, 120, {0, 0, 0});
  int red = 0;
  for (int x = int(mid.x) - 3; x <= int(mid.x) + 3; ++x) {
    const auto p = im.pixel(x, int(mid.y));
    red += p[0] == 255 && p[1] == 0 && p[2] == 0;
  }
  EXPECT_EQ(red, 1) << "one pixel-wide red line at the centre";
  const std::filesystem::path path = std::filesystem::temp_directory_path() / ("dqkit_render_test_" + std::to_string(::getpid()) + ".png");
  ASSERT_TRUE(im.write_png(path).ok());
  int w = 0, h = 0, n = 0;
  unsigned char* data = stbi_load(path.c_str(), &w, &h, &n, 4);
  ASSERT_NE(data, nullptr);
  EXPECT_EQ(w, 160);
  EXPECT_EQ(h, 120);
  EXPECT_TRUE(std::equal(im.rgba.begin(), im.rgba.end(), data));
  stbi_image_free(data);
  std::filesystem::remove(path);
}

// A window (GLFW) where there is a display: the same drawing, shown; without a display, an error
// that says so. (Run under xvfb-run to exercise the window.)
TEST(Render, WindowShowsTheSameDrawing) {
  const bool display = std::getenv("DISPLAY") || std::getenv("WAYLAND_DISPLAY");
  Expected<Renderer> w = Renderer::create_window({160, 120, 1, {1, 1, 1, 1}}, "dqkit test");
  if (!display) {
    ASSERT_FALSE(w.has_value());
    EXPECT_NE(w.error().message.find("no window"), std::string::npos) << w.error().message;
    return;
  }
  ASSERT_TRUE(w.has_value()) << w.error().message;
  Renderer headless = make(160, 120);
  Scene scene;
  scene.meshes.push_back(cube(1));
  Camera cam;
  cam.yaw = 0.5, cam.pitch = 0.4, cam.distance = 6, cam.near_plane = 0.1, cam.far_plane = 20;
  w->draw(scene, cam);
  headless.draw(scene, cam);
  EXPECT_TRUE(w->present());
  const Image a = w->read(), b = headless.read();
  const Coverage ca = coverage(a, 0, 160), cb = coverage(b, 0, 160);
  EXPECT_EQ(ca.x0, cb.x0);
  EXPECT_EQ(ca.x1, cb.x1);
  EXPECT_EQ(ca.y0, cb.y0);
  EXPECT_EQ(ca.y1, cb.y1);
  EXPECT_EQ(ca.count, cb.count);
  EXPECT_FALSE(headless.present());
}

TEST(Render, ErrorsSayWhy) {
  const Expected<Renderer> r = Renderer::create({0, 10, 1, {}});
  ASSERT_FALSE(r.has_value());
  EXPECT_NE(r.error().message.find("image size"), std::string::npos);
  EXPECT_FALSE(Image{}.write_png("/nonexistent-dir/x.png").ok());
}

}  // namespace
}  // namespace dq::render

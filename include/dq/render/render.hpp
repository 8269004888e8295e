// A small OpenGL 3.3 core renderer (library dqkit::render) for pictures without a display:
// triangle meshes with simple lighting, lines and points (skeletons, targets), an orbit camera
// that frames a bounding box, several viewports in one image, PNG output.
//
// The context is Mesa's EGL on the surfaceless platform (no X server, no GPU needed: llvmpipe),
// rendering into a multisampled framebuffer object; or, where there is a display, a GLFW window
// that shows the same framebuffer (create_window, present). Independent of the skinning code: it draws
// positions, normals and triangles.
//
// Conventions: right-handed world, column vectors; the camera looks at `target` from `distance`
// along the direction given by yaw (about +y, from +z towards +x) and pitch (up from the xz
// plane), with +y up on screen. Images are RGBA8, top row first.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "dq/core/matrix.hpp"
#include "dq/core/vec3.hpp"
#include "dq/util/expected.hpp"

namespace dq::render {

struct Color {
  float r = 0.8f, g = 0.8f, b = 0.8f, a = 1.0f;
};

struct Bounds {
  Vec3<double> lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
  void add(const Vec3<double>& p);
  void add(const Bounds& b);
  bool empty() const noexcept { return lo.x > hi.x; }
  Vec3<double> center() const { return (lo + hi) * 0.5; }
  double radius() const { return 0.5 * norm(hi - lo); }  ///< of the bounding sphere of the box
};

/// A triangle mesh. Normals: one per vertex, or empty to have smooth normals computed from the
/// triangles (area-weighted).
struct Mesh {
  std::vector<Vec3<float>> positions;
  std::vector<Vec3<float>> normals;
  std::vector<std::uint32_t> triangles;
  Color color;
  Bounds bounds() const;
};

/// Line segments (pairs of points), drawn one pixel wide and unlit, in front of meshes if
/// `on_top` (a skeleton seen through its skin).
struct Lines {
  std::vector<Vec3<float>> points;
  Color color{0.1f, 0.1f, 0.1f, 1.0f};
  bool on_top = false;
};

/// Points drawn as squares of `size` pixels, unlit.
struct Points {
  std::vector<Vec3<float>> positions;
  Color color{0.9f, 0.2f, 0.1f, 1.0f};
  float size = 6.0f;
  bool on_top = false;
};

struct Scene {
  std::vector<Mesh> meshes;
  std::vector<Lines> lines;
  std::vector<Points> points;
  Bounds bounds() const;
};

struct Camera {
  Vec3<double> target{0, 0, 0};
  double distance = 5;
  double yaw = 0.6;     ///< radians about +y (0: looking from +z)
  double pitch = 0.35;  ///< radians up from the horizontal plane
  double fov_y = 0.7;   ///< vertical field of view, radians
  double near_plane = 0.01, far_plane = 100;

  Vec3<double> eye() const;
  Mat4<double> view() const;                       ///< world to camera
  Mat4<double> projection(double aspect) const;    ///< OpenGL clip space (depth −1..1)
  /// An orbit camera at yaw and pitch whose view (at any aspect ≥ `aspect`) contains the
  /// bounding sphere of `bounds` with a margin of `margin` (fraction of the radius).
  static Camera framing(const Bounds& bounds, double aspect, double yaw = 0.6, double pitch = 0.35, double fov_y = 0.7,
                        double margin = 0.05);
};

/// The pixel where a world point lands in a viewport of `width` × `height` pixels (x right from the
/// left edge, y down from the top row; pixel centres at half-integers), and its depth in NDC.
struct Projected {
  double x, y, depth;
};
Projected project(const Camera& camera, int width, int height, const Vec3<double>& point);

struct Image {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgba;  ///< top row first
  std::array<std::uint8_t, 4> pixel(int x, int y) const;
  /// Writes a PNG through OutputFile (atomically, replacing only a regular file). Errors say why.
  Status write_png(const std::filesystem::path& path) const;
};

/// What the user did in a window renderer's window during the last present() (which handles the
/// window's events). Positions are image pixels (x right from the left edge, y down from the top
/// row), scaled when the window was resized. Escape closes the window (present() then returns false).
struct WindowInput {
  double x = 0, y = 0;            ///< the cursor
  double drag_x = 0, drag_y = 0;  ///< cursor motion with the left button held
  bool clicked = false;           ///< the left button released within 3 pixels of where it was pressed
  double click_x = 0, click_y = 0;
  double wheel = 0;               ///< wheel steps, positive away from the user
  std::u32string typed;           ///< characters typed (keys without a character are not reported)
};

/// Mouse orbit, for a window's camera: a left-button drag turns it by `orbit_radians_per_pixel` per
/// pixel (dragging right turns the model right: yaw decreases; dragging down lowers the far side:
/// pitch increases, kept within ±orbit_max_pitch), each wheel step away from the user brings it 10%
/// nearer (the near and far planes move with it). The target and field of view stay.
inline constexpr double orbit_radians_per_pixel = 0.01;
inline constexpr double orbit_max_pitch = 1.5;  ///< radians (86°): at ±90° the view's up is undefined
void orbit(Camera& camera, const WindowInput& input);

/// The largest image side the renderer takes (llvmpipe's and most GPUs' framebuffer limit).
inline constexpr int max_image_side = 16384;

struct RenderOptions {
  int width = 800, height = 600;  ///< 1 to max_image_side
  int samples = 4;  ///< multisampling (1: none, so that tests can count exact pixels)
  Color background{1.0f, 1.0f, 1.0f, 1.0f};
};

/// One viewport of the image: pixels [x, x + width) × [y, y + height), y from the top row.
struct Viewport {
  int x = 0, y = 0, width = 0, height = 0;
};

class Renderer {
 public:
  /// Creates the headless context and the framebuffer. Errors say what is missing (no EGL
  /// display, no OpenGL 3.3 core context, ...).
  static Expected<Renderer> create(const RenderOptions& options);
  /// The same drawing shown in a window of the image's size (GLFW), for when there is a display:
  /// draw, then present(). Errors: dqkit built without GLFW, no display.
  static Expected<Renderer> create_window(const RenderOptions& options, const std::string& title = "dqkit");
  Renderer(Renderer&&) noexcept;
  Renderer& operator=(Renderer&&) noexcept;
  ~Renderer();

  int width() const noexcept;
  int height() const noexcept;
  /// "llvmpipe (LLVM 15.0.6, 256 bits) | 4.5 (Core Profile) Mesa 22.3.6"
  std::string description() const;
  /// Clears the whole image to the background colour.
  void clear();
  /// Draws a scene into a viewport (the whole image when the viewport is empty).
  void draw(const Scene& scene, const Camera& camera, Viewport viewport = {});
  /// Reads the image back.
  Image read() const;
  /// Window renderers: shows the image drawn since clear() (stretched to the window), then calls
  /// `overlay` (if any) with the window's own framebuffer bound and its viewport set, to draw over
  /// the image (a user interface: Dear ImGui's OpenGL 3 backend), swaps, waits for the rest of
  /// 1/60 s since the previous present (no busier where the swap does not wait for the display),
  /// and handles the window's events (input()). Returns false once the user has closed the window.
  /// Headless renderers: false, the overlay not called.
  bool present(const std::function<void()>& overlay = {});
  /// What the user did during the last present(); headless renderers: nothing.
  WindowInput input() const;
  /// The window (a GLFWwindow*; nullptr headless), for a toolkit drawing in it from the overlay,
  /// e.g. ImGui_ImplGlfw_InitForOpenGL(window, true). The toolkit must chain the callbacks it
  /// installs to the previous ones (ImGui's backend does), since input() comes from them.
  void* native_window() const noexcept;

 private:
  struct Impl;
  explicit Renderer(std::unique_ptr<Impl> impl);
  static Expected<Renderer> make(const RenderOptions& options, const std::string* window_title);
  std::unique_ptr<Impl> impl_;
};

/// Smooth per-vertex normals (area-weighted face normals) of a triangle mesh.
std::vector<Vec3<float>> vertex_normals(const std::vector<Vec3<float>>& positions, const std::vector<std::uint32_t>& triangles);

/// Side-by-side viewports: `count` columns of equal width filling width × height.
std::vector<Viewport> columns(int width, int height, int count);

}  // namespace dq::render

#define GL_GLEXT_PROTOTYPES
#include <GL/glcorearb.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "context.hpp"
#include "dq/render/render.hpp"

namespace dq::render {

// ---- camera -----------------------------------------------------------------------------------
Vec3<double> Camera::eye() const {
  return target + Vec3<double>{std::cos(pitch) * std::sin(yaw), std::sin(pitch), std::cos(pitch) * std::cos(yaw)} * distance;
}

Mat4<double> Camera::view() const {
  const Vec3<double> e = eye();
  const Vec3<double> f = normalized(target - e);
  Vec3<double> s = cross(f, Vec3<double>{0, 1, 0});
  if (norm(s) < 1e-12) s = {1, 0, 0};  // looking straight up or down
  s = normalized(s);
  const Vec3<double> u = cross(s, f);
  return Mat4<double>::from_rows(s.x, s.y, s.z, -dot(s, e), u.x, u.y, u.z, -dot(u, e), -f.x, -f.y, -f.z, dot(f, e), 0, 0, 0, 1);
}

Mat4<double> Camera::projection(double aspect) const {
  const double f = 1 / std::tan(fov_y / 2), n = near_plane, r = far_plane;
  return Mat4<double>::from_rows(f / aspect, 0, 0, 0, 0, f, 0, 0, 0, 0, (r + n) / (n - r), 2 * r * n / (n - r), 0, 0, -1, 0);
}

Camera Camera::framing(const Bounds& bounds, double aspect, double yaw, double pitch, double fov_y, double margin) {
  Camera c;
  c.yaw = yaw, c.pitch = pitch, c.fov_y = fov_y;
  const double r = bounds.empty() ? 1.0 : std::max(bounds.radius(), 1e-6);
  c.target = bounds.empty() ? Vec3<double>{0, 0, 0} : bounds.center();
  // The sphere fits when its angular radius is below the smaller half field of view.
  const double half = std::min(fov_y / 2, std::atan(std::tan(fov_y / 2) * aspect));
  c.distance = r * (1 + margin) / std::sin(half);
  c.near_plane = std::max(c.distance - 2 * r, c.distance * 1e-3);
  c.far_plane = c.distance + 2 * r;
  return c;
}

void orbit(Camera& c, const WindowInput& in) {
  c.yaw -= in.drag_x * orbit_radians_per_pixel;
  c.pitch = std::clamp(c.pitch + in.drag_y * orbit_radians_per_pixel, -orbit_max_pitch, orbit_max_pitch);
  if (in.wheel != 0) {
    const double distance = c.distance * std::pow(0.9, in.wheel), change = distance - c.distance;
    c.distance = distance;
    c.far_plane += change;
    c.near_plane = std::max(c.near_plane + change, distance * 1e-3);
  }
}

Projected project(const Camera& camera, int width, int height, const Vec3<double>& p) {
  const Mat4<double> m = camera.projection(double(width) / double(height)) * camera.view();
  double clip[4];
  for (int r = 0; r < 4; ++r) clip[r] = m(r, 0) * p.x + m(r, 1) * p.y + m(r, 2) * p.z + m(r, 3);
  return {(clip[0] / clip[3] + 1) / 2 * width, (1 - clip[1] / clip[3]) / 2 * height, clip[2] / clip[3]};
}

// ---- OpenGL -----------------------------------------------------------------------------------
namespace {

const char* kMeshVertex = R"(#version 330 core
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;
uniform mat4 model_view;
uniform mat4 projection;
out vec3 view_normal;
out vec3 view_position;
void main() {
  vec4 p = model_view * vec4(position, 1.0);
  view_position = p.xyz;
  view_normal = mat3(model_view) * normal;
  gl_Position = projection * p;
})";

// A key light above and to the left of the camera, a weaker fill from the right, ambient, and a
// little specular; two-sided (back faces lit as front faces seen from behind).
const char* kMeshFragment = R"(#version 330 core
in vec3 view_normal;
in vec3 view_position;
uniform vec4 color;
out vec4 fragment;
void main() {
  vec3 n = normalize(view_normal);
  if (!gl_FrontFacing) n = -n;
  vec3 v = normalize(-view_position);
  if (dot(n, v) < 0.0) n = -n;
  vec3 key = normalize(vec3(-0.4, 0.6, 0.7));
  vec3 fill = normalize(vec3(0.6, 0.1, 0.5));
  float diffuse = 0.7 * max(dot(n, key), 0.0) + 0.25 * max(dot(n, fill), 0.0);
  float specular = 0.25 * pow(max(dot(reflect(-key, n), v), 0.0), 24.0);
  fragment = vec4(color.rgb * (0.22 + diffuse) + vec3(specular), color.a);
})";

const char* kFlatVertex = R"(#version 330 core
layout(location = 0) in vec3 position;
uniform mat4 model_view;
uniform mat4 projection;
uniform float point_size;
void main() {
  gl_Position = projection * model_view * vec4(position, 1.0);
  gl_PointSize = point_size;
})";

const char* kFlatFragment = R"(#version 330 core
uniform vec4 color;
out vec4 fragment;
void main() { fragment = color; })";

GLuint compile(GLenum type, const char* source, std::string& error) {
  const GLuint s = glCreateShader(type);
  glShaderSource(s, 1, &source, nullptr);
  glCompileShader(s);
  GLint ok = 0;
  glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[1024] = {};
    glGetShaderInfoLog(s, sizeof log, nullptr, log);
    error = std::string("rendering: a shader does not compile: ") + log;
  }
  return s;
}

GLuint program(const char* vertex, const char* fragment, std::string& error) {
  const GLuint p = glCreateProgram();
  const GLuint v = compile(GL_VERTEX_SHADER, vertex, error), f = compile(GL_FRAGMENT_SHADER, fragment, error);
  glAttachShader(p, v);
  glAttachShader(p, f);
  glLinkProgram(p);
  glDeleteShader(v);
  glDeleteShader(f);
  GLint ok = 0;
  glGetProgramiv(p, GL_LINK_STATUS, &ok);
  if (!ok && error.empty()) error = "rendering: a shader program does not link";
  return p;
}

std::array<float, 16> to_float(const Mat4<double>& m) {
  std::array<float, 16> out{};
  for (std::size_t i = 0; i < 16; ++i) out[i] = static_cast<float>(m.m[i]);
  return out;
}

}  // namespace

struct Renderer::Impl {
  std::unique_ptr<detail::Context> context;
  RenderOptions options;
  GLuint msaa_fbo = 0, resolve_fbo = 0, color_rb = 0, depth_rb = 0, resolve_rb = 0;
  GLuint mesh_program = 0, flat_program = 0, vao = 0, vbo = 0, ebo = 0;

  ~Impl() {
    if (!context) return;
    context->make_current();
    glDeleteFramebuffers(1, &msaa_fbo);
    glDeleteFramebuffers(1, &resolve_fbo);
    const GLuint rbs[] = {color_rb, depth_rb, resolve_rb};
    glDeleteRenderbuffers(3, rbs);
    glDeleteProgram(mesh_program);
    glDeleteProgram(flat_program);
    glDeleteVertexArrays(1, &vao);
    glDeleteBuffers(1, &vbo);
    glDeleteBuffers(1, &ebo);
  }

  /// The multisampled image into the single-sampled framebuffer.
  void resolve();

  void uniforms(GLuint prog, const Camera& camera, double aspect, const Color& color) {
    glUseProgram(prog);
    const auto mv = to_float(camera.view()), pr = to_float(camera.projection(aspect));
    glUniformMatrix4fv(glGetUniformLocation(prog, "model_view"), 1, GL_FALSE, mv.data());
    glUniformMatrix4fv(glGetUniformLocation(prog, "projection"), 1, GL_FALSE, pr.data());
    glUniform4f(glGetUniformLocation(prog, "color"), color.r, color.g, color.b, color.a);
  }

  void flat(const std::vector<Vec3<float>>& points, GLenum mode, const Camera& camera, double aspect, const Color& color,
            float size, bool on_top) {
    if (points.empty()) return;
    uniforms(flat_program, camera, aspect, color);
    glUniform1f(glGetUniformLocation(flat_program, "point_size"), size);
    glBindBuffer(GL_ARRAY_BUFFER, vbo);
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(points.size() * sizeof(Vec3<float>)), points.data(), GL_STREAM_DRAW);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(Vec3<float>), nullptr);
    glDisableVertexAttribArray(1);
    if (on_top) glDisable(GL_DEPTH_TEST);
    glDrawArrays(mode, 0, static_cast<GLsizei>(points.size()));
    glEnable(GL_DEPTH_TEST);
  }
};

Renderer::Renderer(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Renderer::Renderer(Renderer&&) noexcept = default;
Renderer& Renderer::operator=(Renderer&&) noexcept = default;
Renderer::~Renderer() = default;

Expected<Renderer> Renderer::create(const RenderOptions& options) { return make(options, nullptr); }

Expected<Renderer> Renderer::create_window(const RenderOptions& options, const std::string& title) { return make(options, &title); }

Expected<Renderer> Renderer::make(const RenderOptions& options, const std::string* window_title) {
  if (options.width < 1 || options.height < 1 || options.width > max_image_side || options.height > max_image_side)
    return Error{"rendering: the image size must be between 1 and " + std::to_string(max_image_side) + " pixels on each side"};
  if (options.samples < 1 || options.samples > 16) return Error{"rendering: samples must be between 1 and 16"};
  Expected<std::unique_ptr<detail::Context>> context =
      window_title ? detail::create_window(options.width, options.height, *window_title) : detail::create_headless();
  if (!context) return context.error();
  auto impl = std::make_unique<Impl>();
  impl->context = std::move(*context);
  impl->options = options;
  Impl& g = *impl;
  const GLsizei w = options.width, h = options.height;
  // One sample: plain storage (a multisampled buffer of "1" sample may get more from the driver).
  auto storage = [&](GLenum format) {
    if (options.samples > 1)
      glRenderbufferStorageMultisample(GL_RENDERBUFFER, options.samples, format, w, h);
    else
      glRenderbufferStorage(GL_RENDERBUFFER, format, w, h);
  };
  glGenRenderbuffers(1, &g.color_rb);
  glBindRenderbuffer(GL_RENDERBUFFER, g.color_rb);
  storage(GL_RGBA8);
  glGenRenderbuffers(1, &g.depth_rb);
  glBindRenderbuffer(GL_RENDERBUFFER, g.depth_rb);
  storage(GL_DEPTH_COMPONENT24);
  glGenFramebuffers(1, &g.msaa_fbo);
  glBindFramebuffer(GL_FRAMEBUFFER, g.msaa_fbo);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, g.color_rb);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, g.depth_rb);
  if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
    return Error{"rendering: the OpenGL driver cannot make a " + std::to_string(w) + " x " + std::to_string(h) + " framebuffer with " +
                 std::to_string(options.samples) + " samples (too large for it? try a smaller size)"};
  glGenRenderbuffers(1, &g.resolve_rb);
  glBindRenderbuffer(GL_RENDERBUFFER, g.resolve_rb);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, w, h);
  glGenFramebuffers(1, &g.resolve_fbo);
  glBindFramebuffer(GL_FRAMEBUFFER, g.resolve_fbo);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, g.resolve_rb);
  if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) return Error{"rendering: the resolve framebuffer is incomplete"};
  std::string error;
  g.mesh_program = program(kMeshVertex, kMeshFragment, error);
  g.flat_program = program(kFlatVertex, kFlatFragment, error);
  if (!error.empty()) return Error{error};
  glGenVertexArrays(1, &g.vao);
  glBindVertexArray(g.vao);
  glGenBuffers(1, &g.vbo);
  glGenBuffers(1, &g.ebo);
  glEnable(GL_PROGRAM_POINT_SIZE);
  glEnable(GL_DEPTH_TEST);
  Renderer r(std::move(impl));
  r.clear();
  return r;
}

int Renderer::width() const noexcept { return impl_->options.width; }
int Renderer::height() const noexcept { return impl_->options.height; }

std::string Renderer::description() const {
  impl_->context->make_current();
  return std::string(reinterpret_cast<const char*>(glGetString(GL_RENDERER))) + " | " +
         reinterpret_cast<const char*>(glGetString(GL_VERSION));
}

void Renderer::clear() {
  impl_->context->make_current();
  glBindFramebuffer(GL_FRAMEBUFFER, impl_->msaa_fbo);
  glDisable(GL_SCISSOR_TEST);
  const Color& c = impl_->options.background;
  glClearColor(c.r, c.g, c.b, c.a);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
}

void Renderer::draw(const Scene& scene, const Camera& camera, Viewport vp) {
  Impl& g = *impl_;
  g.context->make_current();
  if (vp.width <= 0 || vp.height <= 0) vp = {0, 0, width(), height()};
  glBindFramebuffer(GL_FRAMEBUFFER, g.msaa_fbo);
  const GLint gl_y = height() - vp.y - vp.height;  // OpenGL counts rows from the bottom
  glViewport(vp.x, gl_y, vp.width, vp.height);
  glScissor(vp.x, gl_y, vp.width, vp.height);
  glEnable(GL_SCISSOR_TEST);
  glClear(GL_DEPTH_BUFFER_BIT);
  glEnable(GL_DEPTH_TEST);
  const double aspect = double(vp.width) / double(vp.height);
  glBindVertexArray(g.vao);
  std::vector<float> interleaved;
  for (const Mesh& mesh : scene.meshes) {
    if (mesh.triangles.empty()) continue;
    const std::vector<Vec3<float>> computed = mesh.normals.size() == mesh.positions.size() ? std::vector<Vec3<float>>{}
                                                                                              : vertex_normals(mesh.positions, mesh.triangles);
    const std::vector<Vec3<float>>& normals = computed.empty() ? mesh.normals : computed;
    interleaved.resize(mesh.positions.size() * 6);
    for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
      const Vec3<float>& p = mesh.positions[v];
      const Vec3<float>& n = normals[v];
      std::copy_n(std::array<float, 6>{p.x, p.y, p.z, n.x, n.y, n.z}.data(), 6, interleaved.data() + 6 * v);
    }
    g.uniforms(g.mesh_program, camera, aspect, mesh.color);
    glBindBuffer(GL_ARRAY_BUFFER, g.vbo);
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(interleaved.size() * sizeof(float)), interleaved.data(), GL_STREAM_DRAW);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), nullptr);
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), reinterpret_cast<const void*>(3 * sizeof(float)));
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, g.ebo);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(mesh.triangles.size() * sizeof(std::uint32_t)), mesh.triangles.data(), GL_STREAM_DRAW);
    glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(mesh.triangles.size()), GL_UNSIGNED_INT, nullptr);
  }
  for (const Lines& l : scene.lines) g.flat(l.points, GL_LINES, camera, aspect, l.color, 1.0f, l.on_top);
  for (const Points& p : scene.points) g.flat(p.positions, GL_POINTS, camera, aspect, p.color, p.size, p.on_top);
  glDisable(GL_SCISSOR_TEST);
}

void Renderer::Impl::resolve() {
  context->make_current();
  const int w = options.width, h = options.height;
  glBindFramebuffer(GL_READ_FRAMEBUFFER, msaa_fbo);
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, resolve_fbo);
  glBlitFramebuffer(0, 0, w, h, 0, 0, w, h, GL_COLOR_BUFFER_BIT, GL_NEAREST);
}

bool Renderer::present(const std::function<void()>& overlay) {
  Impl& g = *impl_;
  g.resolve();
  const bool open = g.context->present(g.resolve_fbo, width(), height(), overlay);
  glBindFramebuffer(GL_FRAMEBUFFER, g.msaa_fbo);
  return open;
}

WindowInput Renderer::input() const { return impl_->context->input(); }

void* Renderer::native_window() const noexcept { return impl_->context->native_window(); }

Image Renderer::read() const {
  Impl& g = *impl_;
  g.resolve();
  const int w = width(), h = height();
  glBindFramebuffer(GL_READ_FRAMEBUFFER, g.resolve_fbo);
  Image image;
  image.width = w, image.height = h;
  image.rgba.resize(static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * 4);
  std::vector<std::uint8_t> bottom_up(image.rgba.size());
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, bottom_up.data());
  const std::size_t row = static_cast<std::size_t>(w) * 4;
  for (int y = 0; y < h; ++y)
    std::copy_n(bottom_up.data() + static_cast<std::size_t>(h - 1 - y) * row, row, image.rgba.data() + static_cast<std::size_t>(y) * row);
  glBindFramebuffer(GL_FRAMEBUFFER, g.msaa_fbo);
  return image;
}

}  // namespace dq::render

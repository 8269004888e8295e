// The window context of dqkit::render (GLFW, Debian libglfw3-dev), for when there is a display.
#include "context.hpp"

#if defined(DQKIT_HAVE_GLFW)
#include <algorithm>
#include <chrono>
#include <cmath>
#include <thread>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#define GL_GLEXT_PROTOTYPES
#include <GL/glcorearb.h>
#endif

namespace dq::render::detail {

#if defined(DQKIT_HAVE_GLFW)
namespace {

class GlfwContext final : public Context {
 public:
  GlfwContext(GLFWwindow* window, int width, int height) : window_(window), width_(width), height_(height) {
    glfwSetWindowUserPointer(window_, this);
    glfwSetMouseButtonCallback(window_, [](GLFWwindow* w, int button, int action, int) {
      if (button == GLFW_MOUSE_BUTTON_LEFT) self(w).button(action == GLFW_PRESS);
    });
    glfwSetCursorPosCallback(window_, [](GLFWwindow* w, double x, double y) { self(w).moved(x, y); });
    glfwSetScrollCallback(window_, [](GLFWwindow* w, double, double dy) { self(w).input_.wheel += dy; });
    glfwSetCharCallback(window_, [](GLFWwindow* w, unsigned code) { self(w).input_.typed += static_cast<char32_t>(code); });
    glfwSetKeyCallback(window_, [](GLFWwindow* w, int key, int, int action, int) {
      if (key == GLFW_KEY_ESCAPE && action == GLFW_PRESS) glfwSetWindowShouldClose(w, GLFW_TRUE);
    });
  }
  ~GlfwContext() override {
    release_if_current();
    glfwDestroyWindow(window_);  // GLFW itself stays initialized
  }
  void acquire() const override { glfwMakeContextCurrent(window_); }
  void release() const override { glfwMakeContextCurrent(nullptr); }
  bool present(unsigned fbo, int width, int height, const std::function<void()>& overlay) override {
    make_current();
    int w = 0, h = 0;
    glfwGetFramebufferSize(window_, &w, &h);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
    glBlitFramebuffer(0, 0, width, height, 0, 0, w, h, GL_COLOR_BUFFER_BIT, GL_LINEAR);
    if (overlay) {
      glBindFramebuffer(GL_FRAMEBUFFER, 0);
      glViewport(0, 0, w, h);
      overlay();
    }
    glfwSwapBuffers(window_);
    const auto next = last_present_ + std::chrono::microseconds(1000000 / 60);
    std::this_thread::sleep_until(next);
    last_present_ = std::chrono::steady_clock::now();
    const double x = input_.x, y = input_.y;
    input_ = WindowInput{};
    input_.x = x, input_.y = y;
    glfwPollEvents();
    return !glfwWindowShouldClose(window_);
  }
  WindowInput input() const override { return input_; }
  void* native_window() const override { return window_; }

 private:
  static GlfwContext& self(GLFWwindow* w) { return *static_cast<GlfwContext*>(glfwGetWindowUserPointer(w)); }
  /// A cursor position in window coordinates, in image pixels.
  void moved(double wx, double wy) {
    int w = 1, h = 1;
    glfwGetWindowSize(window_, &w, &h);
    const double x = wx * width_ / std::max(w, 1), y = wy * height_ / std::max(h, 1);
    if (pressed_) {
      input_.drag_x += x - input_.x, input_.drag_y += y - input_.y;
      travel_ = std::max(travel_, std::hypot(x - press_x_, y - press_y_));
    }
    input_.x = x, input_.y = y;
  }
  // At the cursor of the events handled so far, where the press happened (GLFW reports the cursor
  // on entering the window too); querying the pointer now would give a later position.
  void button(bool down) {
    if (down) {
      press_x_ = input_.x, press_y_ = input_.y, travel_ = 0;
    } else if (pressed_ && travel_ <= 3) {
      input_.clicked = true, input_.click_x = input_.x, input_.click_y = input_.y;
    }
    pressed_ = down;
  }

  GLFWwindow* window_;
  int width_, height_;  ///< of the image
  WindowInput input_;
  bool pressed_ = false;
  double press_x_ = 0, press_y_ = 0, travel_ = 0;
  std::chrono::steady_clock::time_point last_present_{};
};

std::string glfw_error(const char* what) {
  const char* description = nullptr;
  glfwGetError(&description);
  return std::string("rendering: ") + what + (description ? std::string(" (GLFW: ") + description + ")" : std::string());
}

}  // namespace

Expected<std::unique_ptr<Context>> create_window(int width, int height, const std::string& title) {
  if (!glfwInit()) return Error{glfw_error("no window: GLFW cannot start, is there a display?")};
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  GLFWwindow* window = glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr);
  if (!window) return Error{glfw_error("no window with an OpenGL 3.3 core context")};
  auto context = std::make_unique<GlfwContext>(window, width, height);
  context->make_current();
  glfwSwapInterval(1);
  return std::unique_ptr<Context>(std::move(context));
}

#else

Expected<std::unique_ptr<Context>> create_window(int, int, const std::string&) {
  return Error{"rendering: no window: dqkit was built without GLFW (Debian libglfw3-dev)"};
}

#endif

}  // namespace dq::render::detail

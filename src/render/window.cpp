// The window context of dqkit::render (GLFW, Debian libglfw3-dev), for when there is a display.
#include "context.hpp"

#if defined(DQKIT_HAVE_GLFW)
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
  explicit GlfwContext(GLFWwindow* window) : window_(window) {}
  ~GlfwContext() override {
    release_if_current();
    glfwDestroyWindow(window_);  // GLFW itself stays initialized
  }
  void acquire() const override { glfwMakeContextCurrent(window_); }
  void release() const override { glfwMakeContextCurrent(nullptr); }
  bool present(unsigned fbo, int width, int height) override {
    make_current();
    int w = 0, h = 0;
    glfwGetFramebufferSize(window_, &w, &h);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
    glBlitFramebuffer(0, 0, width, height, 0, 0, w, h, GL_COLOR_BUFFER_BIT, GL_LINEAR);
    glfwSwapBuffers(window_);
    glfwPollEvents();
    return !glfwWindowShouldClose(window_);
  }

 private:
  GLFWwindow* window_;
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
  auto context = std::make_unique<GlfwContext>(window);
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

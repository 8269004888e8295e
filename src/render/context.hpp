// The OpenGL contexts of dqkit::render: headless (EGL on Mesa's surfaceless platform) and, where
// GLFW is available and there is a display, a window.
#pragma once

#include <functional>
#include <memory>
#include <string>

#include "dq/render/render.hpp"
#include "dq/util/expected.hpp"

namespace dq::render::detail {

class Context {
 public:
  virtual ~Context() = default;
  /// Makes the context current on the calling thread, first releasing the thread's current one
  /// if it is another (GLVND refuses an EGL context on a thread where a GLX context is current).
  void make_current() const;
  /// Windows: copies the framebuffer object `fbo` (width × height) to the window, calls `overlay`
  /// (if set) to draw over it, shows it and handles events; returns false once the window was
  /// closed. Headless: nothing, false.
  virtual bool present(unsigned fbo, int width, int height, const std::function<void()>& overlay) = 0;
  /// Windows: what the user did during the last present(). Headless: nothing.
  virtual WindowInput input() const { return {}; }
  /// Windows: the GLFWwindow*. Headless: nullptr.
  virtual void* native_window() const { return nullptr; }

 protected:
  virtual void acquire() const = 0;
  virtual void release() const = 0;
  /// For the destructors of derived classes: releases the context if it is the thread's current.
  void release_if_current() const;
};

/// An OpenGL 3.3 core context with no surface, current on the calling thread.
Expected<std::unique_ptr<Context>> create_headless();
/// A window of width × height showing an OpenGL 3.3 core context (GLFW); an error when dqkit was
/// built without GLFW or there is no display.
Expected<std::unique_ptr<Context>> create_window(int width, int height, const std::string& title);

}  // namespace dq::render::detail

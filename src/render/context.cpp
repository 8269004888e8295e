#include "context.hpp"

#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <cstdio>
#include <string>

namespace dq::render::detail {

namespace {
std::string egl_error(const char* what) {
  char code[16];
  std::snprintf(code, sizeof code, "0x%04x", static_cast<unsigned>(eglGetError()));
  return std::string("rendering: ") + what + " (EGL error " + code + ")";
}

thread_local const Context* current = nullptr;

class EglContext final : public Context {
 public:
  ~EglContext() override {
    release_if_current();
    if (context_ != EGL_NO_CONTEXT) eglDestroyContext(display_, context_);
    // The display is shared by every context of the process: it stays initialized.
  }
  void acquire() const override { eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_); }
  void release() const override { eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT); }
  bool present(unsigned, int, int, const std::function<void()>&) override { return false; }
  EGLDisplay display_ = EGL_NO_DISPLAY;
  EGLContext context_ = EGL_NO_CONTEXT;
};

}  // namespace

void Context::make_current() const {
  if (current == this) return;
  if (current) current->release();
  acquire();
  current = this;
}

void Context::release_if_current() const {
  if (current != this) return;
  release();
  current = nullptr;
}

Expected<std::unique_ptr<Context>> create_headless() {
  auto c = std::make_unique<EglContext>();
  // Mesa's surfaceless platform needs no X server, Wayland compositor or GPU (llvmpipe).
  EGLDisplay display = EGL_NO_DISPLAY;
  const char* extensions = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  if (extensions && std::string(extensions).find("EGL_MESA_platform_surfaceless") != std::string::npos) {
    auto get_platform_display = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
    if (get_platform_display) display = get_platform_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
  }
  if (display == EGL_NO_DISPLAY) display = eglGetDisplay(EGL_DEFAULT_DISPLAY);
  if (display == EGL_NO_DISPLAY) return Error{egl_error("no EGL display (is Mesa's libegl-mesa0 installed?)")};
  EGLint major = 0, minor = 0;
  if (!eglInitialize(display, &major, &minor)) return Error{egl_error("EGL could not be initialized")};
  c->display_ = display;
  if (!eglBindAPI(EGL_OPENGL_API)) return Error{egl_error("EGL has no desktop OpenGL")};
  const EGLint config_attributes[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
  EGLConfig config = nullptr;
  EGLint configs = 0;
  eglChooseConfig(display, config_attributes, &config, 1, &configs);
  const EGLint context_attributes[] = {EGL_CONTEXT_MAJOR_VERSION, 3, EGL_CONTEXT_MINOR_VERSION, 3, EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                       EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
  // Rendering goes to framebuffer objects: a configless context is enough where there is no config.
  EGLContext context = eglCreateContext(display, configs > 0 ? config : EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, context_attributes);
  if (context == EGL_NO_CONTEXT) return Error{egl_error("no OpenGL 3.3 core context")};
  c->context_ = context;
  c->make_current();
  if (eglGetCurrentContext() != context) return Error{egl_error("the context cannot be made current without a surface")};
  return std::unique_ptr<Context>(std::move(c));
}

}  // namespace dq::render::detail

#include "common.hpp"

#include <cstdio>
#include <iostream>

#if defined(DQKIT_DEMO_WINDOW)
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <imgui.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#define GL_GLEXT_PROTOTYPES
#include <GL/glcorearb.h>
#endif

namespace dq::apps {

void add_options(CLI::App& app, Options& o) {
  app.add_flag("--headless", o.headless, "Render frames to PNG without a display (EGL), then exit");
  app.add_option("--frames", o.frames, "Frames to render headless")->check(CLI::Range(1, 100000));
  app.add_option("--out", o.out, "Directory for frame_0000.png ... (created)");
  app.add_option("--width", o.width, "Image width, pixels")->check(CLI::Range(16, 8192));
  app.add_option("--height", o.height, "Image height, pixels")->check(CLI::Range(16, 8192));
  app.add_option("--quit-after", o.quit_after, "Window: close after this many frames (0: never)")->check(CLI::NonNegativeNumber);
  app.add_option("--screenshot", o.screenshot, "Window: write the last image shown to this PNG on exit");
}

int run_headless(const Options& o, const std::function<std::vector<demo::View>(int)>& views) {
  render::RenderOptions ro;
  ro.width = o.width;
  ro.height = o.height;
  auto renderer = render::Renderer::create(ro);
  if (!renderer) {
    std::cerr << "error: no headless renderer: " << renderer.error().message << "\n";
    return 1;
  }
  std::error_code ec;
  std::filesystem::create_directories(o.out, ec);
  if (ec) {
    std::cerr << "error: cannot create " << o.out << ": " << ec.message() << "\n";
    return 1;
  }
  for (int f = 0; f < o.frames; ++f) {
    renderer->clear();
    for (const demo::View& v : views(f)) renderer->draw(v.scene, v.camera, v.viewport);
    char name[32];
    std::snprintf(name, sizeof name, "frame_%04d.png", f);
    if (const Status s = renderer->read().write_png(o.out / name); !s) {
      std::cerr << "error: " << s.error().message << "\n";
      return 1;
    }
  }
  std::cout << "wrote " << o.frames << " frames to " << (o.out / "frame_0000.png").string() << " ...\n";
  return 0;
}

#if defined(DQKIT_DEMO_WINDOW)
int run_window(const Options& o, const char* title,
               const std::function<std::vector<demo::View>(const Input&, render::Renderer&)>& frame) {
  // The image comes from the headless renderer (EGL); the window's context (GLX) only shows it.
  // A thread has one current context across both APIs: the window's is released while the
  // renderer draws.
  render::RenderOptions ro;
  ro.width = o.width;
  ro.height = o.height;
  auto renderer = render::Renderer::create(ro);
  if (!renderer) {
    std::cerr << "error: no renderer: " << renderer.error().message << "\n";
    return 1;
  }
  if (!glfwInit()) {
    std::cerr << "error: no display for a window (GLFW could not initialize); use --headless\n";
    return 1;
  }
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_CONTEXT_CREATION_API, GLFW_EGL_CONTEXT_API);  // as the renderer: one API switching contexts
  GLFWwindow* window = glfwCreateWindow(o.width, o.height, title, nullptr, nullptr);
  if (!window) {
    std::cerr << "error: could not open an OpenGL 3.3 window\n";
    glfwTerminate();
    return 1;
  }
  glfwMakeContextCurrent(window);
  glfwSwapInterval(1);
  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGui::GetIO().IniFilename = nullptr;
  ImGui_ImplGlfw_InitForOpenGL(window, true);
  ImGui_ImplOpenGL3_Init("#version 330");
  Input input;
  glfwSetWindowUserPointer(window, &input);
  glfwSetKeyCallback(window, [](GLFWwindow* w, int key, int scancode, int action, int mods) {
    ImGui_ImplGlfw_KeyCallback(w, key, scancode, action, mods);
    if (action == GLFW_PRESS && !ImGui::GetIO().WantCaptureKeyboard) static_cast<Input*>(glfwGetWindowUserPointer(w))->keys.push_back(key);
  });

  GLuint texture = 0;
  glGenTextures(1, &texture);
  render::Image image;
  bool pressed = false;
  double press_x = 0, press_y = 0, last_x = 0, last_y = 0, dragged = 0;
  for (int count = 0; !glfwWindowShouldClose(window) && (o.quit_after == 0 || count < o.quit_after); ++count) {
    glfwPollEvents();
    glfwMakeContextCurrent(window);
    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
    // The mouse, in image pixels (the image fills the window).
    double mx = 0, my = 0;
    int ww = 1, wh = 1;
    glfwGetCursorPos(window, &mx, &my);
    glfwGetWindowSize(window, &ww, &wh);
    input.mouse_x = mx * o.width / std::max(ww, 1);
    input.mouse_y = my * o.height / std::max(wh, 1);
    const bool down = glfwGetMouseButton(window, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS && !ImGui::GetIO().WantCaptureMouse;
    input.clicked = false;
    input.drag_x = input.drag_y = 0;
    if (down && !pressed) press_x = last_x = input.mouse_x, press_y = last_y = input.mouse_y, dragged = 0;
    if (down) {
      input.drag_x = input.mouse_x - last_x, input.drag_y = input.mouse_y - last_y;
      dragged += std::abs(input.drag_x) + std::abs(input.drag_y);
      last_x = input.mouse_x, last_y = input.mouse_y;
    }
    if (!down && pressed && dragged < 4) input.clicked = true;
    pressed = down;
    (void)press_x, (void)press_y;

    const std::vector<demo::View> views = frame(input, *renderer);
    input.keys.clear();
    glfwMakeContextCurrent(nullptr);
    renderer->clear();
    for (const demo::View& v : views) renderer->draw(v.scene, v.camera, v.viewport);
    image = renderer->read();
    glfwMakeContextCurrent(window);
    glBindTexture(GL_TEXTURE_2D, texture);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, image.width, image.height, 0, GL_RGBA, GL_UNSIGNED_BYTE, image.rgba.data());
    // The image as the window's background (top row first, as ImGui's UVs).
    ImGui::GetBackgroundDrawList()->AddImage(reinterpret_cast<ImTextureID>(static_cast<std::uintptr_t>(texture)), {0, 0},
                                             ImGui::GetIO().DisplaySize);
    ImGui::Render();
    int fw = 0, fh = 0;
    glfwGetFramebufferSize(window, &fw, &fh);
    glViewport(0, 0, fw, fh);
    glClearColor(1, 1, 1, 1);
    glClear(GL_COLOR_BUFFER_BIT);
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
    glfwSwapBuffers(window);
  }
  int code = 0;
  if (!o.screenshot.empty())
    if (const Status s = image.write_png(o.screenshot); !s) std::cerr << "error: " << s.error().message << "\n", code = 1;
  glDeleteTextures(1, &texture);
  ImGui_ImplOpenGL3_Shutdown();
  ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
  glfwDestroyWindow(window);
  glfwTerminate();
  return code;
}
#else
int run_window(const Options&, const char*, const std::function<std::vector<demo::View>(const Input&, render::Renderer&)>&) {
  std::cerr << "error: built without GLFW and Dear ImGui (libglfw3-dev, libimgui-dev): only --headless\n";
  return 1;
}
#endif

}  // namespace dq::apps

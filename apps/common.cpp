#include "common.hpp"

#include <algorithm>
#include <cstdio>
#include <iostream>
#include <string>
#include <vector>

#if defined(DQKIT_DEMO_WINDOW)
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <imgui.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#endif

namespace dq::apps {

namespace {
void draw(render::Renderer& renderer, const std::vector<demo::View>& views) {
  renderer.clear();
  for (const demo::View& v : views) renderer.draw(v.scene, v.camera, v.viewport);
}
}  // namespace

void add_options(CLI::App& app, Options& o) {
  CLI::Option* headless = app.add_flag("--headless", o.headless, "Render frames to PNG without a display (EGL), then exit");
  app.add_option("--frames", o.frames, "Frames to render headless")->check(CLI::Range(1, 100000));
  app.add_option("--out", o.out, "Directory for frame_0000.png ... (created)");
  app.add_flag("--force", o.force, "Headless: replace the frames already in --out (those of a longer earlier run are removed)");
  // At least 16 pixels for the demos' captions; at most the renderer's limit, as dqkit render.
  app.add_option("--width", o.width, "Image width, pixels")->check(CLI::Range(16, render::max_image_side));
  app.add_option("--height", o.height, "Image height, pixels")->check(CLI::Range(16, render::max_image_side));
  app.add_option("--quit-after", o.quit_after, "Window: close after this many frames (0: never)")
      ->check(cli::whole_number_up_to(1u << 30))
      ->excludes(headless);
  app.add_option("--screenshot", o.screenshot, "Window: write the last picture drawn (without the ImGui panel) to this PNG on exit")
      ->excludes(headless);
}

char32_t lower_case(char32_t c) { return c >= U'A' && c <= U'Z' ? c - U'A' + U'a' : c; }

bool Playback::apply(const std::u32string& typed) {
  bool restart = false;
  for (char32_t c : clicked_ + typed) {
    const char32_t key = lower_case(c);
    if (key == U' ') paused = !paused;
    if (key == U'n') ++frame, paused = true;
    if (key == U'r') frame = 0, restart = true;
  }
  clicked_.clear();
  return restart;
}

#if defined(DQKIT_DEMO_WINDOW)
void Playback::panel() {
  if (ImGui::Button(paused ? "Play" : "Pause")) clicked_ += U' ';
  ImGui::SameLine();
  if (ImGui::Button("Step")) clicked_ += U'n';
  ImGui::SameLine();
  if (ImGui::Button("Restart")) clicked_ += U'r';
  ImGui::SameLine();
  ImGui::Text("frame %d", frame);
  ImGui::TextWrapped("Keys: Space pause, N step, R restart, Esc quit.");
}
#else
void Playback::panel() {}
#endif

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
  // Frames of an earlier run: replaced only when asked, and then none of them left behind (a glob
  // of frame_*.png would otherwise mix two runs).
  std::vector<std::filesystem::path> earlier;
  for (const auto& entry : std::filesystem::directory_iterator(o.out, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.size() == 14 && name.starts_with("frame_") && name.ends_with(".png") &&
        std::all_of(name.begin() + 6, name.begin() + 10, [](char c) { return c >= '0' && c <= '9'; }))
      earlier.push_back(entry.path());
  }
  if (!earlier.empty() && !o.force) {
    std::cerr << "error: " << o.out.string() << " already holds frames of an earlier run (" << earlier.size()
              << "); they are replaced only when asked (--force), or choose another --out\n";
    return 1;
  }
  for (const auto& path : earlier) std::filesystem::remove(path, ec);
  for (int f = 0; f < o.frames; ++f) {
    draw(*renderer, views(f));
    char name[32];
    std::snprintf(name, sizeof name, "frame_%04d.png", f);
    if (const Status s = renderer->read().write_png(o.out / name); !s) {
      std::cerr << "error: " << s.error().message << "\n";
      return 1;
    }
  }
  std::cout << "wrote " << o.frames << (o.frames == 1 ? " frame to " : " frames to ") << (o.out / "frame_0000.png").string()
            << (o.frames == 1 ? "\n" : " ...\n");
  return 0;
}

#if defined(DQKIT_DEMO_WINDOW)
int run_window(const Options& o, const char* title, const std::function<std::vector<demo::View>(const render::WindowInput&)>& frame) {
  render::RenderOptions ro;
  ro.width = o.width;
  ro.height = o.height;
  auto renderer = render::Renderer::create_window(ro, title);
  if (!renderer) {
    std::cerr << "error: " << renderer.error().message << " (use --headless without a display)\n";
    return 1;
  }
  // ImGui in the renderer's window and context (current after create_window), its callbacks
  // chained to the renderer's.
  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGui::GetIO().IniFilename = nullptr;
  ImGui_ImplGlfw_InitForOpenGL(static_cast<GLFWwindow*>(renderer->native_window()), true);
  ImGui_ImplOpenGL3_Init("#version 330");
  const auto draw_imgui = [] {
    ImGui::Render();
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
  };
  bool open = true;
  for (int count = 0; open && (o.quit_after == 0 || count < o.quit_after); ++count) {
    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
    render::WindowInput input = renderer->input();
    if (ImGui::GetIO().WantCaptureMouse) input.drag_x = input.drag_y = input.wheel = 0, input.clicked = false;
    draw(*renderer, frame(input));
    open = renderer->present(draw_imgui);
  }
  int code = 0;
  if (!o.screenshot.empty())
    if (const Status s = renderer->read().write_png(o.screenshot); !s) std::cerr << "error: " << s.error().message << "\n", code = 1;
  ImGui_ImplOpenGL3_Shutdown();
  ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
  return code;
}
#else
int run_window(const Options&, const char*, const std::function<std::vector<demo::View>(const render::WindowInput&)>&) {
  std::cerr << "error: built without GLFW and Dear ImGui (libglfw3-dev, libimgui-dev): only --headless\n";
  return 1;
}
#endif

}  // namespace dq::apps

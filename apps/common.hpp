// What the three demo programs share: their command line, the headless run (frames to PNG through
// dqkit::render), and the interactive window (GLFW + Dear ImGui) that shows the same renderer's
// image as a texture, with ImGui controls beside it.
#pragma once

#include <CLI/CLI.hpp>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "dq/demo/scenes.hpp"

namespace dq::apps {

struct Options {
  bool headless = false;
  int frames = 60;
  std::filesystem::path out = "frames";
  int width = 800, height = 600;
  int quit_after = 0;  ///< interactive: close after this many frames (0: never), for scripted tests
  std::filesystem::path screenshot;  ///< interactive: write the last shown image here on exit
};

/// Adds --headless, --frames, --out, --width, --height, --quit-after, --screenshot.
void add_options(CLI::App& app, Options& options);

/// Renders frames 0 … frames − 1 of `views(frame)` to out/frame_0000.png …; prints where they are.
/// Returns the process's exit code (errors printed).
int run_headless(const Options& options, const std::function<std::vector<demo::View>(int frame)>& views);

/// Input of one window frame: the mouse in image pixels, and what happened since the last frame.
struct Input {
  double mouse_x = 0, mouse_y = 0;
  bool clicked = false;             ///< left button released without a drag
  double drag_x = 0, drag_y = 0;    ///< left-button drag, pixels
  std::vector<int> keys;            ///< GLFW key codes pressed
};

/// A window showing the renderer's image, with an ImGui panel. `frame` is called once per window
/// frame with the input; it draws with the renderer and its ImGui widgets (between NewFrame and
/// Render, which the window calls). Returns the exit code.
int run_window(const Options& options, const char* title,
               const std::function<std::vector<demo::View>(const Input& input, render::Renderer& renderer)>& frame);

}  // namespace dq::apps

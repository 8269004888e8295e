// What the three demo programs share: their command line, the headless run (frames to PNG through
// dqkit::render), and the interactive window: the renderer's own window (Renderer::create_window)
// with Dear ImGui drawn over the image in the same OpenGL context.
#pragma once

#include <CLI/CLI.hpp>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "cli_validators.hpp"
#include "dq/demo/scenes.hpp"

namespace dq::apps {

struct Options {
  bool headless = false;
  int frames = 60;
  std::filesystem::path out = "frames";
  int width = 800, height = 600;
  int quit_after = 0;  ///< interactive: close after this many frames (0: never), for scripted tests
  std::filesystem::path screenshot;  ///< interactive: write the last image drawn (without ImGui) here on exit
  bool force = false;                ///< headless: replace the frames of an earlier run in `out`
};

/// Adds --headless, --frames, --out, --force, --width, --height, --quit-after, --screenshot.
void add_options(CLI::App& app, Options& options);

/// Renders frames 0 … frames − 1 of `views(frame)` to out/frame_0000.png …; prints where they are.
/// Returns the process's exit code (errors printed).
int run_headless(const Options& options, const std::function<std::vector<demo::View>(int frame)>& views);

/// The renderer's window with Dear ImGui over the image. `frame` is called once per window frame
/// with what the user did during the previous one (mouse input over an ImGui window removed); it
/// makes its ImGui widgets (the window calls NewFrame before and renders them over the image after)
/// and returns the views to draw. Closes on Escape, when the window is closed, or after
/// options.quit_after frames. Returns the exit code (errors printed).
int run_window(const Options& options, const char* title,
               const std::function<std::vector<demo::View>(const render::WindowInput& input)>& frame);

/// A Latin capital letter as lower case; other characters unchanged.
char32_t lower_case(char32_t c);

/// The frame an animated demo shows in a window: it advances by one per window frame unless
/// paused. Keys: Space pauses and resumes, N steps one frame forward (and pauses), R goes back to
/// frame 0; the same as buttons in panel().
struct Playback {
  int frame = 0;
  bool paused = false;
  /// Applies typed keys (and the buttons of the last panel()); true if the demo restarts at 0.
  bool apply(const std::u32string& typed);
  /// Buttons and the frame number, in the current ImGui window.
  void panel();
  void advance() {
    if (!paused) ++frame;
  }

 private:
  std::u32string clicked_;  ///< the keys of the buttons clicked in panel()
};

}  // namespace dq::apps

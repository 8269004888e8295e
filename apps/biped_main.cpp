// dqkit-biped: the 16-link biped of the Kenwright paper (§10) reaching for a moving 6-DOF target
// with inverse kinematics, by dual quaternions and by matrices side by side.
#include <cmath>
#include <optional>

#include "common.hpp"

#if defined(DQKIT_DEMO_WINDOW)
#include <imgui.h>
#endif

using namespace dq;

int main(int argc, char** argv) {
  CLI::App app{"dqkit-biped: the Kenwright biped's right hand following a moving 6-DOF target by IK (dual quaternions | matrices)"};
  apps::Options o;
  o.width = 1000;
  apps::add_options(app, o);
  double fps = 30;
  app.add_option("--fps", fps, "Frames per second of the target's motion")->check(cli::finite_in(0, 1000));
  CLI11_PARSE(app, argc, argv);
  std::optional<demo::BipedDemo> demo(std::in_place);
  if (o.headless) {
    return apps::run_headless(o, [&](int f) {
      demo->step(f / fps);
      return demo->views(o.width, o.height);
    });
  }
  // The solvers are warm-started from the previous frame: each frame is solved once, in order, and
  // a restart starts them afresh.
  apps::Playback playback;
  int solved = -1;
  return apps::run_window(o, "dqkit-biped", [&](const render::WindowInput& in) {
    if (playback.apply(in.typed)) demo.emplace(), solved = -1;
    for (; solved < playback.frame; ++solved) demo->step((solved + 1) / fps);
#if defined(DQKIT_DEMO_WINDOW)
    // Between the two figures, below the labels.
    ImGui::SetNextWindowPos({float(o.width) * 0.5f, float(o.height) * 0.17f}, ImGuiCond_Once, {0.5f, 0});
    ImGui::SetNextWindowSize({float(o.width) * 0.26f, 0}, ImGuiCond_Once);
    ImGui::Begin("IK: dual quaternions | matrices");
    playback.panel();
    ImGui::TextColored({0.9f, 0.3f, 0.3f, 1}, "red: ideal");
    ImGui::SameLine();
    ImGui::TextColored({0.2f, 0.75f, 0.2f, 1}, "green: computed");
    ImGui::TextUnformatted("left: dual quaternions\nright: matrices");
    for (bool matrices : {false, true}) {
      const std::vector<double>& e = demo->errors(matrices);
      std::vector<float> log_errors;
      const std::size_t first = e.size() > 150 ? e.size() - 150 : 0;
      for (std::size_t i = first; i < e.size(); ++i) log_errors.push_back(float(std::log10(std::max(e[i], 1e-16))));
      const char* name = matrices ? "matrices" : "dual quaternions";
      ImGui::Text("%s: error %.1e m,\nsolved in %.0f us", name, e.empty() ? 0.0 : e.back(),
                  demo->solve_times(matrices).empty() ? 0.0 : demo->solve_times(matrices).back());
      ImGui::SetNextItemWidth(-1);  // the panel's width
      ImGui::PlotLines(matrices ? "##matrices" : "##dual", log_errors.data(), int(log_errors.size()), 0, "log10 error", -16, 0,
                       {0, 40});
    }
    ImGui::End();
#endif
    auto views = demo->views(o.width, o.height);
    playback.advance();
    return views;
  });
}

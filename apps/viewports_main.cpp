// dqkit-viewports: the four viewports of the Arends thesis (chapter 6 and appendix): a vector moved
// by a rotation matrix, a quaternion with SLERP, a dual quaternion and a hyper-dual quaternion.
#include "common.hpp"

#if defined(DQKIT_DEMO_WINDOW)
#include <imgui.h>
#endif

using namespace dq;

int main(int argc, char** argv) {
  CLI::App app{"dqkit-viewports: the Arends thesis' four viewports (matrix, quaternion with SLERP, dual and hyper-dual quaternion)"};
  apps::Options o;
  o.width = o.height = 800;
  apps::add_options(app, o);
  CLI11_PARSE(app, argc, argv);
  if (o.headless) {
    return apps::run_headless(o, [&](int f) {
      const demo::ViewportsState s = demo::viewports_state(f);
      const auto ns = demo::time_methods(s);
      return demo::viewports_views(s, &ns, o.width, o.height);
    });
  }
  apps::Playback playback;
  int timed = -1;  // the frame whose methods were timed: a paused picture stays still
  std::array<double, demo::method_count> ns{};
  return apps::run_window(o, "dqkit-viewports", [&](const render::WindowInput& in) {
    playback.apply(in.typed);
    const demo::ViewportsState s = demo::viewports_state(playback.frame);
    if (timed != playback.frame) ns = demo::time_methods(s), timed = playback.frame;
#if defined(DQKIT_DEMO_WINDOW)
    // Between the upper two vectors, which stay within 0.4 of their viewports' half-width.
    ImGui::SetNextWindowPos({float(o.width) * 0.5f, float(o.height) * 0.09f}, ImGuiCond_Once, {0.5f, 0});
    ImGui::SetNextWindowSize({float(o.width) * 0.27f, 0}, ImGuiCond_Once);
    ImGui::Begin("Four viewports");
    playback.panel();
    ImGui::Separator();
    ImGui::TextUnformatted("Time per frame:");
    static constexpr const char* short_names[demo::method_count] = {"matrix", "quaternion", "dual", "hyper-dual"};
    for (int m = 0; m < demo::method_count; ++m) {
      const render::Color c = demo::method_color(static_cast<demo::Method>(m));
      ImGui::TextColored({c.r, c.g, c.b, 1}, "%-10s %5.1f ns", short_names[m], ns[std::size_t(m)]);
    }
    if (ImGui::CollapsingHeader("The thesis' claims")) {
      ImGui::TextWrapped(
          "SLERP's failure cases: the thesis' formula divides by sin(omega) = 0 for q and q (omega = 0) and for q "
          "and -q (omega = pi); dqkit's slerp keeps norm 1 in both (the notes in the lower left viewport).");
      ImGui::TextWrapped(
          "Gimbal lock: glRotatef(90, z) then glRotatef(45, y) leaves (0, 1, 0) where the first rotation puts it "
          "because the vector lies on the second rotation's axis, not because of gimbal lock.");
    }
    ImGui::End();
#endif
    auto views = demo::viewports_views(s, &ns, o.width, o.height);
    playback.advance();
    return views;
  });
}

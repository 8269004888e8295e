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
  o.width = o.height = 700;
  apps::add_options(app, o);
  CLI11_PARSE(app, argc, argv);
  auto views = [&](int f) {
    const demo::ViewportsState s = demo::viewports_state(f);
    const auto ns = demo::time_methods(s);
    return demo::viewports_views(s, &ns, o.width, o.height);
  };
  if (o.headless) return apps::run_headless(o, views);
  int frame = 0;
  return apps::run_window(o, "dqkit-viewports", [&](const apps::Input&, render::Renderer&) { return views(frame++); });
}

// dqkit-biped: the 16-link biped of the Kenwright paper (§10) reaching for a moving 6-DOF target
// with inverse kinematics, by dual quaternions and by matrices side by side.
#include "common.hpp"

using namespace dq;

int main(int argc, char** argv) {
  CLI::App app{"dqkit-biped: the Kenwright biped's right hand following a moving 6-DOF target by IK (dual quaternions | matrices)"};
  apps::Options o;
  o.width = 1000;
  apps::add_options(app, o);
  double fps = 30;
  app.add_option("--fps", fps, "Frames per second of the target's motion")->check(CLI::PositiveNumber);
  CLI11_PARSE(app, argc, argv);
  demo::BipedDemo demo;
  auto views = [&](int f) {
    demo.step(f / fps);
    return demo.views(o.width, o.height);
  };
  if (o.headless) return apps::run_headless(o, views);
  int frame = 0;
  return apps::run_window(o, "dqkit-biped", [&](const apps::Input&, render::Renderer&) { return views(frame++); });
}

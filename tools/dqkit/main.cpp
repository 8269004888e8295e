// dqkit: inspect motion files, compute forward kinematics, convert formats.
// The only place that touches argv and exit codes.
#include "app.hpp"

int main(int argc, char** argv) {
  dq::cli::Arguments args;
  const auto app = dq::cli::make_app(args);
  try {
    app->parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app->exit(e);
  }
  return dq::cli::run_command(args);
}

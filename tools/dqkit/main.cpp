// dqkit: inspect motion files, compute forward kinematics, convert formats.
// The only place that touches argv and exit codes (through run_tool, which catches everything).
#include "app.hpp"

int main(int argc, char** argv) { return dq::cli::run_tool(argc, argv); }

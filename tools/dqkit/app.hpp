// The dqkit command line: its definition (CLI11, from the command table in commands.hpp), shared
// by main() and the argument fuzzer.
#pragma once

#include <CLI/CLI.hpp>
#include <memory>
#include <utility>
#include <vector>

#include "commands.hpp"

namespace dq::cli {

struct Arguments {
  std::vector<std::pair<CLI::App*, Runner>> commands;  ///< each subcommand and what runs it
};

/// Builds the parser; options are stored in the runners kept in `args`.
std::unique_ptr<CLI::App> make_app(Arguments& args);

/// Runs the parsed command (after app.parse succeeded); throws Failure and other exceptions.
int run_command(const Arguments& args);

/// The whole tool: parses argv, runs the command, turns every exception into "dqkit: <what>" on
/// standard error and exit code 1 (CLI11's usage errors keep CLI11's codes).
int run_tool(int argc, char** argv);

}  // namespace dq::cli

// The commands of the dqkit tool, in ONE table (commands.cpp). Each command lives in its own file
// (info.cpp, fk.cpp, convert.cpp, ...) and provides a `define_<name>` function: it adds the
// command's options to its CLI11 subcommand and returns what runs it (with the parsed options).
//
// To add a command (skin, render, fix-feet, ...): write tools/dqkit/<name>.cpp with
//   dq::cli::Runner dq::cli::define_<name>(CLI::App& command) { ... }
// declare it below, add one line to kCommands in commands.cpp, and the file to tools/CMakeLists.txt
// (dqkit_cli_commands). Helpers for inputs, outputs, CSV/JSON and errors: common.hpp.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <span>
#include <string_view>

namespace dq::cli {

/// Runs a parsed command; returns the exit code (errors: throw Failure, see common.hpp).
using Runner = std::function<int()>;

struct Command {
  std::string_view name;
  std::string_view description;
  Runner (*define)(CLI::App& command);
};

/// Every command, in the order `dqkit --help` lists them.
std::span<const Command> commands();

Runner define_info(CLI::App& command);
Runner define_fk(CLI::App& command);
Runner define_convert(CLI::App& command);
Runner define_skin(CLI::App& command);    // skin.cpp (with dqkit::skin and dqkit::import)
Runner define_render(CLI::App& command);  // render.cpp (with dqkit::render as well)
#if defined(DQKIT_HAVE_IK)
Runner define_fix_feet(CLI::App& command);
#endif

}  // namespace dq::cli

// The dqkit command line: its definition (CLI11), shared by main() and the argument fuzzer.
#pragma once

#include <CLI/CLI.hpp>
#include <memory>

#include "commands.hpp"

namespace dq::cli {

struct Arguments {
  InfoArgs info;
  FkArgs fk;
  ConvertArgs convert;
  CLI::App* info_cmd = nullptr;
  CLI::App* fk_cmd = nullptr;
  CLI::App* convert_cmd = nullptr;
};

/// Builds the parser; options are stored into `args`.
std::unique_ptr<CLI::App> make_app(Arguments& args);

/// Runs the parsed command (after app.parse succeeded).
int run_command(const Arguments& args);

}  // namespace dq::cli

// Fuzz target: the command-line tool. Three parts per input:
//  - dqkit's frame selection parser (--frames: numbers and Python slices), which must return
//    values in range or a message, never both;
//  - the same bytes as an argument vector (NUL-separated) to the whole CLI11 parser (never run);
//  - the same bytes as a motion file run through every command (info text and JSON, fk CSV and
//    JSON in world and local space with every rotation form, convert), output to a file: a command
//    either succeeds or reports a Failure (the "dqkit: ..." exit 1); any other exception escaping a
//    command (e.g. a JSON library refusing a name) is a crash, as it would abort the tool.
// Run under a memory limit (scripts/fuzz.sh), so output built in memory or declared counts
// trusted for allocation are found too.
#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "../tools/dqkit/app.hpp"
#include "../tools/dqkit/common.hpp"
#include "check.hpp"

using dq::fuzz::check;

namespace {

void parse_arguments(const std::string& text) {
  std::vector<std::string> args{"dqkit"};
  std::string current;
  for (char c : text) {
    if (c == '\0') {
      args.push_back(current);
      current.clear();
    } else {
      current += c;
    }
  }
  args.push_back(current);
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  dq::cli::Arguments parsed;
  const auto app = dq::cli::make_app(parsed);
  try {
    app->parse(static_cast<int>(argv.size()), argv.data());
  } catch (const CLI::Error&) {
    // a usage error: fine (the tool prints it and exits non-zero)
  }
}

void run_commands(const std::string& text, unsigned variant) {
  static const std::filesystem::path dir = [] {
    auto d = std::filesystem::temp_directory_path() / ("dqkit_fuzz_cli_" + std::to_string(::getpid()));
    std::filesystem::create_directories(d);
    return d;
  }();
  const std::string in = (dir / "in.bvh").string(), out = (dir / "out").string();
  std::ofstream(in, std::ios::binary | std::ios::trunc) << text;
  static const std::vector<std::vector<std::string>> commands = {
      {"info", in, "--format", "json", "-o", out + ".json"},
      {"info", in, "-o", out + ".txt"},
      {"fk", in, "--all", "--format", "json", "-o", out + ".json"},
      {"fk", in, "--all", "--time", "--parents", "-o", out + ".csv"},
      {"fk", in, "--frames", "::2,-1", "--space", "local", "--rotation", "euler", "--degrees", "-o", out + ".csv"},
      {"fk", in, "--all", "--rotation", "matrix", "--format", "json", "--scale", "0.01", "-o", out + ".json"},
      {"convert", in, out + ".bvh", "--rotation-order", "XZY"},
      {"convert", in, out + ".bvh", "--rate", "7"},
  };
  std::vector<std::string> args = commands[variant % commands.size()];
  args.insert(args.begin(), "dqkit");
  args.push_back("--force");
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  dq::cli::Arguments parsed;
  const auto app = dq::cli::make_app(parsed);
  app->parse(static_cast<int>(argv.size()), argv.data());  // fixed arguments: always valid
  try {
    check(dq::cli::run_command(parsed) == 0, "a command that does not fail succeeds");
  } catch (const dq::cli::Failure&) {
    // a clear error for the user
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 2) return 0;
  const std::size_t count = data[0] * 256u + data[1];
  const std::string text(reinterpret_cast<const char*>(data + 2), size - 2);
  std::string error;
  const auto frames = dq::cli::parse_frame_list(text, count, error, 1u << 20);
  if (error.empty()) {
    for (std::size_t f : frames) check(f < count, "frame numbers in range");
  } else {
    check(frames.empty(), "no frames with an error");
  }
  parse_arguments(text);
  run_commands(text, data[0]);
  return 0;
}

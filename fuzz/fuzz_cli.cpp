// Fuzz target: the command-line tool. Three parts per input:
//  - dqkit's frame selection parser (--frames: numbers and Python slices), which must return
//    values in range or a message, never both;
//  - the same bytes as an argument vector (NUL-separated) to the whole CLI11 parser (never run);
//  - the same bytes as a motion file run through every command (info text and JSON, fk CSV and
//    JSON in world and local space with every rotation form, convert), output to standard output
//    (sent to /dev/null): a command
//    either succeeds or reports a Failure (the "dqkit: ..." exit 1); any other exception escaping a
//    command (e.g. a JSON library refusing a name) is a crash, as it would abort the tool.
// Run under a memory limit (scripts/fuzz.sh), so output built in memory or declared counts
// trusted for allocation are found too.
#include <fcntl.h>
#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>
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
  // Output goes to standard output, sent to /dev/null once (a file per input would be fsynced:
  // slow). The safe file writing has its own tests. The input file's folder is removed at exit
  // (libFuzzer ends a time-bounded run with exit()).
  struct ScratchFolder {
    std::filesystem::path path;
    ~ScratchFolder() {
      std::error_code ignored;
      std::filesystem::remove_all(path, ignored);
    }
  };
  static const ScratchFolder dir = [] {
    auto d = std::filesystem::temp_directory_path() / ("dqkit_fuzz_cli_" + std::to_string(::getpid()));
    std::filesystem::create_directories(d);
    const int null = ::open("/dev/null", O_WRONLY);
    ::dup2(null, STDOUT_FILENO);
    ::close(null);
    return ScratchFolder{d};
  }();
  const std::string in = (dir.path / "in.bvh").string();
  std::ofstream(in, std::ios::binary | std::ios::trunc) << text;
  static const std::vector<std::vector<std::string>> commands = {
      {"info", in, "--format", "json"},
      {"info", in},
      {"fk", in, "--all", "--format", "json"},
      {"fk", in, "--all", "--time", "--parents"},
      {"fk", in, "--frames", "::2,-1", "--space", "local", "--rotation", "euler", "--degrees"},
      {"fk", in, "--all", "--rotation", "matrix", "--format", "json", "--scale", "0.01"},
      {"convert", in, "-", "--rotation-order", "XZY"},
      {"convert", in, "-", "--rate", "7"},
  };
  std::vector<std::string> args = commands[variant % commands.size()];
  args.insert(args.begin(), "dqkit");
  args.push_back("--memory-limit");  // the fuzzer's own limit is 512 MB per allocation
  args.push_back("64");
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

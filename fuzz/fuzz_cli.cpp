// Fuzz target: the command-line tool's argument parsing (CLI11 with dqkit's options, arguments
// separated by NUL bytes in the input; parsed, never run) and its own number and list parsing
// (--frames), which must return values in range or a message, never both, and never crash.
#include <cstdint>
#include <string>
#include <vector>

#include "../tools/dqkit/app.hpp"
#include "check.hpp"

using dq::fuzz::check;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 2) return 0;
  const std::size_t count = data[0] * 256u + data[1];
  const std::string text(reinterpret_cast<const char*>(data + 2), size - 2);
  std::string error;
  const auto frames = dq::cli::parse_frame_list(text, count, error);
  if (error.empty()) {
    for (std::size_t f : frames) check(f < count, "frame numbers in range");
  } else {
    check(frames.empty(), "no frames with an error");
  }
  // The same bytes as an argument vector.
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
  return 0;
}

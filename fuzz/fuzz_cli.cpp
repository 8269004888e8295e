// Fuzz target: the command-line tool's own parsing of numbers and lists (--frames), which must
// either return values in range or a message, and never crash.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "../tools/dqkit/commands.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 2) return 0;
  const std::size_t count = data[0] * 256u + data[1];
  const std::string text(reinterpret_cast<const char*>(data + 2), size - 2);
  std::string error;
  const auto frames = dq::cli::parse_frame_list(text, count, error);
  if (error.empty()) {
    for (std::size_t f : frames)
      if (f >= count) std::abort();
  } else if (!frames.empty()) {
    std::abort();
  }
  return 0;
}

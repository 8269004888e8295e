// What every dqkit command shares: reading the input (a file or `-`), writing the output (standard
// output or a file, safely), numbers, CSV and JSON text, frame selections, progress, and errors.
// Commands report errors by throwing Failure; main() turns every exception into "dqkit: <what>"
// and exit code 1.
#pragma once

#include <CLI/CLI.hpp>
#include <chrono>
#include <cstddef>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "../cli_validators.hpp"
#include "dq/io/file.hpp"
#include "dq/io/motion.hpp"

namespace dq::cli {

/// An error for the user: main() prints "dqkit: <what>" and exits with 1.
struct Failure : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Prints "dqkit: warning: ..." lines.
void print_warnings(const std::vector<std::string>& warnings);

/// The options of every command that reads a motion file.
struct InputOptions {
  std::string file;  ///< a path, or "-" for standard input (BVH)
  std::size_t animation = 0;
  double rate = 0;  ///< 0: the file's own (BVH) or 30 Hz (imported)
  double import_timeout = 120;
  std::size_t memory_limit_mb = 4096;  ///< MotionOptions::memory_limit_mb
  bool lights_and_cameras = false;
};
/// Adds `file`, --animation, --rate, --import-timeout, --memory-limit and --lights-and-cameras to a command.
void add_input_options(CLI::App& command, InputOptions& options, const std::string& option_name = "file");
/// Adds --lights-and-cameras (ImportOptions::lights_and_cameras).
void add_lights_and_cameras_option(CLI::App& command, bool& keep);
/// Loads the input (warnings printed); throws Failure.
Motion load(const InputOptions& options);

/// A file name: not empty ('-' names standard input or output).
CLI::Validator file_name();
/// An animation number: 0, 1, ...
CLI::Validator animation_index();

/// Where a command writes: standard output ("-" or empty) or a file written safely (OutputFile:
/// created exclusively, or with `force` replacing only a regular file; never one of `inputs`,
/// also through links). Text is buffered; every write error is a Failure, also on standard output.
class Output {
 public:
  Output(const std::string& path, bool force, const std::vector<std::string>& inputs);
  void write(std::string_view text);
  /// Completes the output (renames the file into place); without it, nothing is left behind.
  void finish();

 private:
  void flush_stdout();
  std::optional<OutputFile> file_;
  std::string buffer_;
};

/// "-" or empty: standard output.
bool is_stdout(const std::string& path);

/// Text as the terminal gets it: control characters (an escape sequence in a joint's name would
/// reach the terminal) as '?'; UTF-8 kept. For the text report, warnings and errors.
std::string printable(std::string_view text);

/// Adds --format FORMAT (one of `formats`, the first the default) and returns the function that
/// gives the format to write to `output`: --format when given, else the output name's extension
/// when it names one (out.json: json; .txt: text), else the default. --format naming another of
/// them than the extension is an error (--format csv -o out.json).
std::function<std::string(const std::string& output)> add_format_option(CLI::App& command, const std::vector<std::string>& formats,
                                                                        const std::string& help);

/// Shortest text that reads back as the same double ("%.17g" digits, via to_chars).
void append_number(std::string& out, double v);
/// append_number for a JSON value that may be beyond double's range (a rate of 1 ÷ a denormal frame
/// time): null where it is not finite, as JSON has no ∞ or NaN.
void append_json_number_or_null(std::string& out, double v);
/// A CSV field (RFC 4180): quoted, with quotes doubled, when it holds a comma, quote, CR or LF.
void append_csv_field(std::string& out, std::string_view field);
/// A JSON string literal; bytes that are not UTF-8 become U+FFFD (the readers give UTF-8 names).
void append_json_string(std::string& out, std::string_view s);

/// "1 frame", "2 frames".
std::string count_text(std::size_t n, std::string_view singular, std::string_view plural);

/// Parses a frame selection below `count`: a comma-separated list of numbers and Python slices
/// (start:stop[:step], stop exclusive, negative values from the end, omitted parts default), in
/// the order given. Numbers out of range are errors; slices are clipped as in Python. The error
/// says which item is wrong. The result never has more than `max_frames` entries (error beyond).
std::vector<std::size_t> parse_frame_list(const std::string& text, std::size_t count, std::string& error,
                                          std::size_t max_frames = std::size_t{1} << 26);

/// "frame N/M" on standard error, at most 5 times a second, only when standard error is a terminal.
class Progress {
 public:
  Progress(std::string label, std::size_t total);
  ~Progress();
  void update(std::size_t done);

 private:
  std::string label_;
  std::size_t total_;
  bool enabled_;
  std::chrono::steady_clock::time_point next_;
};

}  // namespace dq::cli

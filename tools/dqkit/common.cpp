#include "common.hpp"

#include "dq/io/utf8.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <charconv>
#include <limits>
#include <cmath>
#include <cstdio>
#include <cstring>

#ifdef DQKIT_HAVE_IMPORT
#include "dq/io/scene.hpp"
#endif

namespace dq::cli {

void print_warnings(const std::vector<std::string>& warnings) {
  for (const std::string& w : warnings) std::fprintf(stderr, "dqkit: warning: %s\n", printable(w).c_str());
}

std::string printable(std::string_view text) {
  std::string out(text);
  for (char& c : out)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = '?';
  return out;
}

CLI::Validator animation_index() { return whole_number_up_to(std::numeric_limits<std::size_t>::max(), "an animation number", "INDEX"); }

CLI::Validator file_name() {
  return CLI::Validator([](std::string& text) -> std::string { return text.empty() ? "an empty file name ('-' is standard input or output)" : ""; },
                        "FILE");
}

void add_input_options(CLI::App& c, InputOptions& o, const std::string& option_name) {
  c.add_option(option_name, o.file, "Motion file: BVH (recognized by content or a .bvh name), glTF, FBX, Collada, X, IQM, ...; - for standard input (BVH)")
      ->required()
      ->check(file_name());
  c.add_option("--animation", o.animation, "Which animation of a multi-animation file (from 0)")->check(animation_index());
  c.add_option("--rate", o.rate, "Frames per second: resample the animation at frames f / RATE; the last one, at or up to one frame past the "
                 "end, holds the clip's last pose (default: the file's own; imported clips 30)")
      ->check(finite_in(0, 1000));
  c.add_option("--import-timeout", o.import_timeout, "Seconds before the importer (a separate process) is abandoned")
      ->check(finite_in(0, 86400));
  c.add_option("--memory-limit", o.memory_limit_mb, "MB the animation may take (frames x joints x 64 bytes; default 4096)")
      ->check(whole_number_up_to(std::size_t{1} << 30, "a whole number of megabytes", "MB", 1));
  add_lights_and_cameras_option(c, o.lights_and_cameras);
}

void add_lights_and_cameras_option(CLI::App& c, bool& keep) {
  c.add_flag("--lights-and-cameras", keep, "Keep an imported file's light and camera nodes (leaves without meshes) as joints");
}

bool is_stdout(const std::string& path) { return path.empty() || path == "-"; }

std::function<std::string(const std::string& output)> add_format_option(CLI::App& command, const std::vector<std::string>& formats,
                                                                        const std::string& help) {
  auto value = std::make_shared<std::string>(formats.front());
  CLI::Option* option = command.add_option("--format", *value, help + " (default: from the output's extension, else " + formats.front() + ")")
                            ->check(CLI::IsMember(formats));
  return [value, option, formats](const std::string& output) {
    std::string named;  // the format the output's extension names, if any
    if (!is_stdout(output)) {
      std::string extension = lowercase_extension(output);
      if (!extension.empty()) extension.erase(0, 1);
      if (extension == "txt") extension = "text";
      if (std::find(formats.begin(), formats.end(), extension) != formats.end()) named = extension;
    }
    if (option->count() == 0) return named.empty() ? *value : named;
    if (!named.empty() && named != *value)
      throw Failure("--format " + *value + ", but the output " + output + " is named as " + named + " (give the name its format's extension)");
    return *value;
  };
}

namespace {
std::string read_stdin() {
  std::string text;
  std::array<char, 1 << 16> buf{};
  while (true) {
    const ssize_t n = ::read(STDIN_FILENO, buf.data(), buf.size());
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) throw Failure("standard input: read error: " + std::string(std::strerror(errno)));
    if (n == 0) return text;
    text.append(buf.data(), static_cast<std::size_t>(n));
    if (text.size() > BvhLimits::max_file_bytes)
      throw Failure("standard input: more than the " + std::to_string(BvhLimits::max_file_bytes) + " bytes a BVH file may have");
  }
}
}  // namespace

Motion load(const InputOptions& o) {
  MotionOptions options;
  options.animation = o.animation;
  options.import_timeout = o.import_timeout;
  options.sample_rate = o.rate;
  options.memory_limit_mb = o.memory_limit_mb;
  options.lights_and_cameras = o.lights_and_cameras;
  Expected<Motion> m = [&]() -> Expected<Motion> {
    if (o.file == "-") {
      const std::string text = read_stdin();
      if (!looks_like_bvh(text))
        return Error{"standard input: not BVH (only BVH is read from standard input; give other formats as a file)"};
      return read_motion(text, "<stdin>", options);
    }
#ifdef DQKIT_HAVE_IMPORT
    return import_motion(o.file, options);
#else
    return load_motion(o.file, options);
#endif
  }();
  if (!m) throw Failure(m.error().message);
  print_warnings(m->warnings);
  return std::move(*m);
}

Output::Output(const std::string& path, bool force, const std::vector<std::string>& inputs) {
  if (is_stdout(path)) return;
  struct stat out {};
  if (::stat(path.c_str(), &out) == 0)  // follows links: a link to the input is the input
    for (const std::string& input : inputs) {
      struct stat in {};
      if (input != "-" && ::stat(input.c_str(), &in) == 0 && in.st_dev == out.st_dev && in.st_ino == out.st_ino)
        throw Failure(path + ": is the input file; write to another file");
    }
  Expected<OutputFile> f = OutputFile::create(path, force ? Overwrite::allow : Overwrite::refuse);
  if (!f) throw Failure(f.error().message);
  file_.emplace(std::move(*f));
}

void Output::flush_stdout() {
  std::size_t done = 0;
  while (done < buffer_.size()) {
    const ssize_t n = ::write(STDOUT_FILENO, buffer_.data() + done, buffer_.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) throw Failure("standard output: write failed: " + std::string(std::strerror(errno)));
    done += static_cast<std::size_t>(n);
  }
  buffer_.clear();
}

void Output::write(std::string_view text) {
  if (file_) {
    if (Status s = file_->write(text); !s) throw Failure(s.error().message);
    return;
  }
  buffer_.append(text);
  if (buffer_.size() >= (1u << 16)) flush_stdout();
}

void Output::finish() {
  if (file_) {
    if (Status s = file_->commit(); !s) throw Failure(s.error().message);
    return;
  }
  flush_stdout();
}

void append_number(std::string& out, double v) {
  std::array<char, 32> buf{};
  const auto r = std::to_chars(buf.data(), buf.data() + buf.size(), v, std::chars_format::general, 17);
  out.append(buf.data(), r.ptr);
}

void append_json_number_or_null(std::string& out, double v) {
  if (std::isfinite(v)) {
    append_number(out, v);
  } else {
    out += "null";
  }
}

void append_csv_field(std::string& out, std::string_view field) {
  if (field.find_first_of(",\"\r\n") == std::string_view::npos) {
    out += field;
    return;
  }
  out += '"';
  for (char c : field) {
    if (c == '"') out += '"';
    out += c;
  }
  out += '"';
}

void append_json_string(std::string& out, std::string_view s) {
  static constexpr char hex[] = "0123456789abcdef";
  out += '"';
  std::size_t i = 0;
  while (i < s.size()) {
    const auto c = static_cast<unsigned char>(s[i]);
    if (c < 0x80) {
      if (c == '"' || c == '\\') {
        out += '\\';
        out += static_cast<char>(c);
      } else if (c < 0x20 || c == 0x7f) {
        out += "\\u00";
        out += hex[c >> 4];
        out += hex[c & 15];
      } else {
        out += static_cast<char>(c);
      }
      ++i;
      continue;
    }
    const std::size_t n = utf8_sequence_length(s, i);  // a well-formed sequence is copied, a stray byte is U+FFFD
    out += n ? s.substr(i, n) : std::string_view("\xEF\xBF\xBD");
    i += n ? n : 1;
  }
  out += '"';
}

std::string count_text(std::size_t n, std::string_view singular, std::string_view plural) {
  return std::to_string(n) + " " + std::string(n == 1 ? singular : plural);
}

namespace {
std::optional<long long> parse_integer(std::string_view s) {
  long long v = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (s.empty() || ec != std::errc() || end != s.data() + s.size()) return std::nullopt;
  return v;
}
std::string_view trim(std::string_view s) {
  while (!s.empty() && s.front() == ' ') s.remove_prefix(1);
  while (!s.empty() && s.back() == ' ') s.remove_suffix(1);
  return s;
}
}  // namespace

std::vector<std::size_t> parse_frame_list(const std::string& text, std::size_t count, std::string& error, std::size_t max_frames) {
  std::vector<std::size_t> out;
  auto fail = [&](std::string what) {
    error = "--frames: " + std::move(what);
    return std::vector<std::size_t>{};
  };
  if (trim(text).empty()) return fail("empty (give frame numbers and slices, e.g. 0,10:20,::5)");
  const auto n = static_cast<long long>(count);
  const std::string range = "(the file has " + count_text(count, "frame", "frames") + ", numbered from 0)";
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t comma = std::min(text.find(',', start), text.size());
    const std::string_view item = trim(std::string_view(text).substr(start, comma - start));
    start = comma + 1;
    if (item.find(':') == std::string_view::npos) {
      const auto v = parse_integer(item);
      if (!v) return fail("'" + std::string(item) + "' is not a frame number or a slice (start:stop:step)");
      const long long f = *v < 0 ? *v + n : *v;
      if (f < 0 || f >= n) return fail("frame " + std::string(item) + " out of range " + range);
      if (out.size() >= max_frames) return fail("more than " + std::to_string(max_frames) + " frames selected");
      out.push_back(static_cast<std::size_t>(f));
      continue;
    }
    // A slice, with Python's meaning (slice.indices).
    std::array<std::optional<long long>, 3> part;
    std::size_t parts = 0, from = 0;
    while (true) {
      const std::size_t colon = std::min(item.find(':', from), item.size());
      if (parts == 3) return fail("'" + std::string(item) + "' is not a slice (start:stop:step)");
      const std::string_view p = trim(item.substr(from, colon - from));
      if (!p.empty()) {
        part[parts] = parse_integer(p);
        if (!part[parts]) return fail("'" + std::string(item) + "': '" + std::string(p) + "' is not an integer");
      }
      ++parts;
      if (colon == item.size()) break;
      from = colon + 1;
    }
    const long long step = part[2].value_or(1);
    if (step == 0) return fail("'" + std::string(item) + "': the step of a slice cannot be zero");
    auto bound = [&](std::optional<long long> v, long long fallback) {
      if (!v) return fallback;
      long long x = *v < 0 ? *v + n : *v;
      return step > 0 ? std::clamp(x, 0LL, n) : std::clamp(x, -1LL, n - 1);
    };
    const long long first = bound(part[0], step > 0 ? 0 : n - 1), stop = bound(part[1], step > 0 ? n : -1);
    for (long long f = first; step > 0 ? f < stop : f > stop; f += step) {
      if (out.size() >= max_frames) return fail("more than " + std::to_string(max_frames) + " frames selected");
      out.push_back(static_cast<std::size_t>(f));
    }
  }
  return out;
}

Progress::Progress(std::string label, std::size_t total)
    : label_(std::move(label)), total_(total), enabled_(::isatty(STDERR_FILENO) == 1),
      next_(std::chrono::steady_clock::now() + std::chrono::milliseconds(500)) {}  // short work shows nothing

Progress::~Progress() {
  if (enabled_) std::fprintf(stderr, "\r\033[K");
}

void Progress::update(std::size_t done) {
  if (!enabled_) return;
  const auto now = std::chrono::steady_clock::now();
  if (now < next_) return;
  next_ = now + std::chrono::milliseconds(200);
  std::fprintf(stderr, "\r%s %zu/%zu (%.0f%%)", label_.c_str(), done, total_, total_ ? 100.0 * static_cast<double>(done) / static_cast<double>(total_) : 100.0);
}

}  // namespace dq::cli

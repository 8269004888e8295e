#include "dq/io/bvh.hpp"

#include "dq/io/utf8.hpp"
#include "dq/util/assert.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <optional>
#include <unordered_map>
#include <unordered_set>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace dq {

namespace {

constexpr double kDegree = std::numbers::pi / 180;

// ---- lexing: the text as lines of whitespace-separated tokens ------------------------------------

struct Token {
  std::string_view text;
  std::size_t line = 0;  // 1-based
};

/// Splits the text into lines (\n, \r\n or a lone \r) and tokens (separated by spaces, tabs, \v, \f).
class Lexer {
 public:
  explicit Lexer(std::string_view text) : text_(text) {}

  /// The next token, skipping blank lines; an empty token at the end of the text.
  Token next() {
    skip_blank();
    if (pos_ >= text_.size()) return {{}, line_};
    const std::size_t start = pos_;
    while (pos_ < text_.size() && !is_space(text_[pos_]) && !is_newline(text_[pos_])) ++pos_;
    return {text_.substr(start, pos_ - start), line_};
  }
  /// The next token on the current line (consumed); nothing at the end of the line. Lines are
  /// read token by token, so a huge line costs no memory beyond what is kept of it.
  std::optional<Token> next_on_line() {
    while (pos_ < text_.size() && is_space(text_[pos_])) ++pos_;
    if (pos_ >= text_.size() || is_newline(text_[pos_])) return std::nullopt;
    const std::size_t start = pos_;
    while (pos_ < text_.size() && !is_space(text_[pos_]) && !is_newline(text_[pos_])) ++pos_;
    return Token{text_.substr(start, pos_ - start), line_};
  }
  /// Moves to the start of the next line that has any token; false at the end of the text.
  bool next_nonblank_line() {
    skip_blank();
    return pos_ < text_.size();
  }
  std::size_t line() const noexcept { return line_; }
  std::size_t bytes_left() const noexcept { return text_.size() - pos_; }

 private:
  static bool is_space(char c) { return c == ' ' || c == '\t' || c == '\v' || c == '\f'; }
  static bool is_newline(char c) { return c == '\n' || c == '\r'; }
  void skip_blank() {
    while (pos_ < text_.size()) {
      const char c = text_[pos_];
      if (is_space(c)) {
        ++pos_;
      } else if (c == '\r') {
        ++pos_;
        if (pos_ < text_.size() && text_[pos_] == '\n') ++pos_;
        ++line_;
      } else if (c == '\n') {
        ++pos_;
        ++line_;
      } else {
        break;
      }
    }
  }
  std::string_view text_;
  std::size_t pos_ = 0;
  std::size_t line_ = 1;
};

bool iequals(std::string_view a, std::string_view b) {
  return a.size() == b.size() &&
         std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) { return std::tolower(static_cast<unsigned char>(x)) == std::tolower(static_cast<unsigned char>(y)); });
}

std::string quoted(std::string_view s) {
  if (s.empty()) return "end of file";
  std::string out = "'";
  for (char c : s.substr(0, 40)) out += (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) >= 0x7f) ? '?' : c;
  if (s.size() > 40) out += "...";
  return out + "'";
}

std::optional<double> parse_double(std::string_view s) {
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  double v = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || end != s.data() + s.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

std::optional<std::size_t> parse_count(std::string_view s, std::size_t max) {
  std::size_t v = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || end != s.data() + s.size() || v > max) return std::nullopt;
  return v;
}

std::optional<BvhChannel> parse_channel(std::string_view s) {
  static constexpr std::array<std::pair<std::string_view, BvhChannel>, 6> names{{{"Xposition", BvhChannel::Xposition},
                                                                                 {"Yposition", BvhChannel::Yposition},
                                                                                 {"Zposition", BvhChannel::Zposition},
                                                                                 {"Xrotation", BvhChannel::Xrotation},
                                                                                 {"Yrotation", BvhChannel::Yrotation},
                                                                                 {"Zrotation", BvhChannel::Zrotation}}};
  for (const auto& [name, c] : names)
    if (iequals(s, name)) return c;
  return std::nullopt;
}

class Parser {
 public:
  Parser(std::string_view text, std::string_view source) : lex_(text), source_(source) {}

  Expected<BvhFile> parse() {
    if (auto e = expect_word("HIERARCHY")) return *e;
    Token t = lex_.next();
    if (!iequals(t.text, "ROOT")) return fail(t, "expected 'ROOT'");
    while (iequals(t.text, "ROOT")) {
      if (auto e = parse_joint_tree(t)) return *e;
      t = lex_.next();
    }
    if (!iequals(t.text, "MOTION")) return fail(t, "expected 'ROOT' or 'MOTION'");
    if (auto e = parse_motion()) return *e;
    name_end_sites();
    return std::move(bvh_);
  }

 private:
  using Failure = std::optional<Error>;

  Error fail(const Token& t, const std::string& what) const {
    return Error{std::string(source_) + ":" + std::to_string(t.line) + ": " + what + ", found " + quoted(t.text)};
  }
  Error fail_line(std::size_t line, const std::string& what) const {
    return Error{std::string(source_) + ":" + std::to_string(line) + ": " + what};
  }
  Failure expect_word(std::string_view word) {
    const Token t = lex_.next();
    if (!iequals(t.text, word)) return fail(t, "expected '" + std::string(word) + "'");
    return std::nullopt;
  }
  Failure read_number(double& out) {
    const Token t = lex_.next();
    const auto v = parse_double(t.text);
    if (!v) return fail(t, "expected a finite number");
    out = *v;
    return std::nullopt;
  }
  Failure read_offset(Vec3<double>& out) {
    for (int i = 0; i < 3; ++i)
      if (auto e = read_number(out[i])) return e;
    return std::nullopt;
  }

  /// ROOT/JOINT name on the rest of the line; a '{' may end that line.
  Failure read_name(const Token& keyword, std::string& name, bool& brace_seen) {
    name.clear();
    brace_seen = false;
    while (const auto t = lex_.next_on_line()) {
      if (brace_seen) name += name.empty() ? "{" : " {";  // a '{' that was not the last token
      brace_seen = t->text == "{";
      if (brace_seen) continue;
      if (!name.empty()) name += ' ';
      name += t->text;
      if (name.size() > BvhLimits::max_name_bytes)
        return fail_line(keyword.line, "a joint name longer than " + std::to_string(BvhLimits::max_name_bytes) + " bytes");
    }
    if (name.empty()) return fail_line(keyword.line, "expected a joint name after '" + std::string(keyword.text) + "'");
    if (!is_valid_utf8(name)) return fail_line(keyword.line, "a joint name must be UTF-8 text");
    // Braces delimit blocks: a name containing one could not be written back unambiguously.
    if (name.find_first_of("{}") != std::string::npos)
      return fail_line(keyword.line, "a joint name may not contain '{' or '}'");
    return std::nullopt;
  }

  /// Parses a ROOT block and everything nested in it, iteratively (no recursion, so deeply
  /// nested hostile input cannot overflow the stack).
  Failure parse_joint_tree(const Token& root_keyword) {
    std::vector<int> stack;  // open joints
    Token keyword = root_keyword;
    while (true) {
      // Open a joint: name, '{', OFFSET, CHANNELS.
      BvhJoint j;
      bool brace = false;
      if (auto e = read_name(keyword, j.name, brace)) return e;
      if (!brace)
        if (auto e = expect_word("{")) return e;
      j.parent = stack.empty() ? -1 : stack.back();
      if (auto e = expect_word("OFFSET")) return e;
      if (auto e = read_offset(j.offset)) return e;
      if (auto e = expect_word("CHANNELS")) return e;
      const Token count = lex_.next();
      const auto n = parse_count(count.text, 6);
      if (!n) return fail(count, "expected a channel count from 0 to 6");
      for (std::size_t i = 0; i < *n; ++i) {
        const Token c = lex_.next();
        const auto ch = parse_channel(c.text);
        if (!ch) return fail(c, "expected a channel name (Xposition ... Zrotation)");
        if (std::find(j.channels.begin(), j.channels.end(), *ch) != j.channels.end()) return fail(c, "channel repeated in a joint");
        j.channels.push_back(*ch);
      }
      j.first_channel = channels_;
      channels_ += j.channels.size();
      if (bvh_.joints.size() >= BvhLimits::max_joints)
        return fail_line(count.line, "more than " + std::to_string(BvhLimits::max_joints) + " joints");
      bvh_.joints.push_back(std::move(j));
      stack.push_back(static_cast<int>(bvh_.joints.size()) - 1);
      // Children until this joint closes; closing may pop several levels.
      while (true) {
        const Token t = lex_.next();
        if (iequals(t.text, "JOINT")) {
          keyword = t;
          break;  // open the child (outer loop)
        }
        if (iequals(t.text, "End")) {
          if (auto e = expect_word("Site")) return e;
          BvhJoint end;
          // named once the whole hierarchy is known (name_end_sites)
          end.parent = stack.back();
          end.end_site = true;
          end.first_channel = channels_;
          if (auto e = expect_word("{")) return e;
          if (auto e = expect_word("OFFSET")) return e;
          if (auto e = read_offset(end.offset)) return e;
          if (auto e = expect_word("}")) return e;
          if (bvh_.joints.size() >= BvhLimits::max_joints)
            return fail_line(lex_.line(), "more than " + std::to_string(BvhLimits::max_joints) + " joints");
          bvh_.joints.push_back(std::move(end));
          continue;
        }
        if (t.text == "}") {
          stack.pop_back();
          if (stack.empty()) return std::nullopt;
          continue;
        }
        return fail(t, "expected 'JOINT', 'End Site' or '}'");
      }
    }
  }

  Failure parse_motion() {
    // "Frames: N" (also "Frames : N").
    Token t = lex_.next();
    if (!iequals(t.text, "Frames:")) {
      if (!iequals(t.text, "Frames")) return fail(t, "expected 'Frames:'");
      if (auto e = expect_word(":")) return e;
    }
    const Token count = lex_.next();
    const auto frames = parse_count(count.text, BvhLimits::max_frames);
    if (!frames) return fail(count, "expected a frame count");
    // "Frame Time: t".
    if (auto e = expect_word("Frame")) return e;
    t = lex_.next();
    if (!iequals(t.text, "Time:")) {
      if (!iequals(t.text, "Time")) return fail(t, "expected 'Time:'");
      if (auto e = expect_word(":")) return e;
    }
    const Token ft = lex_.next();
    const auto frame_time = parse_double(ft.text);
    if (!frame_time || *frame_time <= 0) return fail(ft, "expected a positive frame time");
    bvh_.frame_count = *frames;
    bvh_.frame_time = *frame_time;
    // One frame per line, exactly channels_ numbers each. The declared count is not trusted for
    // allocation: every value takes at least two bytes of the text that is left.
    bvh_.motion.reserve(std::min(*frames * channels_, lex_.bytes_left() / 2));
    for (std::size_t f = 0; f < *frames && channels_ > 0; ++f) {
      if (!lex_.next_nonblank_line())
        return fail_line(lex_.line(), "expected " + std::to_string(*frames) + " frames, found " + std::to_string(f));
      const std::size_t line = lex_.line();
      std::size_t n = 0;
      while (const auto v = lex_.next_on_line()) {
        if (++n > channels_) continue;  // counted for the message, not kept
        const auto x = parse_double(v->text);
        if (!x) return fail(*v, "expected a finite number in frame " + std::to_string(f));
        bvh_.motion.push_back(*x);
      }
      if (n != channels_)
        return fail_line(line, "frame " + std::to_string(f) + " has " + std::to_string(n) + " values, expected " + std::to_string(channels_));
    }
    // Whole frame lines past the declared count (some published files have one) are ignored
    // with a warning that says where; anything else after the motion is an error.
    std::size_t extra_frames = 0, first_extra_line = 0;
    while (channels_ > 0 && lex_.next_nonblank_line()) {
      const std::size_t line = lex_.line();
      std::size_t n = 0;
      std::optional<Token> first, bad;
      while (const auto v = lex_.next_on_line()) {
        if (!first) first = v;
        if (!bad && !parse_double(v->text)) bad = v;
        ++n;
      }
      if (n != channels_ || bad) return fail(*first, "expected end of file after " + frames_text(*frames));
      if (extra_frames++ == 0) first_extra_line = line;
    }
    if (extra_frames > 0)
      bvh_.warnings.push_back(std::string(source_) + ":" + std::to_string(first_extra_line) + ": " + std::to_string(extra_frames) +
                              " frame line(s) beyond the " + std::to_string(*frames) + " declared in 'Frames:' ignored");
    const Token extra = lex_.next();
    if (!extra.text.empty()) return fail(extra, "expected end of file after " + frames_text(*frames));
    return std::nullopt;
  }

  static std::string frames_text(std::size_t n) { return std::to_string(n) + (n == 1 ? " frame" : " frames"); }

  /// End Sites are named "<parent>_End"; where a joint of the file already has that name (or an
  /// earlier End Site took it), "<parent>_End_2", "_3", ...: End Site names never collide.
  void name_end_sites() {
    std::unordered_set<std::string> taken;
    for (const BvhJoint& j : bvh_.joints)
      if (!j.end_site) taken.insert(j.name);
    std::unordered_map<std::string, std::size_t> next_suffix;  // per base name: amortized linear
    for (BvhJoint& j : bvh_.joints) {
      if (!j.end_site) continue;
      const std::string base = bvh_.joints[static_cast<std::size_t>(j.parent)].name + "_End";
      std::size_t& k = next_suffix[base];
      std::string name = k == 0 ? base : base + "_" + std::to_string(k);
      while (taken.count(name)) name = base + "_" + std::to_string(k = std::max<std::size_t>(k + 1, 2));
      k = std::max<std::size_t>(k + 1, 2);
      taken.insert(name);
      j.name = std::move(name);
    }
  }

  Lexer lex_;
  std::string_view source_;
  BvhFile bvh_;
  std::size_t channels_ = 0;
};

constexpr std::size_t kMaxIndent = 32;

void append_number(std::string& out, double v) {
  std::array<char, 32> buf{};
  const auto r = std::to_chars(buf.data(), buf.data() + buf.size(), v);
  out.append(buf.data(), r.ptr);
}

Quaternion<double> axis_rotation(BvhChannel c, double degrees) {
  const Vec3<double> axis = c == BvhChannel::Xrotation ? Vec3<double>{1, 0, 0}
                            : c == BvhChannel::Yrotation ? Vec3<double>{0, 1, 0}
                                                         : Vec3<double>{0, 0, 1};
  return Quaternion<double>::from_axis_angle(axis, degrees * kDegree);
}

bool is_rotation(BvhChannel c) { return c >= BvhChannel::Xrotation; }

bool translation_moved(const Vec3<double>& t, const Vec3<double>& rest) {
  const double scale = 1 + std::max({std::abs(rest.x), std::abs(rest.y), std::abs(rest.z)});
  return std::max({std::abs(t.x - rest.x), std::abs(t.y - rest.y), std::abs(t.z - rest.z)}) > 1e-9 * scale;
}

}  // namespace

std::string_view to_string(BvhChannel c) noexcept {
  constexpr std::array<std::string_view, 6> names{"Xposition", "Yposition", "Zposition", "Xrotation", "Yrotation", "Zrotation"};
  return names[static_cast<std::size_t>(c)];
}

std::size_t BvhFile::channel_count() const noexcept {
  std::size_t n = 0;
  for (const BvhJoint& j : joints) n += j.channels.size();
  return n;
}

Expected<BvhFile> read_bvh(std::string_view text, std::string_view source) {
  if (text.starts_with("\xEF\xBB\xBF")) text.remove_prefix(3);  // a UTF-8 byte-order mark
  return Parser(text, source).parse();
}

Expected<BvhFile> read_bvh_file(const std::filesystem::path& path) {
  const std::string name = path.string();
  // Non-blocking open: a FIFO must not hang us before we can see that it is one.
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK | O_NOCTTY);
  if (fd < 0) return Error{name + ": cannot open for reading: " + std::strerror(errno)};
  struct Closer {
    int fd;
    ~Closer() { ::close(fd); }
  } closer{fd};
  struct stat st {};
  if (::fstat(fd, &st) != 0) return Error{name + ": cannot open for reading: " + std::strerror(errno)};
  if (S_ISDIR(st.st_mode)) return Error{name + ": is a directory"};
  if (!S_ISREG(st.st_mode)) return Error{name + ": is not a regular file (a device, FIFO or socket)"};
  const auto size = static_cast<std::size_t>(st.st_size);
  if (size > BvhLimits::max_file_bytes)
    return Error{name + ": " + std::to_string(size) + " bytes, more than the " + std::to_string(BvhLimits::max_file_bytes) +
                 " a BVH file may have"};
  std::string text(size, '\0');
  std::size_t done = 0;
  while (done < size) {  // a file that shrinks meanwhile ends early; one that grows is read as it was
    const ssize_t n = ::read(fd, text.data() + done, size - done);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) return Error{name + ": read error: " + std::strerror(errno)};
    if (n == 0) break;
    done += static_cast<std::size_t>(n);
  }
  text.resize(done);
  return read_bvh(text, name);
}

namespace {
/// A name read_bvh reads back unchanged: it joins a name's words with single spaces.
bool name_reads_back(const std::string& name) {
  return !name.empty() && name.size() <= BvhLimits::max_name_bytes && is_valid_utf8(name) &&
         name.find_first_of("{}\t\n\v\f\r") == std::string::npos && name.front() != ' ' && name.back() != ' ' &&
         name.find("  ") == std::string::npos;
}
std::string joint_label(const BvhFile& bvh, std::size_t i) { return "joint " + std::to_string(i) + " ('" + bvh.joints[i].name + "')"; }
}  // namespace

Status check_writable(const BvhFile& bvh) {
  const auto fail = [](const std::string& what) { return Error{"cannot write BVH: " + what}; };
  if (bvh.joints.empty() || bvh.joints[0].parent != -1 || bvh.joints[0].end_site) return fail("the first joint must be a root joint");
  if (bvh.joints.size() > BvhLimits::max_joints) return fail("more than " + std::to_string(BvhLimits::max_joints) + " joints");
  std::size_t channels = 0;
  std::vector<int> open;  // the writer's open blocks: a joint's parent must be one of them (depth-first order)
  for (std::size_t i = 0; i < bvh.joints.size(); ++i) {
    const BvhJoint& j = bvh.joints[i];
    if (j.parent < -1 || j.parent >= static_cast<int>(i)) return fail(joint_label(bvh, i) + ": its parent must come before it");
    while (!open.empty() && open.back() != j.parent) open.pop_back();
    if (open.empty() && j.parent != -1)
      return fail(joint_label(bvh, i) + ": the joints are not in depth-first order (a subtree must follow its parent without a gap)");
    open.push_back(static_cast<int>(i));
    for (std::size_t a = 0; a < j.channels.size(); ++a)
      for (std::size_t b = a + 1; b < j.channels.size(); ++b)
        if (j.channels[a] == j.channels[b]) return fail(joint_label(bvh, i) + ": channel " + std::string(to_string(j.channels[a])) + " repeated");
    if (j.parent >= 0 && bvh.joints[static_cast<std::size_t>(j.parent)].end_site) return fail(joint_label(bvh, i) + ": its parent is an End Site");
    if (j.parent < 0 && j.end_site) return fail(joint_label(bvh, i) + ": an End Site without a parent");
    if (!j.end_site && !name_reads_back(j.name))
      return fail(joint_label(bvh, i) + ": the name would not read back (empty, not UTF-8, braces, line breaks or runs of spaces)");
    if (!std::isfinite(j.offset.x) || !std::isfinite(j.offset.y) || !std::isfinite(j.offset.z))
      return fail(joint_label(bvh, i) + ": the offset is not finite");
    if (j.end_site && !j.channels.empty()) return fail(joint_label(bvh, i) + ": an End Site has no channels");
    if (j.channels.size() > 6) return fail(joint_label(bvh, i) + ": more than 6 channels");
    if (j.first_channel != channels) return fail(joint_label(bvh, i) + ": first_channel is not the count of the channels before it");
    channels += j.channels.size();
  }
  if (!std::isfinite(bvh.frame_time) || !(bvh.frame_time > 0)) return fail("the frame time must be finite and positive");
  if (bvh.frame_count > BvhLimits::max_frames) return fail("more than " + std::to_string(BvhLimits::max_frames) + " frames");
  if (bvh.motion.size() != bvh.frame_count * channels)
    return fail(std::to_string(bvh.motion.size()) + " motion values for " + std::to_string(bvh.frame_count) + " frames of " +
                std::to_string(channels) + " channels");
  for (std::size_t k = 0; k < bvh.motion.size(); ++k)
    if (!std::isfinite(bvh.motion[k])) {
      const std::size_t c = k % channels;
      std::size_t i = 0;
      while (bvh.joints[i].first_channel + bvh.joints[i].channels.size() <= c) ++i;
      return fail("frame " + std::to_string(k / channels) + ", " + joint_label(bvh, i) + " " +
                  std::string(to_string(bvh.joints[i].channels[c - bvh.joints[i].first_channel])) + ": the value is not finite");
    }
  return {};
}

Expected<std::string> write_bvh(const BvhFile& bvh) {
  std::string text;
  if (Status s = write_bvh(bvh, [&](std::string_view chunk) { text += chunk; }); !s) return s.error();
  return text;
}

Status write_bvh(const BvhFile& bvh, const std::function<void(std::string_view)>& sink) {
  if (Status s = check_writable(bvh); !s) return s;
  std::string out = "HIERARCHY\n";
  std::vector<int> open;  // joints whose block is open
  // Indentation is capped, so that the text stays linear in the number of joints at any depth.
  auto indent = [&](std::size_t depth) { out.append(std::min(depth, kMaxIndent), '\t'); };
  for (std::size_t i = 0; i < bvh.joints.size(); ++i) {
    const BvhJoint& j = bvh.joints[i];
    while (!open.empty() && open.back() != j.parent) {  // close finished subtrees
      open.pop_back();
      indent(open.size());
      out += "}\n";
    }
    indent(open.size());
    if (j.end_site) {
      out += "End Site\n";
    } else {
      out += (j.parent < 0 ? "ROOT " : "JOINT ") + j.name + "\n";
    }
    indent(open.size());
    out += "{\n";
    indent(open.size() + 1);
    out += "OFFSET ";
    for (int k = 0; k < 3; ++k) {
      append_number(out, j.offset[k]);
      out += k < 2 ? " " : "\n";
    }
    if (!j.end_site) {
      indent(open.size() + 1);
      out += "CHANNELS ";
      out += std::to_string(j.channels.size());
      for (BvhChannel c : j.channels) {
        out += ' ';
        out += to_string(c);
      }
      out += "\n";
    }
    open.push_back(static_cast<int>(i));
  }
  while (!open.empty()) {
    open.pop_back();
    indent(open.size());
    out += "}\n";
  }
  out += "MOTION\nFrames: " + std::to_string(bvh.frame_count) + "\nFrame Time: ";
  append_number(out, bvh.frame_time);
  out += "\n";
  const std::size_t n = bvh.channel_count();
  for (std::size_t f = 0; f < bvh.frame_count && n > 0; ++f) {
    for (std::size_t c = 0; c < n; ++c) {
      if (c) out += ' ';
      append_number(out, bvh.motion[f * n + c]);
    }
    out += '\n';
    if (out.size() >= (1u << 16)) sink(std::exchange(out, {}));
  }
  sink(out);
  return {};
}

namespace {
Quaternion<double> joint_rotation(const BvhJoint& j, std::span<const double> frame) {
  Quaternion<double> q;
  for (std::size_t k = 0; k < j.channels.size(); ++k)
    if (is_rotation(j.channels[k])) q = q * axis_rotation(j.channels[k], frame[j.first_channel + k]);
  return q;
}
Vec3<double> joint_translation(const BvhJoint& j, std::span<const double> frame) {
  Vec3<double> t = j.offset;
  for (std::size_t k = 0; k < j.channels.size(); ++k)
    if (!is_rotation(j.channels[k])) t[static_cast<int>(j.channels[k])] += frame[j.first_channel + k];
  return t;
}
}  // namespace

namespace {
std::optional<Error> check_bvh_order(EulerOrder order) {
  if (!is_proper_euler(order)) return std::nullopt;
  return Error{std::string(to_string(order)) + " repeats an axis, which BVH channels cannot (use XYZ, XZY, YXZ, YZX, ZXY or ZYX)"};
}
}  // namespace

Expected<BvhFile> with_rotation_order(const BvhFile& bvh, EulerOrder order) {
  if (auto e = check_bvh_order(order)) return *e;
  const auto axes = euler_axes(order);
  BvhFile out = bvh;
  out.motion.clear();
  std::size_t next = 0;
  for (BvhJoint& j : out.joints) {  // new channel lists: positions first, then the new rotations
    if (j.end_site) {
      j.first_channel = next;
      continue;
    }
    const bool had_rotation = std::any_of(j.channels.begin(), j.channels.end(), is_rotation);
    std::vector<BvhChannel> channels;
    for (BvhChannel c : j.channels)
      if (!is_rotation(c)) channels.push_back(c);
    if (had_rotation)
      for (int a : axes) channels.push_back(static_cast<BvhChannel>(static_cast<int>(BvhChannel::Xrotation) + a));
    j.channels = channels;
    j.first_channel = next;
    next += j.channels.size();
  }
  out.motion.reserve(bvh.frame_count * next);
  for (std::size_t f = 0; f < bvh.frame_count; ++f) {
    const auto frame = bvh.frame(f);
    for (std::size_t i = 0; i < out.joints.size(); ++i) {
      const BvhJoint& src = bvh.joints[i];
      const BvhJoint& dst = out.joints[i];
      for (std::size_t k = 0; k < src.channels.size(); ++k)
        if (!is_rotation(src.channels[k])) out.motion.push_back(frame[src.first_channel + k]);
      if (dst.channels.size() > 0 && is_rotation(dst.channels.back())) {
        const EulerAngles<double> e = to_euler(joint_rotation(src, frame), order, EulerFrame::intrinsic).angles;
        out.motion.push_back(e.a / kDegree);
        out.motion.push_back(e.b / kDegree);
        out.motion.push_back(e.c / kDegree);
      }
    }
  }
  return out;
}

DualQuaternion<double> bvh_local_transform(const BvhFile& bvh, std::size_t joint, std::size_t frame) {
  DQ_PRECONDITION(joint < bvh.joints.size() && frame < bvh.frame_count && bvh.motion.size() == bvh.frame_count * bvh.channel_count(),
                  "bvh_local_transform needs a joint and a frame of the file", DualQuaternion<double>{});
  const BvhJoint& j = bvh.joints[joint];
  const auto values = bvh.frame(frame);
  return DualQuaternion<double>::from_rotation_translation(joint_rotation(j, values), joint_translation(j, values));
}

DualQuaternion<double> bvh_rest_transform(const BvhFile& bvh, std::size_t joint) {
  return DualQuaternion<double>::from_translation(bvh.joints[joint].offset);
}

Expected<BvhFile> to_bvh(const Skeleton& skeleton, const Animation& given, EulerOrder order) {
  if (auto e = check_bvh_order(order)) return *e;
  // A skeleton without animation is written with its rest pose as its one frame: OFFSET holds
  // only translations, so the rest rotations would be lost otherwise.
  Animation rest_pose;
  if (given.frame_count == 0) {
    rest_pose.frame_time = given.frame_time;
    rest_pose.frame_count = 1;
    rest_pose.joint_count = skeleton.size();
    rest_pose.locals.assign(skeleton.rest_pose().begin(), skeleton.rest_pose().end());
  }
  const Animation& animation = given.frame_count == 0 ? rest_pose : given;
  if (animation.joint_count != skeleton.size() || animation.locals.size() != animation.frame_count * animation.joint_count)
    return Error{"the animation has " + std::to_string(animation.joint_count) + " joints (" + std::to_string(animation.locals.size()) +
                 " transforms), the skeleton " + std::to_string(skeleton.size()) + ": they are not one character's"};
  BvhFile out;
  out.frame_count = animation.frame_count;
  out.frame_time = animation.frame_time > 0 ? animation.frame_time : 1.0 / 30;
  const std::size_t n = skeleton.size();
  // Names as BVH can hold them (no whitespace or braces, UTF-8 by the caller), made unique again.
  std::unordered_set<std::string> taken;
  std::vector<std::string> names(n);
  for (std::size_t j = 0; j < n; ++j) {
    std::string& name = names[j];
    name = skeleton.names()[j];
    if (name.size() > BvhLimits::max_name_bytes - 16) name.resize(BvhLimits::max_name_bytes - 16);  // room for a suffix
    const bool utf8 = is_valid_utf8(name);
    std::replace_if(name.begin(), name.end(), [utf8](unsigned char c) { return std::isspace(c) || c == '{' || c == '}' || c < 0x20 || (!utf8 && c >= 0x80); }, '_');
  }
  for (std::size_t j = 0; j < n; ++j)
    if (names[j] == skeleton.names()[j]) taken.insert(names[j]);  // unchanged names keep priority
  for (std::size_t j = 0; j < n; ++j) {
    if (names[j] == skeleton.names()[j]) continue;
    std::string candidate = names[j];
    for (std::size_t k = 2; taken.count(candidate); ++k) candidate = names[j] + "_" + std::to_string(k);
    taken.insert(candidate);
    names[j] = std::move(candidate);
    out.warnings.push_back("joint '" + skeleton.names()[j] + "' is written as '" + names[j] + "' (BVH names have no whitespace or braces)");
  }
  const auto axes = euler_axes(order);
  std::vector<bool> moves(n, false);
  for (std::size_t j = 0; j < n; ++j) {
    const Vec3<double> rest = skeleton.rest_pose()[j].translation();
    for (std::size_t f = 0; f < animation.frame_count && !moves[j]; ++f)
      moves[j] = translation_moved(animation.frame(f)[j].translation(), rest);
  }
  std::size_t next = 0;
  for (std::size_t j = 0; j < n; ++j) {
    BvhJoint b;
    b.name = std::move(names[j]);
    b.parent = skeleton.parents()[j];
    b.offset = skeleton.rest_pose()[j].translation();
    b.end_site = skeleton.is_end_site(j);
    if (!b.end_site) {
      if (b.parent < 0 || moves[j]) b.channels = {BvhChannel::Xposition, BvhChannel::Yposition, BvhChannel::Zposition};
      for (int a : axes) b.channels.push_back(static_cast<BvhChannel>(static_cast<int>(BvhChannel::Xrotation) + a));
    }
    b.first_channel = next;
    next += b.channels.size();
    out.joints.push_back(std::move(b));
  }
  out.motion.reserve(out.frame_count * next);
  for (std::size_t f = 0; f < out.frame_count; ++f) {
    const auto frame = animation.frame(f);
    for (std::size_t j = 0; j < n; ++j) {
      const BvhJoint& b = out.joints[j];
      if (b.end_site) continue;
      if (b.channels.size() == 6) {
        const Vec3<double> d = frame[j].translation() - b.offset;
        out.motion.insert(out.motion.end(), {d.x, d.y, d.z});
      }
      const EulerAngles<double> e = to_euler(frame[j].real, order, EulerFrame::intrinsic).angles;
      out.motion.insert(out.motion.end(), {e.a / kDegree, e.b / kDegree, e.c / kDegree});
    }
  }
  return out;
}

Expected<Skeleton> bvh_skeleton(const BvhFile& bvh) {
  RawSkeleton raw;
  for (std::size_t i = 0; i < bvh.joints.size(); ++i)
    raw.add(bvh.joints[i].name, bvh.joints[i].parent, bvh_rest_transform(bvh, i), bvh.joints[i].end_site);
  return build_skeleton(raw);
}

bool is_skeleton_of(const Skeleton& skeleton, const BvhFile& bvh) {
  if (skeleton.size() != bvh.joints.size() || bvh.motion.size() != bvh.frame_count * bvh.channel_count()) return false;
  const auto raw = skeleton.raw_indices();
  for (std::size_t j = 0; j < skeleton.size(); ++j)
    if (raw[j] < 0 || static_cast<std::size_t>(raw[j]) >= bvh.joints.size() ||
        bvh.joints[static_cast<std::size_t>(raw[j])].name != skeleton.names()[j])
      return false;
  return true;
}

Animation bvh_animation(const BvhFile& bvh, const Skeleton& skeleton) {
  DQ_PRECONDITION(is_skeleton_of(skeleton, bvh), "bvh_animation needs the file's own skeleton (bvh_skeleton)", Animation{});
  Animation anim;
  anim.frame_time = bvh.frame_time;
  anim.frame_count = bvh.frame_count;
  anim.joint_count = skeleton.size();
  anim.locals.resize(anim.frame_count * anim.joint_count);
  const auto raw = skeleton.raw_indices();
  const std::size_t channels = bvh.channel_count();  // once: linear in frames × joints
  for (std::size_t f = 0; f < bvh.frame_count; ++f) {
    const std::span<const double> values = std::span(bvh.motion).subspan(f * channels, channels);
    for (std::size_t j = 0; j < skeleton.size(); ++j) {
      const BvhJoint& b = bvh.joints[static_cast<std::size_t>(raw[j])];
      anim.locals[f * anim.joint_count + j] =
          DualQuaternion<double>::from_rotation_translation(joint_rotation(b, values), joint_translation(b, values));
    }
  }
  return anim;
}

}  // namespace dq

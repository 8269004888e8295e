#include "dq/io/motion.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <limits>

#include "dq/anim/animation.hpp"
#include "dq/io/file.hpp"

namespace dq {

std::size_t resampled_frame_count(double seconds, double rate) {
  // 1e-9 of a frame of rounding does not add a frame; a clip of any positive length keeps its last
  // pose (a 1e-14 s clip at 30 Hz lost it to that tolerance).
  const double steps = std::max(std::ceil(seconds * rate - 1e-9), seconds > 0 ? 1.0 : 0.0);
  if (!(steps < 0x1p62)) return std::numeric_limits<std::size_t>::max();  // also NaN
  return static_cast<std::size_t>(std::max(steps, 0.0)) + 1;
}

bool is_bvh_file(const std::filesystem::path& path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK | O_NOCTTY);
  if (fd < 0) return false;
  struct stat st {};
  char head[256];
  const ssize_t n = ::fstat(fd, &st) == 0 && S_ISREG(st.st_mode) ? ::read(fd, head, sizeof head) : -1;
  ::close(fd);
  return n > 0 && looks_like_bvh(std::string_view(head, static_cast<std::size_t>(n)));
}

bool looks_like_bvh(std::string_view s) {
  if (s.starts_with("\xEF\xBB\xBF")) s.remove_prefix(3);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  if (s.size() < 9) return false;
  return std::equal(s.begin(), s.begin() + 9, "HIERARCHY", [](char a, char b) { return std::toupper(static_cast<unsigned char>(a)) == b; });
}

namespace {

Status check_budget(std::size_t frames, std::size_t joints, const MotionOptions& options, const std::string& source) {
  const double bytes = static_cast<double>(frames) * static_cast<double>(joints) * sizeof(DualQuaternion<double>);
  if (bytes <= static_cast<double>(options.memory_limit_mb) * 1048576.0) return {};
  char megabytes[32];  // as a double: the count may be beyond any integer type (resampled_frame_count saturates)
  std::snprintf(megabytes, sizeof megabytes, "%.4g", bytes / 1048576.0);
  return Error{source + ": " + std::to_string(frames) + " frames of " + std::to_string(joints) + " joints need " + megabytes +
               " MB, more than the " + std::to_string(options.memory_limit_mb) + " MB allowed"};
}

Expected<Motion> from_bvh(Expected<BvhFile> bvh, const std::string& source, const MotionOptions& options) {
  if (!bvh) return bvh.error();
  if (options.animation != 0) return Error{source + ": animation " + std::to_string(options.animation) + " requested, a BVH file has 1"};
  Expected<Skeleton> skeleton = bvh_skeleton(*bvh);
  if (!skeleton) return Error{source + ": " + skeleton.error().message};
  Motion m;
  m.format = "bvh";
  m.skeleton = std::move(*skeleton);
  const bool resample = options.sample_rate > 0;
  if (resample && !(options.sample_rate <= 1000)) return Error{source + ": the sample rate must be in (0, 1000] Hz"};
  if (auto s = check_budget(bvh->frame_count, m.skeleton.size(), options, source); !s) return s.error();
  m.animation = bvh_animation(*bvh, m.skeleton);
  if (resample && m.animation.frame_count > 0) {
    const double duration = m.animation.duration();
    const std::size_t frames = resampled_frame_count(duration, options.sample_rate);
    if (auto s = check_budget(frames, m.skeleton.size(), options, source); !s) return s.error();
    Animation out;
    out.frame_time = 1 / options.sample_rate;
    out.frame_count = frames;
    out.joint_count = m.skeleton.size();
    out.locals.resize(frames * out.joint_count);
    for (std::size_t f = 0; f < frames; ++f)
      sample<double>(m.animation, std::min(static_cast<double>(f) / options.sample_rate, duration), Interpolation::screw, WrapMode::clamp,
                     std::span(out.locals).subspan(f * out.joint_count, out.joint_count));
    m.animation = std::move(out);
  } else if (resample) {
    m.animation.frame_time = 1 / options.sample_rate;  // no frames, but the rate asked for (convert writes it)
  }
  m.animation_count = 1;
  m.warnings = bvh->warnings;
  m.bvh = std::move(*bvh);
  return m;
}

}  // namespace

bool has_bvh_extension(const std::filesystem::path& path) {
  return lowercase_extension(path) == ".bvh";
}

Expected<Motion> load_motion(const std::filesystem::path& path, const MotionOptions& options) {
  std::error_code ec;
  // A file named .bvh is read as BVH whatever it holds, so that a damaged one gets the reader's error.
  if (std::filesystem::is_regular_file(path, ec) && !is_bvh_file(path) && !has_bvh_extension(path))
    return Error{path.string() + ": not a BVH file (other formats are read by dq::import_motion, in dqkit::import, built with Assimp)"};
  return from_bvh(read_bvh_file(path), path.string(), options);  // missing files, directories, FIFOs: its errors
}

Expected<Motion> read_motion(std::string_view bvh_text, std::string_view source, const MotionOptions& options) {
  return from_bvh(read_bvh(bvh_text, source), std::string(source), options);
}

}  // namespace dq

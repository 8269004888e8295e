// Fuzz target: the BVH reader, and everything downstream of a file it accepts. Properties
// checked (abort on violation): a rejected file has a "source:line: " message; an accepted file
// round-trips exactly through the writer and the writer's text is a fixed point; End Site names
// never collide with joint names; skeleton, animation and rotation-order conversion produce finite
// unit transforms; every BVH the converters write (another order, or any skeleton through to_bvh)
// reads back. Run under a memory limit (scripts/fuzz.sh: -rss_limit_mb, -malloc_limit_mb), so a
// declared count that allocates more than the text justifies is found as an out-of-memory crash.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string_view>

#include "check.hpp"
#include "dq/io/bvh.hpp"
#include "dq/io/motion.hpp"

namespace {
using dq::fuzz::check;
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  const dq::Expected<dq::BvhFile> bvh = dq::read_bvh(text, "fuzz");
  if (!bvh) {
    check(bvh.error().message.rfind("fuzz:", 0) == 0, "error message names the source and line");
    return 0;
  }
  check(bvh->motion.size() <= size, "no more values than the text can hold");
  const dq::Expected<std::string> text_written = dq::write_bvh(*bvh);
  check(text_written.has_value(), "every file the reader accepts is writable");
  const std::string& written = *text_written;
  const dq::Expected<dq::BvhFile> again = dq::read_bvh(written, "written");
  check(again.has_value(), "written file reads back");
  check(again->motion == bvh->motion && again->joints.size() == bvh->joints.size(), "round trip is exact");
  check(dq::write_bvh(*again).value() == written, "writer output is a fixed point");
  check(written.size() <= 64 * size + 4096, "written text linear in the input");  // indentation is capped
  // The path of the tool: load (with its memory budget) and convert.
  dq::MotionOptions options;
  options.memory_limit_mb = 64;
  const dq::Expected<dq::Motion> m = dq::read_motion(text, "fuzz", options);
  if (!m) {
    check(m.error().message.rfind("fuzz", 0) == 0, "error message names the source");
    return 0;
  }
  for (const auto& q : m->animation.locals) check(q.is_unit(1e-9), "local transforms are unit");
  if (bvh->frame_count * bvh->joints.size() > 200000) return 0;  // keep each input fast
  const auto order = static_cast<dq::EulerOrder>(size % 6);  // the Tait-Bryan orders
  const dq::Expected<dq::BvhFile> converted = dq::with_rotation_order(*bvh, order);
  check(converted.has_value(), "Tait-Bryan orders convert");
  for (double v : converted->motion) check(std::isfinite(v), "converted angles are finite");
  const dq::Expected<std::string> converted_text = dq::write_bvh(*converted);
  check(converted_text.has_value() && dq::read_bvh(*converted_text, "converted").has_value(), "converted file reads back");
  check(!dq::with_rotation_order(*bvh, dq::EulerOrder::ZXZ).has_value(), "a proper Euler order is refused");
  const dq::Expected<dq::BvhFile> rebuilt = dq::to_bvh(m->skeleton, m->animation, order);
  check(rebuilt.has_value(), "to_bvh accepts any skeleton");
  const dq::Expected<std::string> rebuilt_text = dq::write_bvh(*rebuilt);
  check(rebuilt_text.has_value(), "to_bvh output is writable");
  const dq::Expected<dq::BvhFile> reread = dq::read_bvh(*rebuilt_text, "rebuilt");
  check(reread.has_value(), "to_bvh output reads back");
  check(dq::bvh_skeleton(*reread).has_value(), "to_bvh output has unique names");
  return 0;
}

// Fuzz target: the BVH reader, and everything downstream of a file it accepts. Properties
// checked (abort on violation): a rejected file has a "source:line: " message; an accepted file
// round-trips exactly through the writer; skeleton, animation and rotation-order conversion
// produce finite unit transforms.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string_view>

#include "check.hpp"
#include "dq/io/bvh.hpp"

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
  const std::string written = dq::write_bvh(*bvh);
  const dq::Expected<dq::BvhFile> again = dq::read_bvh(written, "written");
  check(again.has_value(), "written file reads back");
  check(again->motion == bvh->motion && again->joints.size() == bvh->joints.size(), "round trip is exact");
  check(dq::write_bvh(*again) == written, "writer output is a fixed point");
  const dq::Expected<dq::Skeleton> skeleton = dq::bvh_skeleton(*bvh);
  if (!skeleton) return 0;  // e.g. duplicate joint names: a clear error, fine
  if (bvh->frame_count * skeleton->size() > 200000) return 0;  // keep each input fast
  const dq::Animation anim = dq::bvh_animation(*bvh, *skeleton);
  for (const auto& q : anim.locals) check(q.is_unit(1e-9), "local transforms are unit");
  const dq::BvhFile converted = dq::with_rotation_order(*bvh, dq::EulerOrder::XZY);
  for (double v : converted.motion) check(std::isfinite(v), "converted angles are finite");
  return 0;
}

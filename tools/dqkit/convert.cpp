// dqkit convert: any motion file to BVH, optionally in another rotation order, at another rate or
// in another unit.
#include <filesystem>
#include <memory>

#include "commands.hpp"
#include "common.hpp"

namespace dq::cli {

namespace {

struct ConvertArgs {
  InputOptions input;
  std::string output;
  std::string rotation_order;  ///< empty: keep (BVH) or ZXY
  bool force = false;
  double scale = 1;
};

/// Multiplies every length of the file (offsets and position channels) by `s`.
void scale_lengths(BvhFile& bvh, double s) {
  if (s == 1) return;
  const std::size_t n = bvh.channel_count();
  for (BvhJoint& j : bvh.joints) {
    j.offset = j.offset * s;
    for (std::size_t k = 0; k < j.channels.size(); ++k)
      if (j.channels[k] <= BvhChannel::Zposition)
        for (std::size_t f = 0; f < bvh.frame_count; ++f) bvh.motion[f * n + j.first_channel + k] *= s;
  }
}

int run_convert(const ConvertArgs& args) {
  if (!is_stdout(args.output)) {
    if (lowercase_extension(args.output) != ".bvh") throw Failure(args.output + ": only BVH output is supported (the file name must end in .bvh, or - for standard output)");
  }
  const Motion m = load(args.input);
  Output out(args.output, args.force, {args.input.file});  // before the work: refusals come first
  std::optional<EulerOrder> order;
  for (EulerOrder o : all_euler_orders)
    if (to_string(o) == args.rotation_order) order = o;
  // BVH in, at its own rate: the file's own channels (exact values), reordered if asked.
  // Otherwise (other formats, or a new rate): the skeleton and the sampled animation.
  const bool keep_channels = m.bvh && args.input.rate == 0;
  Expected<BvhFile> bvh = keep_channels ? (order ? with_rotation_order(*m.bvh, *order) : Expected<BvhFile>(*m.bvh))
                                        : to_bvh(m.skeleton, m.animation, order.value_or(EulerOrder::ZXY));
  if (!bvh) throw Failure(bvh.error().message);
  if (!keep_channels) print_warnings(bvh->warnings);
  if (!keep_channels && m.animation.frame_count == 0)
    print_warnings({args.input.file + ": no animation; its rest pose is written as the one frame (BVH offsets hold no rotations)"});
  scale_lengths(*bvh, args.scale);
  if (Status s = write_bvh(*bvh, [&](std::string_view chunk) { out.write(chunk); }); !s)
    throw Failure(args.input.file + ": " + s.error().message + (args.scale != 1 ? " (after --scale)" : ""));
  out.finish();
  return 0;
}

}  // namespace

Runner define_convert(CLI::App& c) {
  auto args = std::make_shared<ConvertArgs>();
  add_input_options(c, args->input, "input");
  c.add_option("output", args->output, "BVH file to write (- for standard output)")->required()->check(file_name());
  c.add_option("--rotation-order", args->rotation_order, "Euler order of the rotation channels (BVH: the six Tait-Bryan orders)")
      ->check(CLI::IsMember({"XYZ", "XZY", "YXZ", "YZX", "ZXY", "ZYX"}));
  c.add_flag("--force", args->force, "Replace the output file if it exists (a regular file only)");
  c.add_option("--scale", args->scale, "Multiply every length by this (unit conversion, e.g. 0.01 for cm to m)")->check(finite_in(0, 1e12));
  return [args] { return run_convert(*args); };
}

}  // namespace dq::cli

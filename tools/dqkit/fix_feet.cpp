// dqkit fix-feet: removes foot sliding from a BVH capture with IK on the legs (dq/ik/motion_capture.hpp).
#include <algorithm>
#include <cstdio>
#include <memory>

#include "commands.hpp"
#include "common.hpp"
#include "dq/ik/motion_capture.hpp"

namespace dq::cli {

namespace {

struct FixFeetArgs {
  InputOptions input;
  std::string output;
  bool force = false;
  std::vector<std::string> feet;
  FixFeetOptions options;
};

int run_fix_feet(const FixFeetArgs& args) {
  if (args.input.rate != 0) throw Failure("fix-feet keeps the capture's own frames: --rate does not apply");
  if (!is_stdout(args.output) && lowercase_extension(args.output) != ".bvh")
    throw Failure(args.output + ": fix-feet writes BVH (the file name must end in .bvh, or - for standard output)");
  for (std::size_t i = 0; i < args.feet.size(); ++i) {
    if (args.feet[i].empty()) throw Failure("--feet: an empty joint name");
    if (std::find(args.feet.begin(), args.feet.begin() + static_cast<std::ptrdiff_t>(i), args.feet[i]) != args.feet.begin() + static_cast<std::ptrdiff_t>(i))
      throw Failure("--feet: '" + args.feet[i] + "' is given twice");
  }
  Motion m = load(args.input);
  if (!m.bvh) throw Failure(args.input.file + ": fix-feet works on BVH captures (convert other formats to BVH first)");
  Output out(args.output, args.force, {args.input.file});  // refusals before the work
  FixFeetOptions options = args.options;
  options.feet = args.feet;
  const Expected<FixFeetReport> report = fix_foot_sliding(*m.bvh, options);
  if (!report) throw Failure(args.input.file + ": " + report.error().message);
  if (Status s = write_bvh(*m.bvh, [&](std::string_view chunk) { out.write(chunk); }); !s) throw Failure(args.input.file + ": " + s.error().message);
  out.finish();
  // The report goes to standard error: standard output may be the BVH itself.
  for (const FootContactReport& f : report->feet)
    std::fprintf(stderr, "%s: %s, slid %.6g during contact before, %.3g after (largest step %.3g before, %.3g after)\n",
                 f.joint.c_str(), count_text(f.contacts.size(), "contact", "contacts").c_str(), f.slide_before, f.slide_after,
                 f.max_slide_step_before, f.max_slide_step_after);
  std::fprintf(stderr, "legs changed (%zu joints, up to %.3g); every other joint moved %.3g; largest pin error %.3g\n",
               report->leg_joints.size(), report->max_leg_joint_motion, report->max_other_joint_motion, report->max_pin_error);
  return 0;
}

}  // namespace

Runner define_fix_feet(CLI::App& c) {
  auto args = std::make_shared<FixFeetArgs>();
  add_input_options(c, args->input, "input");
  c.add_option("-o,--output", args->output, "BVH file to write (- or omitted: standard output)")->check(file_name());
  c.add_flag("--force", args->force, "Replace the output file if it exists (a regular file only)");
  c.add_option("--feet", args->feet, "Foot joints, comma-separated (default: found by name: Toe, else Foot, else Ankle)")
      ->delimiter(',')
      ->allow_extra_args(false)
      ->type_name("JOINT[,JOINT...]");  // one value (with commas): the arguments after it stay arguments
  c.add_option("--height", args->options.height, "Contact when the foot is this far above its lowest point at most (file units; default 0.1 leg lengths)")
      ->check(finite_in(0, 1e12));
  c.add_option("--speed", args->options.speed, "... and slower than this (file units per second; default 1 leg length per second)")
      ->check(finite_in(0, 1e12));
  c.add_option("--min-contact", args->options.min_contact_frames, "Shorter contacts (frames) are ignored")->check(CLI::Range(1, 1000000));
  c.add_option("--merge-gap", args->options.merge_gap_frames, "Gaps up to this many frames between contacts are bridged")
      ->check(CLI::Range(0, 1000000));
  c.add_option("--blend", args->options.blend_frames, "Frames over which each pin is blended in and out")->check(CLI::Range(0, 1000000));
  return [args] { return run_fix_feet(*args); };
}

}  // namespace dq::cli

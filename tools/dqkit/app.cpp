#include "app.hpp"

namespace dq::cli {

std::unique_ptr<CLI::App> make_app(Arguments& a) {
  auto app = std::make_unique<CLI::App>("dqkit: rigid transforms with dual quaternions, for 3D character hierarchies");
  app->require_subcommand(1);
  app->set_version_flag("--version", "dqkit 0.1.0");
  const char* timeout_help = "Seconds before the importer (a separate process) is abandoned";
  const char* animation_help = "Which animation of a multi-animation file (from 0)";

  a.info_cmd = app->add_subcommand("info", "Joints, hierarchy, frames, frame time and channels of a motion file");
  a.info_cmd->add_option("file", a.info.file, "BVH, glTF, FBX, Collada, X, IQM, ... file")->required();
  a.info_cmd->add_option("--animation", a.info.animation, animation_help);
  a.info_cmd->add_option("--import-timeout", a.info.import_timeout, timeout_help)->check(CLI::Range(0.001, 86400.0));

  a.fk_cmd = app->add_subcommand("fk", "World position and rotation of every joint, per frame");
  a.fk_cmd->add_option("file", a.fk.file, "Motion file")->required();
  auto* frames = a.fk_cmd->add_option("--frames", a.fk.frames, "Comma-separated frame numbers, from 0 (default: 0)");
  a.fk_cmd->add_flag("--all", a.fk.all, "Every frame")->excludes(frames);
  a.fk_cmd->add_option("--format", a.fk.format, "Output format")->check(CLI::IsMember({"csv", "json"}));
  a.fk_cmd->add_option("-o,--output", a.fk.output, "Write to this file instead of standard output");
  a.fk_cmd->add_flag("--force", a.fk.force, "Replace the output file if it exists");
  a.fk_cmd->add_option("--animation", a.fk.animation, animation_help);
  a.fk_cmd->add_option("--import-timeout", a.fk.import_timeout, timeout_help)->check(CLI::Range(0.001, 86400.0));

  a.convert_cmd = app->add_subcommand("convert", "Convert a motion file to BVH (optionally changing the rotation order)");
  a.convert_cmd->add_option("input", a.convert.input, "Motion file (BVH or any importable format)")->required();
  a.convert_cmd->add_option("output", a.convert.output, "BVH file to write")->required();
  a.convert_cmd->add_option("--rotation-order", a.convert.rotation_order, "Euler order of the rotation channels, e.g. ZXY")
      ->check(CLI::IsMember({"XYZ", "XZY", "YXZ", "YZX", "ZXY", "ZYX", "XYX", "XZX", "YXY", "YZY", "ZXZ", "ZYZ"}));
  a.convert_cmd->add_flag("--force", a.convert.force, "Replace the output file if it exists");
  a.convert_cmd->add_option("--animation", a.convert.animation, animation_help);
  a.convert_cmd->add_option("--import-timeout", a.convert.import_timeout, timeout_help)->check(CLI::Range(0.001, 86400.0));
  a.convert_cmd->add_option("--rate", a.convert.rate, "Frames per second when resampling imported animations")->check(CLI::Range(0.001, 1000.0));
  return app;
}

int run_command(const Arguments& a) {
  if (a.info_cmd->parsed()) return info(a.info);
  if (a.fk_cmd->parsed()) return fk(a.fk);
  return convert(a.convert);
}

}  // namespace dq::cli

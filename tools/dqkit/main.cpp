// dqkit: inspect motion files, compute forward kinematics, convert formats.
// The only place that touches argv and exit codes.
#include <CLI/CLI.hpp>

#include "commands.hpp"

int main(int argc, char** argv) {
  CLI::App app{"dqkit: rigid transforms with dual quaternions, for 3D character hierarchies"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "dqkit 0.1.0");

  dq::cli::InfoArgs info;
  CLI::App* info_cmd = app.add_subcommand("info", "Joints, hierarchy, frames, frame time and channels of a motion file");
  info_cmd->add_option("file", info.file, "BVH, glTF, FBX, Collada, X, IQM, ... file")->required();
  info_cmd->add_option("--animation", info.animation, "Which animation of a multi-animation file (from 0)");
  const char* timeout_help = "Seconds before the importer (a separate process) is abandoned";
  info_cmd->add_option("--import-timeout", info.import_timeout, timeout_help)->check(CLI::Range(0.001, 86400.0));

  dq::cli::FkArgs fk;
  CLI::App* fk_cmd = app.add_subcommand("fk", "World position and rotation of every joint, per frame");
  fk_cmd->add_option("file", fk.file, "Motion file")->required();
  auto* frames = fk_cmd->add_option("--frames", fk.frames, "Comma-separated frame numbers, from 0 (default: 0)");
  fk_cmd->add_flag("--all", fk.all, "Every frame")->excludes(frames);
  fk_cmd->add_option("--format", fk.format, "Output format")->check(CLI::IsMember({"csv", "json"}));
  fk_cmd->add_option("-o,--output", fk.output, "Write to this file instead of standard output");
  fk_cmd->add_flag("--force", fk.force, "Replace the output file if it exists");
  fk_cmd->add_option("--animation", fk.animation, "Which animation of a multi-animation file (from 0)");
  fk_cmd->add_option("--import-timeout", fk.import_timeout, timeout_help)->check(CLI::Range(0.001, 86400.0));

  dq::cli::ConvertArgs convert;
  CLI::App* convert_cmd = app.add_subcommand("convert", "Convert a motion file to BVH (optionally changing the rotation order)");
  convert_cmd->add_option("input", convert.input, "Motion file (BVH or any importable format)")->required();
  convert_cmd->add_option("output", convert.output, "BVH file to write")->required();
  convert_cmd->add_option("--rotation-order", convert.rotation_order, "Euler order of the rotation channels, e.g. ZXY")
      ->check(CLI::IsMember({"XYZ", "XZY", "YXZ", "YZX", "ZXY", "ZYX", "XYX", "XZX", "YXY", "YZY", "ZXZ", "ZYZ"}));
  convert_cmd->add_flag("--force", convert.force, "Replace the output file if it exists");
  convert_cmd->add_option("--animation", convert.animation, "Which animation of a multi-animation file (from 0)");
  convert_cmd->add_option("--import-timeout", convert.import_timeout, timeout_help)->check(CLI::Range(0.001, 86400.0));
  convert_cmd->add_option("--rate", convert.rate, "Frames per second when resampling imported animations")->check(CLI::Range(0.001, 1000.0));

  CLI11_PARSE(app, argc, argv);
  if (info_cmd->parsed()) return dq::cli::info(info);
  if (fk_cmd->parsed()) return dq::cli::fk(fk);
  return dq::cli::convert(convert);
}

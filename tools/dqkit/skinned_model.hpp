// What `dqkit skin` and `dqkit render` share: a skinned model loaded and ready to pose.
#pragma once

#include <string>

#include <CLI/CLI.hpp>

#include "dq/io/imported_scene.hpp"
#include "dq/skin/scene_skin.hpp"

namespace dq::cli {

struct SkinnedModelOptions {
  std::string file;
  double time = 0;
  std::size_t animation = 0;
  double import_timeout = 120;
  bool lights_and_cameras = false;
};
/// Adds the model file, --time, --animation, --import-timeout and --lights-and-cameras to a command.
void add_skinned_model_options(CLI::App& command, SkinnedModelOptions& options);

struct SkinnedModel {
  ImportedScene scene;
  SceneSkin skins;
};
/// Imports the file and builds its skins (warnings and renormalized weights reported); throws Failure.
SkinnedModel load_skinned_model(const SkinnedModelOptions& options);

/// "lbs", "dqs", "cor" (CLI11 checks the names).
SkinningMethod method_named(const std::string& name);

}  // namespace dq::cli

#include "skinned_model.hpp"

#include "common.hpp"
#include "dq/io/scene.hpp"

namespace dq::cli {

void add_skinned_model_options(CLI::App& c, SkinnedModelOptions& o) {
  c.add_option("file", o.file, "Skinned model (glTF, FBX, Collada, X, ...)")->required()->check(file_name());
  c.add_option("--time", o.time, "Seconds into the animation (clamped to its duration; no animation: the rest pose)")
      ->check(finite_in(-1e9, 1e9));
  c.add_option("--animation", o.animation, "Which animation of a multi-animation file (from 0)")->check(animation_index());
  c.add_option("--import-timeout", o.import_timeout, "Seconds before the importer (a separate process) is abandoned")
      ->check(finite_in(0, 86400));
  add_lights_and_cameras_option(c, o.lights_and_cameras);
}

SkinnedModel load_skinned_model(const SkinnedModelOptions& o) {
  if (o.file == "-") throw Failure("-: skin and render read a model file (the importer needs a file name); standard input is not supported");
  ImportOptions options;
  options.timeout_seconds = o.import_timeout;
  options.lights_and_cameras = o.lights_and_cameras;
  Expected<ImportedScene> scene = import_scene(o.file, options);
  if (!scene) throw Failure(scene.error().message);
  print_warnings(scene->warnings);
  if (scene->meshes.empty()) throw Failure(o.file + ": the file has no mesh to skin");
  // Assimp gives BVH captures a mesh that draws the bones; it is not a character's skin.
  if (has_bvh_extension(o.file) || is_bvh_file(o.file))
    throw Failure(o.file + ": a BVH capture has no mesh to skin (only the skeleton and its motion: dqkit fk, dqkit convert)");
  if (o.animation > 0 && o.animation >= scene->animations.size())  // 0 of none: the rest pose
    throw Failure(o.file + ": animation " + std::to_string(o.animation) + " requested, the file has " + std::to_string(scene->animations.size()));
  Expected<SceneSkin> skins = SceneSkin::build(*scene);
  if (!skins) throw Failure(o.file + ": " + skins.error().message);
  if (skins->renormalized_vertices())
    print_warnings({o.file + ": the weights of " + count_text(skins->renormalized_vertices(), "vertex", "vertices") + " did not sum to 1 and were normalized"});
  return {std::move(*scene), std::move(*skins)};
}

SkinningMethod method_named(const std::string& name) {
  if (name == "lbs") return SkinningMethod::lbs;
  if (name == "cor") return SkinningMethod::cor;
  return SkinningMethod::dqs;
}

}  // namespace dq::cli

// dqkit skin: a model skinned at a time, every vertex in world space (CSV vertex,x,y,z; OBJ; PLY;
// glTF 2.0), all meshes' vertices in import order.
#include <thread>

#include "commands.hpp"
#include "common.hpp"
#include "skinned_model.hpp"

namespace dq::cli {

namespace {

struct SkinArgs {
  SkinnedModelOptions model;
  std::string method = "dqs";
  std::function<std::string(const std::string&)> format;
  std::string output;
  bool force = false;
};

int run_skin(const SkinArgs& a) {
  const std::string format = a.format(a.output);  // refusals before the work
  SkinnedModel m = load_skinned_model(a.model);
  std::vector<DualQuaternion<double>> world;
  if (Status s = pose_at(m.scene, a.model.animation, a.model.time, world); !s) throw Failure(a.model.file + ": " + s.error().message);
  SkinnedFrame frame = m.skins.make_frame();
  SkinningThreads threads(std::max(1u, std::min(4u, std::thread::hardware_concurrency())));
  if (Status s = m.skins.skin(world, method_named(a.method), threads, frame); !s) throw Failure(a.model.file + ": " + s.error().message);
  const Expected<std::string> text = format_frame(frame, *parse_mesh_format(format));
  if (!text) throw Failure(text.error().message);
  Output out(a.output, a.force, {a.model.file});
  out.write(*text);
  out.finish();
  return 0;
}

}  // namespace

Runner define_skin(CLI::App& c) {
  auto a = std::make_shared<SkinArgs>();
  add_skinned_model_options(c, a->model);
  c.add_option("--method", a->method, "lbs (linear blend), dqs (dual quaternion, default), cor (centres of rotation)")
      ->check(CLI::IsMember({"lbs", "dqs", "cor"}));
  a->format = add_format_option(c, {"csv", "obj", "ply", "gltf"}, "csv (vertex,x,y,z), obj, ply or gltf");
  c.add_option("-o,--output", a->output, "Write to this file instead of standard output")->check(file_name());
  c.add_flag("--force", a->force, "Replace the output file if it exists");
  return [a] { return run_skin(*a); };
}

}  // namespace dq::cli

// Fuzz target: one file format through the Assimp importer wrapper (the format is fixed at build
// time: each format's target links a one-line source defining dqkit_fuzz_hint, see
// fuzz/CMakeLists.txt). dqkit's own code must turn whatever Assimp returns into a valid scene or a
// clear error: every transform finite and unit, every index in range.
#include <cstdint>
#include <cstdio>
#include <cstdlib>

#include "check.hpp"
#include "dq/io/scene.hpp"

namespace {
using dq::fuzz::check;
}  // namespace

extern const char* const dqkit_fuzz_hint;  // the file format: "gltf", "fbx", ...

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  dq::ImportOptions options;
  options.sample_rate = 10;
  options.isolate = false;  // in-process, so that coverage guides the fuzzer through dqkit's code
  const dq::Expected<dq::ImportedScene> scene = dq::import_scene_from_memory({data, size}, dqkit_fuzz_hint, options);
  if (!scene) {
    check(!scene.error().message.empty(), "errors say something");
    return 0;
  }
  for (const auto& q : scene->skeleton.rest_pose()) check(q.is_unit(1e-6), "rest transforms are unit");
  for (const auto& m : scene->meshes) {
    for (std::uint32_t i : m.indices) check(i < m.positions.size(), "indices in range");
    for (const auto& inf : m.influences) check(inf.joint < scene->skeleton.size(), "influence joints in range");
  }
  for (const auto& a : scene->animations)
    for (const auto& q : a.animation.locals) check(q.is_unit(1e-6), "animated transforms are unit");
  return 0;
}

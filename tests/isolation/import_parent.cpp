// Imports one file through the isolated importer with generous limits: the parent that
// Isolation.WorkerDiesWithItsParent kills while its worker hangs.
#include <cstdio>

#include "dq/io/scene.hpp"

int main(int argc, char** argv) {
  if (argc != 2) return 2;
  dq::ImportOptions options;
  options.timeout_seconds = 600;
  options.cpu_limit_seconds = 600;
  const dq::Expected<dq::ImportedScene> scene = dq::import_scene(argv[1], options);
  std::puts(scene ? "imported" : scene.error().message.c_str());
  return scene ? 0 : 1;
}

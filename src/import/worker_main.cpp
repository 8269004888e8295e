// dqkit-import-worker: runs Assimp for dqkit::import in a process of its own. Started by
// src/import/isolation.cpp with the socket to the caller as descriptor 3 and /dev/null as 0 to 2;
// the caller limits its memory and CPU time before sending the request.
#include <signal.h>
#include <sys/prctl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <string>
#include <string_view>

#include "import_internal.hpp"

namespace {

constexpr int kChannel = 3;

bool read_all(int fd, std::string& out) {
  char buffer[65536];
  while (true) {
    const ssize_t k = ::read(fd, buffer, sizeof buffer);
    if (k < 0 && errno == EINTR) continue;
    if (k < 0) return false;
    if (k == 0) return true;
    out.append(buffer, static_cast<std::size_t>(k));
  }
}

bool write_all(int fd, std::string_view data) {
  while (!data.empty()) {
    const ssize_t k = ::write(fd, data.data(), data.size());
    if (k < 0 && errno == EINTR) continue;
    if (k <= 0) return false;
    data.remove_prefix(static_cast<std::size_t>(k));
  }
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  // Die with the caller, even when it is killed with SIGKILL. Armed first, then checked: the
  // caller may have died before it was armed, and then this process has another parent already.
  ::prctl(PR_SET_PDEATHSIG, SIGKILL);
  if (argc != 3 || std::string_view(argv[1]) != "--parent") {
    std::fprintf(stderr, "dqkit-import-worker: started by dqkit's importer (dq::import_scene), not by hand\n");
    return 2;
  }
  if (std::to_string(::getppid()) != argv[2]) return 3;
  std::string bytes;
  if (!read_all(kChannel, bytes)) return 4;
  const std::optional<dq::detail::ImportRequest> request = dq::detail::decode_request(bytes);
  if (!request) return 2;
  dq::ImportOptions options;
  options.sample_rate = request->sample_rate;
  options.meshes = request->meshes;
  options.lights_and_cameras = request->lights_and_cameras;
  options.result_limit_mb = request->result_limit_mb;
  options.isolate = false;
  const std::string source = request->from_memory ? "<memory." + request->path_or_hint + ">" : request->path_or_hint;
  const dq::Expected<dq::ImportedScene> result = [&]() -> dq::Expected<dq::ImportedScene> {
    try {
      return request->from_memory ? dq::detail::import_memory_in_process(request->data, request->path_or_hint, options)
                                  : dq::detail::import_file_in_process(request->path_or_hint, options);
    } catch (const std::exception& e) {
      return dq::Error{source + ": the importer failed: " + e.what()};
    }
  }();
  return write_all(kChannel, dq::detail::encode_response(result)) ? 0 : 4;
}

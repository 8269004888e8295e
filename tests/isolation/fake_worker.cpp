// A misbehaving stand-in for dqkit-import-worker, to show that the caller's limits and checks hold
// whatever the worker does. DQKIT_FAKE_WORKER_MODE says how it misbehaves; descriptor 3 is the
// socket to the caller, as for the real worker.
#include <dirent.h>
#include <sys/resource.h>
#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

#include "dq/core/dual_quaternion.hpp"

namespace {

void send(std::string_view bytes) {
  while (!bytes.empty()) {
    const ssize_t k = ::write(3, bytes.data(), bytes.size());
    if (k <= 0) std::exit(4);
    bytes.remove_prefix(static_cast<std::size_t>(k));
  }
}

template <class T>
void put(std::string& out, T v) {
  out.append(reinterpret_cast<const char*>(&v), sizeof v);
}

/// A well-framed response: the length, then the payload.
void respond(const std::string& payload) {
  std::string framed;
  put<std::uint64_t>(framed, payload.size());
  send(framed + payload);
}

void respond_error(const std::string& message) {
  std::string payload = "E";
  put<std::uint64_t>(payload, message.size());
  respond(payload + message);
}

}  // namespace

int main() {
  const char* env = std::getenv("DQKIT_FAKE_WORKER_MODE");
  const std::string_view mode = env ? env : "";
  if (mode == "spin") {
    volatile std::uint64_t spins = 0;
    while (true) spins = spins + 1;
  }
  if (mode == "hang") {
    while (true) ::pause();
  }
  if (mode == "allocate") {  // 2 GB, touched
    std::vector<char*> blocks;
    for (int i = 0; i < 128; ++i) {
      char* b = static_cast<char*>(std::malloc(16u << 20));
      if (!b) return 5;
      std::memset(b, 1, 16u << 20);
      blocks.push_back(b);
    }
    respond_error("allocated 2 GB: no memory limit");
    return 0;
  }
  if (mode == "limits") {  // reports the limits it runs under, once the request has begun (they are set before it is sent)
    char first = 0;
    if (::read(3, &first, 1) != 1) return 4;
    rlimit as{}, cpu{};
    ::getrlimit(RLIMIT_AS, &as);
    ::getrlimit(RLIMIT_CPU, &cpu);
    respond_error("limits: AS " + std::to_string(as.rlim_cur) + " " + std::to_string(as.rlim_max) + ", CPU " + std::to_string(cpu.rlim_cur) +
                  " " + std::to_string(cpu.rlim_max));
    return 0;
  }
  if (mode == "huge_length") {  // announces an exabyte
    std::string header;
    put<std::uint64_t>(header, std::uint64_t{1} << 60);
    send(header + "S");
    return 0;
  }
  if (mode == "overlong") {  // sends more than it announces
    std::string payload = "E";
    put<std::uint64_t>(payload, 2);
    respond(payload + "no" + "trailing bytes");
    return 0;
  }
  if (mode == "many_meshes") {  // a payload under the size limit whose mesh count needs more memory than allowed
    std::string p = "S";
    put<std::uint64_t>(p, 1);  // one joint
    put<std::uint64_t>(p, 4);
    p += "root";
    put<int>(p, -1);
    put(p, dq::DualQuaternion<double>::identity());
    put<std::uint8_t>(p, 0);
    put<std::uint64_t>(p, 1);  // joint_scale
    put<double>(p, 1.0);
    const std::uint64_t meshes = 13000;
    put<std::uint64_t>(p, meshes);
    p.append(meshes * (8 + 8 * 8 + sizeof(int)), '\0');  // empty meshes
    respond(p);
    return 0;
  }
  if (mode == "fds") {  // which descriptors it inherited
    std::string open;
    DIR* d = ::opendir("/proc/self/fd");
    while (dirent* e = ::readdir(d))
      if (e->d_name[0] != '.' && std::atoi(e->d_name) != ::dirfd(d)) open += std::string(open.empty() ? "" : " ") + e->d_name;
    ::closedir(d);
    respond_error("fds: " + open);
    return 0;
  }
  return 9;
}

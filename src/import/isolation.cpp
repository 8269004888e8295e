// Isolated import: Assimp runs in dqkit-import-worker, an executable of its own started with
// posix_spawn. Not fork(): the caller may be multithreaded (Python), and a forked copy of such a
// process may block on a lock some other thread held (docs/design.md).
#include <dlfcn.h>
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <optional>

#include "dq/util/sanitizers.hpp"
#include "import_internal.hpp"

extern char** environ;

namespace dq::detail {

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

constexpr const char* kWorkerName = "dqkit-import-worker";

bool is_executable_file(const fs::path& p) {
  std::error_code ec;
  return fs::is_regular_file(p, ec) && ::access(p.c_str(), X_OK) == 0;
}

/// The directory of the running program, and that of the shared library holding this code when
/// dqkit::import is a shared library.
std::vector<fs::path> module_directories() {
  std::vector<fs::path> dirs;
  std::error_code ec;
  const fs::path program = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) dirs.push_back(program.parent_path());
  static const char anchor = 0;
  Dl_info info{};
  // For code in the program itself dladdr gives argv[0], which may be relative: only absolute
  // names of shared objects are used.
  if (::dladdr(&anchor, &info) != 0 && info.dli_fname && info.dli_fname[0] == '/') {
    const fs::path library = fs::canonical(info.dli_fname, ec);
    if (!ec && library != program) dirs.push_back(library.parent_path());
  }
  return dirs;
}

Expected<fs::path> find_worker(const ImportOptions& options) {
  auto given = [](const fs::path& p, const char* by) -> Expected<fs::path> {
    if (is_executable_file(p)) return p;
    return Error{"the import worker '" + p.string() + "' (from " + by + ") is not an executable file"};
  };
  if (!options.worker_path.empty()) return given(options.worker_path, "ImportOptions::worker_path");
  if (const char* env = std::getenv("DQKIT_IMPORT_WORKER"); env && *env) return given(env, "DQKIT_IMPORT_WORKER");
  std::vector<fs::path> candidates;
  for (const fs::path& dir : module_directories())
    for (const char* relative : {DQKIT_WORKER_FROM_BINDIR, DQKIT_WORKER_FROM_LIBDIR})
      candidates.push_back((dir / relative / kWorkerName).lexically_normal());
  candidates.emplace_back(DQKIT_WORKER_INSTALLED);
  std::string tried;
  for (const fs::path& p : candidates) {
    if (is_executable_file(p)) return p;
    tried += (tried.empty() ? "" : ", ") + p.string();
  }
  return Error{std::string("cannot find the import worker ") + kWorkerName + " (looked for " + tried +
               "); set DQKIT_IMPORT_WORKER or ImportOptions::worker_path"};
}

/// Starts the worker with the socket `channel` as its descriptor 3, /dev/null as 0 to 2, no other
/// descriptor of this process, an empty signal mask and default signal dispositions. Returns the
/// errno value of a failure.
int spawn_worker(const fs::path& worker, int channel, pid_t& pid) {
  posix_spawn_file_actions_t actions;
  posix_spawnattr_t attributes;
  ::posix_spawn_file_actions_init(&actions);
  ::posix_spawnattr_init(&attributes);
  ::posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  ::posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
  ::posix_spawn_file_actions_addopen(&actions, 2, "/dev/null", O_WRONLY, 0);
  ::posix_spawn_file_actions_adddup2(&actions, channel, 3);
  ::posix_spawn_file_actions_addclosefrom_np(&actions, 4);
  sigset_t none, all;
  ::sigemptyset(&none);
  ::sigfillset(&all);
  ::posix_spawnattr_setsigmask(&attributes, &none);
  ::posix_spawnattr_setsigdefault(&attributes, &all);
  ::posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETSIGMASK | POSIX_SPAWN_SETSIGDEF);
  std::string program = worker.string(), flag = "--parent", parent = std::to_string(::getpid());
  char* argv[] = {program.data(), flag.data(), parent.data(), nullptr};
  const int error = ::posix_spawn(&pid, program.c_str(), &actions, &attributes, argv, environ);
  ::posix_spawnattr_destroy(&attributes);
  ::posix_spawn_file_actions_destroy(&actions);
  return error;
}

/// The worker's `resource` limit lowered to `soft` and `hard`, or to what its inherited hard limit
/// allows: an unprivileged process cannot raise a hard limit (a shell's `ulimit -v` or `ulimit -t`
/// sets one), and the inherited limit already bounds the worker. `gap` keeps the soft limit that
/// far below the hard one where both are clamped (the CPU limit's SIGXCPU before its SIGKILL).
/// Returns the soft limit set, or nothing (errno says why).
std::optional<rlim_t> lower_limit(pid_t pid, __rlimit_resource resource, rlim_t soft, rlim_t hard, rlim_t gap) {
  rlimit inherited{};
  if (::prlimit(pid, resource, nullptr, &inherited) != 0) return std::nullopt;
  if (inherited.rlim_max != RLIM_INFINITY && hard > inherited.rlim_max) {
    hard = inherited.rlim_max;
    soft = std::min(soft, hard > gap ? hard - gap : hard);
  }
  const rlimit limit{soft, hard};
  if (::prlimit(pid, resource, &limit, nullptr) != 0) return std::nullopt;
  return soft;
}

/// Limits the worker before it is sent anything (it waits for the request before doing any work).
/// Returns the CPU seconds it may use (0: no limit), for the message when it uses them up.
Expected<double> limit_worker(pid_t pid, const ImportOptions& options) {
  double cpu_seconds = 0;
  if (options.cpu_limit_seconds > 0) {
    const auto seconds = static_cast<rlim_t>(std::ceil(std::min(options.cpu_limit_seconds, 1e9)));
    // SIGXCPU at the soft limit, SIGKILL a second later (at the hard one)
    const std::optional<rlim_t> set = lower_limit(pid, RLIMIT_CPU, seconds, seconds + 1, 1);
    if (!set) return Error{std::string("cannot limit its CPU time: ") + std::strerror(errno)};
    cpu_seconds = *set == seconds ? options.cpu_limit_seconds : static_cast<double>(*set);
  }
  if (!kSanitizedBuild && options.memory_limit_mb > 0) {
    const rlim_t bytes = static_cast<rlim_t>(std::min<std::size_t>(options.memory_limit_mb, std::size_t{1} << 40)) << 20;
    if (!lower_limit(pid, RLIMIT_AS, bytes, bytes, 0)) return Error{std::string("cannot limit its memory: ") + std::strerror(errno)};
  }
  return cpu_seconds;
}

enum class Exchange { complete, ended_early, timed_out, too_large, overlong };

/// Sends the request and receives the response until the worker closes its side or the deadline
/// passes. Allocates at most `budget` bytes for the response, whatever the worker sends.
Exchange talk_to_worker(int socket, const std::string& request, std::string& payload, std::uint64_t& length, std::size_t budget,
                  Clock::time_point deadline) {
  ::fcntl(socket, F_SETFL, ::fcntl(socket, F_GETFL) | O_NONBLOCK);
  std::size_t sent = 0;
  bool sending = true;
  unsigned char header[sizeof length];
  std::size_t header_bytes = 0;
  while (true) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
    if (left <= 0) return Exchange::timed_out;
    pollfd p{socket, static_cast<short>(POLLIN | (sending ? POLLOUT : 0)), 0};
    const int ready = ::poll(&p, 1, static_cast<int>(std::min<long long>(left, 1000)));
    if (ready <= 0) continue;  // timeout or EINTR: the deadline is checked above
    if (sending && (p.revents & POLLOUT)) {
      const ssize_t k = ::send(socket, request.data() + sent, request.size() - sent, MSG_NOSIGNAL);
      if (k > 0) sent += static_cast<std::size_t>(k);
      if (k < 0 && errno != EAGAIN && errno != EINTR) sending = false;  // the worker is gone; its exit status says why
      if (sent == request.size()) {
        ::shutdown(socket, SHUT_WR);
        sending = false;
      }
    }
    if (!(p.revents & (POLLIN | POLLHUP | POLLERR))) continue;
    char buffer[65536];
    const ssize_t k = ::recv(socket, buffer, sizeof buffer, 0);
    if (k < 0 && (errno == EAGAIN || errno == EINTR)) continue;
    if (k <= 0) return header_bytes == sizeof header && payload.size() == length ? Exchange::complete : Exchange::ended_early;
    std::string_view data(buffer, static_cast<std::size_t>(k));
    if (header_bytes < sizeof header) {
      const std::size_t n = std::min(data.size(), sizeof header - header_bytes);
      std::memcpy(header + header_bytes, data.data(), n);
      header_bytes += n;
      data.remove_prefix(n);
      if (header_bytes < sizeof header) continue;
      std::memcpy(&length, header, sizeof length);
      if (length > budget) return Exchange::too_large;
      payload.reserve(static_cast<std::size_t>(length));
    }
    if (data.size() > length - payload.size()) return Exchange::overlong;
    payload.append(data);
  }
}

}  // namespace

Expected<ImportedScene> run_isolated(const ImportRequest& request, const std::string& source, const ImportOptions& options) {
  const Expected<fs::path> worker = find_worker(options);
  if (!worker) return Error{source + ": " + worker.error().message};
  int sockets[2];
  // Close-on-exec: another thread's worker, spawned meanwhile, must not inherit this channel.
  if (::socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, sockets) != 0)
    return Error{source + ": cannot create a socket for the importer: " + std::strerror(errno)};
  pid_t pid = -1;
  const int spawn_error = spawn_worker(*worker, sockets[1], pid);
  ::close(sockets[1]);
  if (spawn_error != 0) {
    ::close(sockets[0]);
    return Error{source + ": cannot start the importer " + worker->string() + ": " + std::strerror(spawn_error)};
  }
  const Clock::time_point deadline =
      Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(std::clamp(options.timeout_seconds, 0.0, 1e9)));
  const std::size_t budget = std::min<std::size_t>(options.result_limit_mb, std::size_t{1} << 40) << 20;
  std::string payload;
  std::uint64_t length = 0;
  const Expected<double> limited = limit_worker(pid, options);
  const Exchange exchanged = limited ? talk_to_worker(sockets[0], encode_request(request), payload, length, budget, deadline) : Exchange::ended_early;
  ::close(sockets[0]);
  // Reap the worker; one that closed its side but does not exit is killed at the deadline.
  bool timed_out = exchanged == Exchange::timed_out;
  if (exchanged != Exchange::complete) ::kill(pid, SIGKILL);
  int status = 0;
  bool reaped = false;
  while (!reaped) {
    const pid_t r = ::waitpid(pid, &status, exchanged == Exchange::complete && !timed_out ? WNOHANG : 0);
    if (r == pid) {
      reaped = true;
    } else if (r < 0 && errno != EINTR) {
      break;  // ECHILD: the program reaps its children itself (SIGCHLD ignored); the status is unknown
    } else if (r == 0) {
      if (Clock::now() >= deadline) {
        ::kill(pid, SIGKILL);
        timed_out = true;
      } else {
        ::poll(nullptr, 0, 5);
      }
    }
  }
  if (!limited) return Error{source + ": cannot start the importer: " + limited.error().message};
  if (timed_out) return Error{source + ": the importer did not finish within " + std::to_string(options.timeout_seconds) + " s"};
  if (exchanged == Exchange::too_large)
    return Error{source + ": the importer's result (" + std::to_string(length >> 20) + " MB) is larger than the " +
                 std::to_string(budget >> 20) + " MB allowed (ImportOptions::result_limit_mb)"};
  if (exchanged == Exchange::overlong) return Error{source + ": the isolated importer returned a damaged result"};
  if (reaped && WIFSIGNALED(status)) {
    if (WTERMSIG(status) == SIGXCPU)
      return Error{source + ": the importer used up its CPU time limit (" + std::to_string(*limited) + " s)"};
    return Error{source + ": the importer (Assimp) crashed on this file (" + std::string(::strsignal(WTERMSIG(status))) + ")"};
  }
  if ((reaped && WEXITSTATUS(status) != 0) || exchanged != Exchange::complete)
    return Error{source + ": the importer failed on this file (out of memory?)"};
  return decode_response(payload, source, budget);
}

}  // namespace dq::detail

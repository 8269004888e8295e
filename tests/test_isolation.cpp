// The isolated importer's process boundary: the worker is spawned (no fork of the caller) with
// nothing inherited but its channel, dies with its parent, and runs under CPU, memory and
// wall-clock limits; whatever it sends back, the caller allocates within its budget. Misbehaving
// workers are played by tests/isolation/fake_worker.cpp.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <thread>

#include "dq/io/scene.hpp"
#include "dq/util/sanitizers.hpp"

namespace {

using namespace dq;
namespace fs = std::filesystem;
using namespace std::chrono_literals;


/// A scratch directory with a file to import (the fake workers never read it).
class Isolation : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("dqkit_isolation_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
    std::ofstream(dir_ / "model.gltf") << "{}";
  }
  void TearDown() override {
    ::unsetenv("DQKIT_FAKE_WORKER_MODE");
    ::unsetenv("DQKIT_IMPORT_WORKER");
    fs::remove_all(dir_);
  }
  /// Imports model.gltf through the fake worker in `mode`.
  Expected<ImportedScene> import_with_fake(const char* mode, ImportOptions options = {}) {
    ::setenv("DQKIT_FAKE_WORKER_MODE", mode, 1);
    options.worker_path = DQKIT_FAKE_WORKER;
    return import_scene(dir_ / "model.gltf", options);
  }
  fs::path dir_;
};

std::string message(const Expected<ImportedScene>& e) { return e ? "(imported)" : e.error().message; }

TEST_F(Isolation, TheWorkerInheritsOnlyItsChannel) {
  // A descriptor that is not close-on-exec, as a careless host program might leave one open.
  const int null = ::open("/dev/null", O_RDONLY);
  const int leaked = ::fcntl(null, F_DUPFD, 20);
  ::close(null);
  ASSERT_GE(leaked, 20);
  const Expected<ImportedScene> s = import_with_fake("fds");
  ::close(leaked);
  EXPECT_EQ(message(s), "fds: 0 1 2 3");
}

TEST_F(Isolation, CpuTimeIsLimited) {
  ImportOptions options;
  options.cpu_limit_seconds = 1;
  options.timeout_seconds = 60;
  const auto start = std::chrono::steady_clock::now();
  const Expected<ImportedScene> s = import_with_fake("spin", options);
  EXPECT_NE(message(s).find("model.gltf: the importer used up its CPU time limit (1.0"), std::string::npos) << message(s);
  EXPECT_LT(std::chrono::steady_clock::now() - start, 20s);
}

TEST_F(Isolation, MemoryIsLimited) {
  if (kSanitizedBuild) GTEST_SKIP() << "no address-space limit under sanitizers (they reserve terabytes of address space)";
  ImportOptions options;
  options.memory_limit_mb = 256;
  const Expected<ImportedScene> s = import_with_fake("allocate", options);
  EXPECT_NE(message(s).find("model.gltf: the importer failed on this file (out of memory?)"), std::string::npos) << message(s);
}

TEST_F(Isolation, TheWorkerGetsTheRequestedLimits) {
  if (kSanitizedBuild) GTEST_SKIP() << "no address-space limit under sanitizers (they reserve terabytes of address space)";
  ImportOptions options;
  options.memory_limit_mb = 3000;
  options.cpu_limit_seconds = 100;
  EXPECT_EQ(message(import_with_fake("limits", options)), "limits: AS " + std::to_string(3000ull << 20) + " " +
                                                              std::to_string(3000ull << 20) + ", CPU 100 101");
}

TEST_F(Isolation, LimitsBelowTheRequestedOnesAreKept) {
  // A shell's `ulimit -v` or `ulimit -t` sets hard limits the worker inherits and, unprivileged,
  // cannot raise: it runs under those (the CPU's soft limit a second below, for SIGXCPU first)
  // instead of failing to start. Played in a child process, whose lowered limits die with it.
  if (kSanitizedBuild) GTEST_SKIP() << "no address-space limit under sanitizers (they reserve terabytes of address space)";
  ::setenv("DQKIT_FAKE_WORKER_MODE", "limits", 1);
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    const rlim_t six_gb = rlim_t{6} << 30;
    const rlimit lower_memory{six_gb, six_gb}, lower_cpu{60, 60};
    if (::setrlimit(RLIMIT_AS, &lower_memory) != 0 || ::setrlimit(RLIMIT_CPU, &lower_cpu) != 0) ::_exit(2);
    ImportOptions options;
    options.worker_path = DQKIT_FAKE_WORKER;
    options.memory_limit_mb = 8192;
    options.cpu_limit_seconds = 3600;
    const Expected<ImportedScene> s = import_scene(dir_ / "model.gltf", options);
    const std::string expected = "limits: AS " + std::to_string(six_gb) + " " + std::to_string(six_gb) + ", CPU 59 60";
    ::_exit(!s && s.error().message == expected ? 0 : 1);
  }
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "status " << status;
}

TEST_F(Isolation, WallClockIsLimited) {
  ImportOptions options;
  options.timeout_seconds = 0.5;
  const auto start = std::chrono::steady_clock::now();
  const Expected<ImportedScene> s = import_with_fake("hang", options);
  EXPECT_NE(message(s).find("the importer did not finish within 0.5"), std::string::npos) << message(s);
  EXPECT_LT(std::chrono::steady_clock::now() - start, 10s);
}

TEST_F(Isolation, AnnouncedResultSizeIsCheckedBeforeAllocating) {
  const Expected<ImportedScene> s = import_with_fake("huge_length");
  EXPECT_NE(message(s).find("the importer's result (1099511627776 MB) is larger than the 2048 MB allowed (ImportOptions::result_limit_mb)"),
            std::string::npos)
      << message(s);
}

TEST_F(Isolation, CountsAreCheckedAgainstTheBudgetBeforeAllocating) {
  ImportOptions options;
  options.result_limit_mb = 1;  // the payload (0.94 MB) fits; 13000 meshes in memory do not
  const Expected<ImportedScene> s = import_with_fake("many_meshes", options);
  EXPECT_NE(message(s).find("model.gltf: the importer's result needs more than the 1 MB allowed (ImportOptions::result_limit_mb)"),
            std::string::npos)
      << message(s);
}

TEST_F(Isolation, MoreBytesThanAnnouncedIsADamagedResult) {
  EXPECT_EQ(message(import_with_fake("overlong")), (dir_ / "model.gltf").string() + ": the isolated importer returned a damaged result");
}

TEST_F(Isolation, TheWorkerIsFoundOrTheErrorSaysWhere) {
  ImportOptions options;
  options.worker_path = "/nonexistent/dqkit-import-worker";
  EXPECT_NE(message(import_scene(dir_ / "model.gltf", options)).find("'/nonexistent/dqkit-import-worker' (from ImportOptions::worker_path) is not an executable file"),
            std::string::npos);
  ::setenv("DQKIT_IMPORT_WORKER", DQKIT_FAKE_WORKER, 1);  // the environment overrides the lookup
  ::setenv("DQKIT_FAKE_WORKER_MODE", "fds", 1);
  EXPECT_EQ(message(import_scene(dir_ / "model.gltf")), "fds: 0 1 2 3");
  ::setenv("DQKIT_IMPORT_WORKER", "/nonexistent/worker", 1);
  EXPECT_NE(message(import_scene(dir_ / "model.gltf")).find("(from DQKIT_IMPORT_WORKER)"), std::string::npos);
}

/// A glTF whose buffer is a FIFO that nobody writes: opening it blocks Assimp in the real worker
/// (a FIFO given as the file itself is refused before any worker starts).
fs::path stuck_gltf(const fs::path& dir) {
  std::ofstream(dir / "stuck.gltf") << R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}], "buffers": [{"uri": "stuck.bin", "byteLength": 36}],
    "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36}],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "max": [1, 1, 1], "min": [0, 0, 0]}]})";
  EXPECT_EQ(::mkfifo((dir / "stuck.bin").c_str(), 0600), 0);
  return dir / "stuck.gltf";
}

TEST_F(Isolation, ARealWorkerStuckInTheFileIsStoppedAtTheDeadline) {
  ImportOptions options;
  options.timeout_seconds = 0.5;
  EXPECT_NE(message(import_scene(stuck_gltf(dir_), options)).find("stuck.gltf: the importer did not finish within 0.5"), std::string::npos);
}

TEST_F(Isolation, AFifoOrDeviceIsRefusedWithoutWaiting) {
  // A FIFO held the worker until the deadline (120 s by default) before it was refused up front.
  const fs::path fifo = dir_ / "fifo.gltf";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const auto start = std::chrono::steady_clock::now();
  EXPECT_NE(message(import_scene(fifo)).find("fifo.gltf: is not a regular file"), std::string::npos);
  EXPECT_NE(message(import_scene("/dev/zero")).find("/dev/zero: is not a regular file"), std::string::npos);
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(5));
  ImportOptions options;
  options.timeout_seconds = 0;
  EXPECT_NE(message(import_scene(dir_ / "model.gltf", options)).find("timeout_seconds must be positive"), std::string::npos);
}

/// The state letter of a process (R, S, Z, ...), or nothing once it is gone.
std::optional<char> process_state(pid_t pid) {
  std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
  std::string line;
  if (!std::getline(stat, line)) return std::nullopt;
  const std::size_t paren = line.rfind(')');
  return paren + 2 < line.size() ? std::optional<char>(line[paren + 2]) : std::nullopt;
}

/// The first child of `parent` found in /proc, or −1.
pid_t child_of(pid_t parent) {
  for (const auto& e : fs::directory_iterator("/proc")) {
    const std::string name = e.path().filename().string();
    if (name.find_first_not_of("0123456789") != std::string::npos) continue;
    std::ifstream stat(e.path() / "stat");
    std::string line;
    if (!std::getline(stat, line)) continue;
    const std::size_t paren = line.rfind(')');
    if (paren == std::string::npos) continue;
    char state = 0;
    long ppid = 0;
    if (std::sscanf(line.c_str() + paren + 1, " %c %ld", &state, &ppid) == 2 && ppid == parent) return static_cast<pid_t>(std::stol(name));
  }
  return -1;
}

TEST_F(Isolation, WorkerDiesWithItsParent) {
  // The parent imports a glTF whose buffer is a FIFO (its worker hangs opening it) and is killed
  // with SIGKILL: no orphan may remain.
  std::string program = DQKIT_IMPORT_PARENT, file = stuck_gltf(dir_).string();
  char* argv[] = {program.data(), file.data(), nullptr};
  pid_t parent = -1;
  ASSERT_EQ(::posix_spawn(&parent, program.c_str(), nullptr, nullptr, argv, environ), 0);
  pid_t worker = -1;
  for (int i = 0; i < 1000 && worker < 0; ++i) {
    worker = child_of(parent);
    if (worker < 0) std::this_thread::sleep_for(10ms);
  }
  ASSERT_GT(worker, 0) << "the parent started no worker";
  // Wait until the worker hangs in Assimp, opening the FIFO (not reading its request: that would
  // end anyway when the parent's end of the socket closes).
  const std::string blocked_in_open = std::to_string(SYS_openat) + " ";
  bool hanging = false;
  for (int i = 0; i < 500 && !hanging; ++i) {
    std::ifstream syscall("/proc/" + std::to_string(worker) + "/syscall");
    std::string line;
    hanging = std::getline(syscall, line) && line.rfind(blocked_in_open, 0) == 0;
    if (!hanging) std::this_thread::sleep_for(10ms);
  }
  ASSERT_TRUE(hanging) << "the worker did not reach the FIFO";
  ::kill(parent, SIGKILL);
  int status = 0;
  ::waitpid(parent, &status, 0);
  bool gone = false;
  for (int i = 0; i < 500 && !gone; ++i) {
    const std::optional<char> state = process_state(worker);
    gone = !state || *state == 'Z';  // a zombie is dead (it waits for its new parent to reap it)
    if (!gone) std::this_thread::sleep_for(10ms);
  }
  EXPECT_TRUE(gone) << "worker " << worker << " outlived its parent";
  if (!gone) ::kill(worker, SIGKILL);
}

}  // namespace

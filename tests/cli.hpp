// Running the command-line tool from the tests as a user runs it from a shell.
#pragma once

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace dq::test {

struct CliOutcome {
  int code;  ///< the exit code; −1 when the command did not exit normally
  std::string out, err;
};

inline std::string read_file(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

/// Runs a shell command line. Standard error is collected in a file, so that it is not a terminal
/// (the tool shows no progress display then), removed afterwards.
inline CliOutcome run_shell(const std::string& line) {
  const auto err_file = std::filesystem::temp_directory_path() / ("dqkit_cli_stderr_" + std::to_string(::getpid()) + ".txt");
  CliOutcome r{-1, "", ""};
  FILE* p = popen(("(" + line + ") 2>" + err_file.string()).c_str(), "r");
  if (!p) return {-1, "", "popen failed"};
  char buf[65536];
  std::size_t n;
  while ((n = fread(buf, 1, sizeof buf, p)) > 0) r.out.append(buf, n);
  const int status = pclose(p);
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.err = read_file(err_file);
  std::filesystem::remove(err_file);
  return r;
}

/// Whether process `pid` has a file open for writing its output in `dir`: an anonymous file
/// (O_TMPFILE, "dir/#inode (deleted)") or a named temporary file (".NAME.tmpN").
inline bool writes_output_in(pid_t pid, const std::filesystem::path& dir) {
  std::error_code ec;
  for (const auto& fd : std::filesystem::directory_iterator("/proc/" + std::to_string(pid) + "/fd", ec)) {
    const std::string target = std::filesystem::read_symlink(fd.path(), ec).string();
    if (!ec && target.rfind(dir.string() + "/", 0) == 0 &&
        (target.ends_with(" (deleted)") || target.find(".tmp") != std::string::npos))
      return true;
  }
  return false;
}

/// Whether the file system of `dir` has anonymous files (O_TMPFILE), which OutputFile uses.
inline bool has_anonymous_files(const std::filesystem::path& dir) {
  const int fd = ::open(dir.c_str(), O_TMPFILE | O_WRONLY | O_CLOEXEC, 0600);
  if (fd < 0) return false;
  ::close(fd);
  return true;
}

}  // namespace dq::test

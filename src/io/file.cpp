#include "dq/io/file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <random>
#include <string>

namespace dq {

Status write_file_atomically(const std::filesystem::path& path, std::string_view contents, Overwrite overwrite) {
  std::error_code ec;
  const auto status = std::filesystem::status(path, ec);
  if (std::filesystem::exists(status)) {
    if (std::filesystem::is_directory(status)) return Error{path.string() + ": is a directory"};
    if (overwrite == Overwrite::refuse) return Error{path.string() + ": already exists (use --force to replace it)"};
  }
  const std::filesystem::path dir = path.parent_path().empty() ? std::filesystem::path(".") : path.parent_path();
  // A unique temporary name in the same directory, so that rename() is atomic.
  std::random_device rd;
  const std::filesystem::path temporary = dir / ("." + path.filename().string() + ".tmp" + std::to_string(rd()));
  const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
  if (fd < 0) return Error{temporary.string() + ": cannot create: " + std::strerror(errno)};
  auto fail = [&](const std::string& what) {
    const int saved = errno;
    ::close(fd);
    ::unlink(temporary.c_str());
    return Error{path.string() + ": " + what + ": " + std::strerror(saved)};
  };
  std::size_t done = 0;
  while (done < contents.size()) {
    const ssize_t n = ::write(fd, contents.data() + done, contents.size() - done);
    if (n < 0) {
      if (errno == EINTR) continue;
      return fail("write failed");
    }
    done += static_cast<std::size_t>(n);
  }
  if (::fsync(fd) != 0) return fail("fsync failed");
  if (::close(fd) != 0) {
    ::unlink(temporary.c_str());
    return Error{path.string() + ": close failed: " + std::strerror(errno)};
  }
  if (::rename(temporary.c_str(), path.c_str()) != 0) {
    const int saved = errno;
    ::unlink(temporary.c_str());
    return Error{path.string() + ": cannot replace: " + std::strerror(saved)};
  }
  return {};
}

}  // namespace dq

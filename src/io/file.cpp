#include "dq/io/file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <random>
#include <utility>

namespace dq {

namespace {

// Temporary files in progress, for the signal handler: fixed storage (no allocation in the
// handler), a slot is claimed with a compare-and-swap (0 free, 1 being filled, 2 live).
struct Slot {
  std::atomic<int> state{0};
  char path[4096]{};
};
std::array<Slot, 64> g_slots;

int claim_slot(const std::filesystem::path& temporary) {
  const std::string& s = temporary.native();
  if (s.size() >= sizeof(Slot::path)) return -1;
  for (std::size_t i = 0; i < g_slots.size(); ++i) {
    int expected = 0;
    if (g_slots[i].state.compare_exchange_strong(expected, 1)) {
      std::memcpy(g_slots[i].path, s.c_str(), s.size() + 1);
      g_slots[i].state.store(2);
      return static_cast<int>(i);
    }
  }
  return -1;  // more than 64 files at once: still written safely, just not cleaned on a signal
}
void release_slot(int slot) {
  if (slot >= 0) g_slots[static_cast<std::size_t>(slot)].state.store(0);
}

extern "C" void remove_temporaries_and_die(int sig) {
  for (Slot& s : g_slots)
    if (s.state.load() == 2) ::unlink(s.path);
  std::signal(sig, SIG_DFL);
  std::raise(sig);
}

std::string reason(int error) { return std::strerror(error); }

std::filesystem::path directory_of(const std::filesystem::path& target) {
  return target.parent_path().empty() ? std::filesystem::path(".") : target.parent_path();
}

/// Gives a temporary file a fresh name beside `target`: `make(name)` (create the file with O_EXCL,
/// or link an anonymous one) under up to 16 random names until one is free. Each name enters the
/// signal handler's table before `make` runs, so that no signal, on any thread, lands between the
/// file's creation and its registration; a name that turns out to be taken leaves the table at once.
/// Returns 0, or the errno of the last attempt (`temporary` is then empty and `slot` −1).
template <class Make>
int name_temporary(const std::filesystem::path& target, std::filesystem::path& temporary, int& slot, Make make) {
  std::random_device rd;
  int error = EEXIST;
  for (int attempt = 0; attempt < 16 && error == EEXIST; ++attempt) {
    temporary = directory_of(target) / ("." + target.filename().string() + ".tmp" + std::to_string(rd()));
    slot = claim_slot(temporary);
    error = make(temporary.c_str());
    if (error != 0) release_slot(std::exchange(slot, -1));
  }
  if (error != 0) temporary.clear();
  return error;
}

constexpr const char* kNotRegular =
    ": is not a regular file (a symbolic link, device, FIFO or socket): dqkit writes only regular files, never through or over one";
constexpr const char* kAlreadyExists = ": already exists; it is replaced only when asked (--force on the command line, overwrite=True in Python, Overwrite::allow in C++)";

}  // namespace

void remove_temporary_files_on_signals() {
  for (int sig : {SIGINT, SIGTERM, SIGHUP, SIGQUIT, SIGXFSZ}) {
    struct sigaction old {};
    if (::sigaction(sig, nullptr, &old) != 0 || old.sa_handler != SIG_DFL) continue;  // e.g. nohup's SIGHUP
    struct sigaction action {};
    action.sa_handler = remove_temporaries_and_die;
    sigemptyset(&action.sa_mask);
    ::sigaction(sig, &action, nullptr);
  }
}

Expected<OutputFile> OutputFile::create(const std::filesystem::path& path, Overwrite overwrite) {
  const std::string name = path.string();
  if (name.empty()) return Error{"an empty file name"};
  struct stat st {};
  if (::lstat(path.c_str(), &st) == 0) {
    if (S_ISDIR(st.st_mode)) return Error{name + ": is a directory"};
    if (!S_ISREG(st.st_mode)) return Error{name + kNotRegular};
    if (overwrite == Overwrite::refuse) return Error{name + kAlreadyExists};
  } else if (errno != ENOENT) {
    return Error{name + ": " + reason(errno)};
  }
  const std::filesystem::path dir = directory_of(path);
  OutputFile out;
  out.path_ = path;
  out.overwrite_ = overwrite;
  // An anonymous file in the target's directory (O_TMPFILE): it has no name until commit() links
  // it in, so nothing is left behind whatever stops the process (SIGKILL, a crash, power loss).
  // commit() names it through /proc/self/fd (linkat needs no privileges that way). Named temporary
  // files remain for file systems without O_TMPFILE and systems without /proc.
  if (::access("/proc/self/fd", X_OK) == 0) {
    out.fd_ = ::open(dir.c_str(), O_TMPFILE | O_WRONLY | O_CLOEXEC, 0666);
    if (out.fd_ >= 0) return out;
  }
  const int error = name_temporary(path, out.temporary_, out.slot_, [&](const char* name_to_make) {
    out.fd_ = ::open(name_to_make, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    return out.fd_ >= 0 ? 0 : errno;
  });
  if (error != 0) return Error{name + ": cannot create a file in " + dir.string() + ": " + reason(error)};
  return out;
}

OutputFile::OutputFile(OutputFile&& o) noexcept
    : path_(std::move(o.path_)), temporary_(std::move(o.temporary_)), overwrite_(o.overwrite_), fd_(o.fd_), slot_(o.slot_),
      buffer_(std::move(o.buffer_)), error_(std::move(o.error_)) {
  o.fd_ = -1;
  o.slot_ = -1;
}

OutputFile& OutputFile::operator=(OutputFile&& o) noexcept {
  if (this != &o) {
    discard();
    path_ = std::move(o.path_);
    temporary_ = std::move(o.temporary_);
    overwrite_ = o.overwrite_;
    fd_ = std::exchange(o.fd_, -1);
    slot_ = std::exchange(o.slot_, -1);
    buffer_ = std::move(o.buffer_);
    error_ = std::move(o.error_);
  }
  return *this;
}

OutputFile::~OutputFile() { discard(); }

void OutputFile::discard() noexcept {
  if (fd_ >= 0) {
    ::close(fd_);
    if (!temporary_.empty()) ::unlink(temporary_.c_str());  // an anonymous file vanishes with its descriptor
    fd_ = -1;
  }
  release_slot(slot_);
  slot_ = -1;
}

Status OutputFile::flush() {
  if (!error_.empty()) return Error{error_};
  if (fd_ < 0) return Error{path_.string() + ": already closed"};
  std::size_t done = 0;
  while (done < buffer_.size()) {
    const ssize_t n = ::write(fd_, buffer_.data() + done, buffer_.size() - done);
    if (n < 0) {
      if (errno == EINTR) continue;
      error_ = path_.string() + ": write failed: " + reason(errno);
      return Error{error_};
    }
    done += static_cast<std::size_t>(n);
  }
  buffer_.clear();
  return {};
}

Status OutputFile::write(std::string_view data) {
  if (!error_.empty()) return Error{error_};
  buffer_.append(data);
  if (buffer_.size() >= (1u << 20)) return flush();
  return {};
}

Status OutputFile::commit() {
  if (auto s = flush(); !s) {
    discard();
    return s;
  }
  const std::string name = path_.string();
  auto fail = [&](const std::string& what, int error) {
    discard();
    return Error{name + ": " + what + ": " + reason(error)};
  };
  struct stat old {};
  if (overwrite_ == Overwrite::allow && ::lstat(path_.c_str(), &old) == 0) {
    if (!S_ISREG(old.st_mode)) {
      discard();
      return Error{name + kNotRegular};
    }
    if (::fchmod(fd_, old.st_mode & 07777) != 0) return fail("cannot keep the permissions", errno);
    (void)!::fchown(fd_, old.st_uid, old.st_gid);  // keeps the owner where allowed (root); else ours
  }
  if (::fsync(fd_) != 0) return fail("fsync failed", errno);
  if (temporary_.empty()) {  // anonymous: the file gets its name now
    const std::string self = "/proc/self/fd/" + std::to_string(fd_);
    if (overwrite_ == Overwrite::refuse) {
      // Exclusive: linkat fails with EEXIST where a file appeared meanwhile (another writer).
      const int rc = ::linkat(AT_FDCWD, self.c_str(), AT_FDCWD, path_.c_str(), AT_SYMLINK_FOLLOW);
      const int error = errno;
      const int closed = ::close(std::exchange(fd_, -1));
      const int close_error = errno;
      if (rc != 0) return Error{name + (error == EEXIST ? kAlreadyExists : ": cannot create: " + reason(error))};
      if (closed != 0) {
        ::unlink(path_.c_str());  // ours, created just now
        return Error{name + ": close failed: " + reason(close_error)};
      }
      return {};
    }
    // Replacing: a name beside the target for an instant, then the rename below.
    const int error = name_temporary(path_, temporary_, slot_, [&](const char* name_to_make) {
      return ::linkat(AT_FDCWD, self.c_str(), AT_FDCWD, name_to_make, AT_SYMLINK_FOLLOW) == 0 ? 0 : errno;
    });
    if (error != 0) return fail("cannot create a file beside it", error);
  }
  const int fd = std::exchange(fd_, -1);
  if (::close(fd) != 0) {
    fd_ = -1;
    const int e = errno;
    ::unlink(temporary_.c_str());
    release_slot(std::exchange(slot_, -1));
    return Error{name + ": close failed: " + reason(e)};
  }
  auto finish = [&](int rc, int error) -> Status {
    if (rc != 0) ::unlink(temporary_.c_str());
    release_slot(std::exchange(slot_, -1));
    if (rc == 0) return {};
    if (error == EEXIST) return Error{name + kAlreadyExists};
    return Error{name + ": cannot " + (overwrite_ == Overwrite::allow ? "replace" : "create") + ": " + reason(error)};
  };
  if (overwrite_ == Overwrite::allow) {
    const int rc = ::rename(temporary_.c_str(), path_.c_str());
    return finish(rc, errno);
  }
  // Exclusive: never replaces a file that appeared meanwhile (another writer).
  int rc = ::renameat2(AT_FDCWD, temporary_.c_str(), AT_FDCWD, path_.c_str(), RENAME_NOREPLACE);
  if (rc != 0 && (errno == EINVAL || errno == ENOSYS || errno == ENOTSUP)) {  // file system without it
    rc = ::link(temporary_.c_str(), path_.c_str());
    const int e = errno;
    ::unlink(temporary_.c_str());
    return finish(rc, e);
  }
  return finish(rc, errno);
}

std::string lowercase_extension(const std::filesystem::path& path) {
  std::string extension = path.extension().string();
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return extension;
}

Status refuse_special_file(const std::filesystem::path& path) {
  std::error_code ec;
  const auto status = std::filesystem::status(path, ec);
  if (std::filesystem::exists(status) && !std::filesystem::is_directory(status) && !std::filesystem::is_regular_file(status))
    return Error{path.string() + ": is not a regular file (a device, FIFO or socket)"};
  return {};
}

Status write_file_atomically(const std::filesystem::path& path, std::string_view contents, Overwrite overwrite) {
  Expected<OutputFile> out = OutputFile::create(path, overwrite);
  if (!out) return out.error();
  if (auto s = out->write(contents); !s) return s;
  return out->commit();
}

}  // namespace dq

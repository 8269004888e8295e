// Safe file writing: the contents go to a file without a name in the target's directory
// (O_TMPFILE; a named temporary file where the file system has none), which is then linked in as
// the target (exclusively) or renamed over it, so a failure at any point, a SIGKILL included,
// leaves what was there before intact and nothing beside it. An existing target is only replaced
// when the caller says so, and only if it is a regular file; its permissions are kept.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

#include "dq/util/expected.hpp"

namespace dq {

enum class Overwrite { refuse, allow };

/// A file being written: data goes to an anonymous file in the target's directory (O_TMPFILE, or
/// a named temporary file where the file system has none); commit() makes it the target.
/// Destroyed without commit() (an error, an exception), it is gone and the target is untouched.
///  - Overwrite::refuse: commit() creates the target exclusively (linkat of the anonymous file, or
///    renameat2 RENAME_NOREPLACE or link of a named one): of two writers racing to a new path, one
///    wins and the other gets "already exists".
///  - Overwrite::allow: only a regular file is replaced (never a directory, symbolic link, device,
///    FIFO or socket); the replacement gets the old file's permission bits (and owner, if allowed).
/// Errors name the target, never the temporary file.
class OutputFile {
 public:
  static Expected<OutputFile> create(const std::filesystem::path& path, Overwrite overwrite);
  OutputFile(OutputFile&& other) noexcept;
  OutputFile& operator=(OutputFile&& other) noexcept;
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;
  ~OutputFile();

  /// Appends (buffered). After an error, later writes and commit() fail too.
  Status write(std::string_view data);
  /// Flushes, fsyncs and moves the file into place.
  Status commit();

 private:
  OutputFile() = default;
  Status flush();
  void discard() noexcept;
  std::filesystem::path path_, temporary_;
  Overwrite overwrite_ = Overwrite::refuse;
  int fd_ = -1;
  int slot_ = -1;  // in the table of named temporary files removed on a signal
  std::string buffer_;
  std::string error_;
};

/// The extension of a file name with its dot, in lower case ("" for none): ".BVH" and ".bvh" alike.
std::string lowercase_extension(const std::filesystem::path& path);

/// An error if `path` exists and is neither a regular file nor a directory (a device, FIFO or
/// socket, which a reader may wait on for ever), found without opening it; otherwise success
/// (a missing file or a directory is the caller's to report).
Status refuse_special_file(const std::filesystem::path& path);

/// Writes `contents` to `path` (OutputFile: create, write, commit). Errors name the file.
Status write_file_atomically(const std::filesystem::path& path, std::string_view contents, Overwrite overwrite);

/// Makes SIGINT, SIGTERM, SIGHUP, SIGQUIT and SIGXFSZ remove the named temporary files of every
/// OutputFile in progress (anonymous ones need nothing) before the process dies of the signal
/// (handlers are installed only for signals whose disposition is the default; a program calls
/// this once, e.g. from main()).
void remove_temporary_files_on_signals();

}  // namespace dq

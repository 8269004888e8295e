// Safe file writing: the contents go to a temporary file beside the target, which is then renamed
// over it, so a failure at any point leaves what was there before intact. An existing target is
// only replaced when the caller says so.
#pragma once

#include <filesystem>
#include <string_view>

#include "dq/util/expected.hpp"

namespace dq {

enum class Overwrite { refuse, allow };

/// Writes `contents` to `path` atomically (temporary file + fsync + rename). Errors name the file.
Status write_file_atomically(const std::filesystem::path& path, std::string_view contents, Overwrite overwrite);

}  // namespace dq

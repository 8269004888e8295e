// dqkit::import internals shared by the library and its worker executable (not installed).
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "dq/io/scene.hpp"

namespace dq::detail {

/// Assimp in this process: what the worker runs, and what `isolate = false` runs.
Expected<ImportedScene> import_file_in_process(const std::filesystem::path& path, const ImportOptions& options);
Expected<ImportedScene> import_memory_in_process(std::span<const std::uint8_t> data, const std::string& hint, const ImportOptions& options);

/// What the caller asks the worker to import.
struct ImportRequest {
  bool from_memory = false;
  std::string path_or_hint{};      ///< the file, or the format hint of `data`
  std::vector<std::uint8_t> data{};  ///< the file's bytes, for from_memory
  double sample_rate = 30;
  bool meshes = true;
  bool lights_and_cameras = false;
  std::size_t result_limit_mb = 2048;  ///< the worker refuses to resample beyond it (the caller would refuse the result)
};

/// The request for a file or memory import with these options.
ImportRequest make_request(bool from_memory, std::string path_or_hint, std::vector<std::uint8_t> data, const ImportOptions& options);

// The worker protocol, over one socket (the worker's descriptor 3). The caller sends the encoded
// request and shuts its side for writing; the worker answers with a 64-bit length and that many
// bytes: 'S' and the encoded scene, or 'E' and an error message.
std::string encode_request(const ImportRequest& request);
std::optional<ImportRequest> decode_request(std::string_view bytes);
std::string encode_response(const Expected<ImportedScene>& result);
/// Decodes a response payload (without its length). Every count is checked against the bytes
/// left and against `budget_bytes` before anything is allocated; indices are checked too.
Expected<ImportedScene> decode_response(std::string_view payload, const std::string& source, std::size_t budget_bytes);

/// Runs the request in a worker process under the options' limits.
Expected<ImportedScene> run_isolated(const ImportRequest& request, const std::string& source, const ImportOptions& options);

}  // namespace dq::detail

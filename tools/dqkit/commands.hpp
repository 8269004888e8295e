// The dqkit command-line tool's commands. Each returns the process exit code and writes its
// errors to stderr as "dqkit: <what>".
#pragma once

#include <string>
#include <vector>

namespace dq::cli {

struct InfoArgs {
  std::string file;
  std::size_t animation = 0;
  double import_timeout = 120;
};
int info(const InfoArgs& args);

struct FkArgs {
  std::string file;
  std::string frames;  ///< "0,1,100"; empty: frame 0
  bool all = false;
  std::string format = "csv";
  std::string output;  ///< empty: stdout
  bool force = false;
  std::size_t animation = 0;
  double import_timeout = 120;
};
int fk(const FkArgs& args);

struct ConvertArgs {
  std::string input, output;
  std::string rotation_order;  ///< empty: keep (BVH) or ZXY
  bool force = false;
  std::size_t animation = 0;
  double rate = 30;
  double import_timeout = 120;
};
int convert(const ConvertArgs& args);

/// Parses "0,1,100" into frame numbers below `count`; the error says which item is wrong.
std::vector<std::size_t> parse_frame_list(const std::string& text, std::size_t count, std::string& error);

}  // namespace dq::cli

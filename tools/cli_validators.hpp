// CLI11 validators shared by the dqkit tool (tools/dqkit) and the demo programs (apps/).
#pragma once

#include <CLI/CLI.hpp>
#include <charconv>
#include <cmath>
#include <string>

namespace dq::cli {

/// A finite number in (low, high]: CLI11's ranges let NaN through (every comparison with it is false).
inline CLI::Validator finite_in(double low, double high) {
  return CLI::Validator(
      [low, high](std::string& text) -> std::string {
        double v = 0;
        const char* end = text.data() + text.size();
        const auto r = std::from_chars(text.data(), end, v);
        if (r.ec != std::errc() || r.ptr != end || !std::isfinite(v)) return "'" + text + "' is not a finite number";
        if (!(v > low && v <= high)) return "'" + text + "' is out of range (" + CLI::detail::to_string(low) + ", " + CLI::detail::to_string(high) + "]";
        return {};
      },
      "NUMBER in (" + CLI::detail::to_string(low) + ", " + CLI::detail::to_string(high) + "]");
}

/// A whole number in [low, high], digits only (CLI11 reads "-1" into an unsigned as 2^64 − 1);
/// `what` names it in the error ("'-1' is not an animation number (0, 1, ...)"), `name` in the help.
inline CLI::Validator whole_number_up_to(unsigned long long high, const std::string& what = "a whole number",
                                         const std::string& name = "NUMBER", unsigned long long low = 0) {
  return CLI::Validator(
      [high, low, what](std::string& text) -> std::string {
        unsigned long long v = 0;
        const char* end = text.data() + text.size();
        const auto r = std::from_chars(text.data(), end, v);
        if (text.empty() || r.ec != std::errc() || r.ptr != end)
          return "'" + text + "' is not " + what + " (" + std::to_string(low) + ", " + std::to_string(low + 1) + ", ...)";
        if (v > high) return "'" + text + "' is more than " + std::to_string(high);
        if (v < low) return "'" + text + "' is less than " + std::to_string(low);
        return {};
      },
      high == ~0ull && low == 0 ? name : name + " in [" + std::to_string(low) + ", " + std::to_string(high) + "]");
}

}  // namespace dq::cli

// UTF-8 checks shared by the readers (names must be text that CSV and JSON carry unchanged) and
// the writers.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace dq {

/// The length of the well-formed UTF-8 sequence at s[i] (1 to 4), or 0 if there is none (a stray
/// continuation byte, an overlong form, a surrogate, beyond U+10FFFF, or cut short).
std::size_t utf8_sequence_length(std::string_view s, std::size_t i) noexcept;

/// Whether the whole text is well-formed UTF-8.
bool is_valid_utf8(std::string_view s) noexcept;

/// The text with every byte that is not part of a well-formed sequence replaced by U+FFFD.
std::string to_valid_utf8(std::string_view s);

}  // namespace dq

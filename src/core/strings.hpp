#pragma once
/// @file String helpers for messages: "did you mean" suggestions, lists.

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace crackle {

/// Levenshtein distance.
std::size_t edit_distance(std::string_view a, std::string_view b);

/// The candidate closest to `word` if it is close enough to be a likely typo, else "".
std::string closest_match(std::string_view word, const std::vector<std::string>& candidates);

/// Splits at every `separator` (an empty text gives no parts; "a,,b" gives "a", "", "b").
std::vector<std::string> split(std::string_view text, char separator);

/// The parts with `separator` between them: join({"a", "b"}, ", ") = "a, b".
std::string join(const std::vector<std::string>& parts, std::string_view separator);

/// Without leading and trailing spaces and tabs.
std::string trim(std::string_view text);

/// 16 lowercase hex digits.
std::string hex64(std::uint64_t value);

/// " (did you mean 'x'?)" or "".
std::string did_you_mean(std::string_view word, const std::vector<std::string>& candidates);

} // namespace crackle

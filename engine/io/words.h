// Words a user may have mistyped: the nearest of those allowed, for "did you mean" in errors.
#pragma once

#include <cstddef>
#include <span>
#include <string>
#include <string_view>

namespace aeroflock {

// Letters to change, add or remove to turn `a` into `b` (Levenshtein).
size_t edit_distance(std::string_view a, std::string_view b);

// The word of `words` nearest `word` within two edits (the first on a tie), or "" when none is:
// farther than that a suggestion misleads more than it helps.
std::string closest_word(std::string_view word, std::span<const std::string_view> words);

// " (did you mean 'WORD'?)" for closest_word's, or "".
std::string did_you_mean(std::string_view word, std::span<const std::string_view> words);

}  // namespace aeroflock

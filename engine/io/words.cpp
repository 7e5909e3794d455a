#include "io/words.h"

#include <algorithm>
#include <vector>

namespace aeroflock {

size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diagonal = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] != b[j - 1])});
      diagonal = up;
    }
  }
  return row[b.size()];
}

std::string closest_word(std::string_view word, std::span<const std::string_view> words) {
  std::string_view closest;
  size_t best = 3;  // within two edits
  for (const std::string_view w : words)
    if (const size_t d = edit_distance(word, w); d < best) best = d, closest = w;
  return std::string(closest);
}

std::string did_you_mean(std::string_view word, std::span<const std::string_view> words) {
  const std::string closest = closest_word(word, words);
  return closest.empty() ? "" : " (did you mean '" + closest + "'?)";
}

}  // namespace aeroflock

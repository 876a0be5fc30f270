// Suggestions for misspelt keys and names.
#pragma once

#include <span>
#include <string>
#include <string_view>

namespace syrof::lab::scenario {

// The Levenshtein distance: fewest single-character insertions, deletions
// and substitutions that turn `a` into `b`.
size_t EditDistance(std::string_view a, std::string_view b);

// The candidate closest to `word` when it is close enough to be a likely
// misspelling (at most 2 edits, or a third of the word's length for long
// words), else "". Ties go to the earlier candidate.
std::string NearestName(std::string_view word, std::span<const std::string_view> candidates);

// The candidates joined with ", ".
std::string JoinNames(std::span<const std::string_view> candidates);

}  // namespace syrof::lab::scenario

#pragma once
/// Words in messages: "did you mean" suggestions and quoted lists (STYLE.md: errors say how to fix).
#include <string>
#include <string_view>
#include <vector>

namespace vantage::detail {

/// Levenshtein distance: insertions, deletions and substitutions of one character each.
size_t EditDistance(std::string_view a, std::string_view b);

/// The word of `valid` closest to `word` when within a third of its length (at least 2 edits);
/// nullptr otherwise. Ties: the first.
const std::string* ClosestWord(std::string_view word, const std::vector<std::string>& valid);

/// 'a', 'b', 'c'
std::string JoinQuoted(const std::vector<std::string>& words);

}  // namespace vantage::detail

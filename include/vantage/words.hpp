#pragma once
/// "Did you mean" suggestions for names the user typed (options, commands, ids, objects).
#include <string>
#include <string_view>
#include <vector>

namespace vantage {

/// Levenshtein distance: insertions, deletions and substitutions of one character each.
size_t EditDistance(std::string_view a, std::string_view b);

/// The word of `valid` closest to `word` when within a third of its length (at least 2 edits);
/// nullptr otherwise. Ties: the first.
const std::string* ClosestWord(std::string_view word, const std::vector<std::string>& valid);

/// `text` from outside (a path, a name) for one line of the summary or a message: each byte that
/// is not well-formed UTF-8 as U+FFFD, control characters escaped (\n, \xNN, \uNNNN) and a
/// backslash doubled, as vantage's error messages show names.
std::string ShownOnOneLine(std::string_view text);

/// `text` with the ASCII letters in lower case (other bytes, UTF-8 included, unchanged).
std::string LowerCase(std::string text);

/// The extension of the file `path` names, dot included, in lower case ("" when none):
/// "Scene.YAML" -> ".yaml".
std::string LowerExtension(const std::string& path);

}  // namespace vantage

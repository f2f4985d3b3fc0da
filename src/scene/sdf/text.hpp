#pragma once
/// Text and path helpers of the SDF reader (scene/sdf/): SDF values are white-space separated
/// words, numbers may carry a leading '+', and paths come from options and the environment.
/// Private to the reader.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace vantage::detail::gazebo {

/// XML white space: ' ', '\t', '\n', '\r'.
bool IsSpace(char c);
/// `s` without leading and trailing white space.
std::string Trim(std::string_view s);
/// The words of `s`, split at white space.
std::vector<std::string> SplitWords(std::string_view s);
/// The non-empty trimmed parts of `s` between `separator`s.
std::vector<std::string> SplitList(std::string_view s, char separator);
/// A number as SDF writes it (a leading '+' allowed); not checked for finiteness.
std::optional<double> ParseDouble(std::string_view s);
/// A whole number as SDF writes it (a leading '+' allowed).
std::optional<int64_t> ParseInteger(std::string_view s);
/// "1.5" -> (1, 5).
std::optional<std::pair<int, int>> ParseVersion(std::string_view s);
/// The folders of a ':'-separated environment variable (GAZEBO_MODEL_PATH); empty when unset.
std::vector<std::string> PathListFromEnv(const char* variable);
/// Whether `path` is a folder / a regular file (false on any error).
bool IsDirectory(const std::string& path);
bool IsFile(const std::string& path);
/// The folder holding `path`, normalised.
std::string ParentDir(const std::string& path);
/// `items` joined by `separator`.
std::string Join(const std::vector<std::string>& items, std::string_view separator);
/// Appends each folder of `folders` that `list` does not hold yet (compared normalised, without
/// a trailing '/'), so that a message lists each searched folder once.
void AppendOnce(const std::vector<std::string>& folders, std::vector<std::string>* list);

}  // namespace vantage::detail::gazebo

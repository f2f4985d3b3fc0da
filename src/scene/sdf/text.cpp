// Text and path helpers of the SDF reader (text.hpp): the small parsing and file-system steps that
// every part of the reader shares, in one place.
#include "scene/sdf/text.hpp"

#include <algorithm>
#include <charconv>
#include <cstdlib>
#include <filesystem>
#include <system_error>

#include "util/xml.hpp"

namespace vantage::detail::gazebo {

namespace fs = std::filesystem;

bool IsSpace(char c) { return IsXmlSpace(c); }

std::string Trim(std::string_view s) { return TrimXmlSpace(s); }

std::vector<std::string> SplitWords(std::string_view s) {
  std::vector<std::string> words;
  size_t i = 0;
  while (i < s.size()) {
    while (i < s.size() && IsSpace(s[i])) ++i;
    const size_t start = i;
    while (i < s.size() && !IsSpace(s[i])) ++i;
    if (i > start) words.emplace_back(s.substr(start, i - start));
  }
  return words;
}

std::vector<std::string> SplitList(std::string_view s, char separator) {
  std::vector<std::string> parts;
  size_t start = 0;
  while (start <= s.size()) {
    size_t end = s.find(separator, start);
    if (end == std::string_view::npos) end = s.size();
    std::string part = Trim(s.substr(start, end - start));
    if (!part.empty()) parts.push_back(std::move(part));
    start = end + 1;
  }
  return parts;
}

/// A number as SDF writes it (a leading '+' allowed); not checked for finiteness.
std::optional<double> ParseDouble(std::string_view s) {
  if (!s.empty() && s[0] == '+') s.remove_prefix(1);
  double value = 0;
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), value);
  if (s.empty() || ec != std::errc() || ptr != s.data() + s.size()) return std::nullopt;
  return value;
}

std::optional<int64_t> ParseInteger(std::string_view s) {
  if (!s.empty() && s[0] == '+') s.remove_prefix(1);
  int64_t value = 0;
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), value);
  if (s.empty() || ec != std::errc() || ptr != s.data() + s.size()) return std::nullopt;
  return value;
}

/// "1.5" -> (1, 5).
std::optional<std::pair<int, int>> ParseVersion(std::string_view s) {
  const size_t dot = s.find('.');
  if (dot == std::string_view::npos) return std::nullopt;
  const auto major = ParseInteger(s.substr(0, dot));
  const auto minor = ParseInteger(s.substr(dot + 1));
  if (!major || !minor || *major < 0 || *minor < 0 || *major > 1000 || *minor > 1000)
    return std::nullopt;
  return std::make_pair(static_cast<int>(*major), static_cast<int>(*minor));
}

std::vector<std::string> PathListFromEnv(const char* variable) {
  // Read while loading only; vantage never sets the environment.
  const char* value = std::getenv(variable);  // NOLINT(concurrency-mt-unsafe)
  return value ? SplitList(value, ':') : std::vector<std::string>{};
}

bool IsDirectory(const std::string& path) {
  std::error_code ec;
  return fs::is_directory(path, ec);
}

bool IsFile(const std::string& path) {
  std::error_code ec;
  return fs::is_regular_file(path, ec);
}

std::string ParentDir(const std::string& path) {
  return fs::path(path).parent_path().lexically_normal().string();
}

void AppendOnce(const std::vector<std::string>& folders, std::vector<std::string>* list) {
  const auto normal = [](const std::string& folder) {
    std::string text = fs::path(folder).lexically_normal().string();
    while (text.size() > 1 && text.back() == '/') text.pop_back();
    return text;
  };
  for (const std::string& folder : folders) {
    const std::string key = normal(folder);
    const bool known = std::any_of(list->begin(), list->end(),
                                   [&](const std::string& f) { return normal(f) == key; });
    if (!known) list->push_back(folder);
  }
}

std::string Join(const std::vector<std::string>& items, std::string_view separator) {
  std::string out;
  for (size_t i = 0; i < items.size(); ++i) {
    if (i) out += separator;
    out += items[i];
  }
  return out;
}

}  // namespace vantage::detail::gazebo

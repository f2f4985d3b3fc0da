#include "util/words.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include "vantage/error.hpp"

namespace vantage {

size_t EditDistance(std::string_view a, std::string_view b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diagonal = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t substitution = diagonal + (a[i - 1] == b[j - 1] ? 0 : 1);
      diagonal = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, substitution});
    }
  }
  return row[b.size()];
}

const std::string* ClosestWord(std::string_view word, const std::vector<std::string>& valid) {
  const std::string* best = nullptr;
  size_t best_distance = std::numeric_limits<size_t>::max();
  for (const std::string& candidate : valid) {
    const size_t distance = EditDistance(word, candidate);
    if (distance < best_distance) {
      best_distance = distance;
      best = &candidate;
    }
  }
  const size_t tolerance = std::max<size_t>(2, word.size() / 3);
  return best && best_distance <= tolerance ? best : nullptr;
}

}  // namespace vantage

namespace vantage::detail {

std::string JoinQuoted(const std::vector<std::string>& words) {
  std::string all;
  for (const std::string& word : words) all += (all.empty() ? "'" : ", '") + word + "'";
  return all;
}

size_t FirstNonUtf8Byte(std::string_view text) {
  size_t i = 0;
  while (i < text.size()) {
    const auto byte = [&](size_t k) { return static_cast<unsigned char>(text[k]); };
    const unsigned char lead = byte(i);
    size_t length = 0;
    uint32_t code = 0;
    if (lead < 0x80) {
      ++i;
      continue;
    } else if (lead >= 0xC2 && lead <= 0xDF) {
      length = 2;
      code = lead & 0x1F;
    } else if (lead >= 0xE0 && lead <= 0xEF) {
      length = 3;
      code = lead & 0x0F;
    } else if (lead >= 0xF0 && lead <= 0xF4) {
      length = 4;
      code = lead & 0x07;
    } else {
      return i;
    }
    if (i + length > text.size()) return i;
    for (size_t k = 1; k < length; ++k) {
      if ((byte(i + k) & 0xC0) != 0x80) return i;
      code = (code << 6) | (byte(i + k) & 0x3F);
    }
    const uint32_t smallest = length == 3 ? 0x800 : length == 4 ? 0x10000 : 0x80;
    if (code < smallest || code > 0x10FFFF || (code >= 0xD800 && code <= 0xDFFF)) return i;
    i += length;
  }
  return std::string_view::npos;
}

void CheckUtf8File(std::string_view text, const std::string& path) {
  const size_t at = FirstNonUtf8Byte(text);
  if (at == std::string_view::npos) return;
  const int line = 1 + static_cast<int>(std::count(text.begin(), text.begin() + at, '\n'));
  throw InputError(AtPlace(
      path, line,
      fmt::format("byte 0x{:02X} is not UTF-8 (a name in Latin-1?) — save the file as UTF-8",
                  static_cast<unsigned char>(text[at]))));
}

std::string ReadInputFile(const std::string& path, std::string_view kind) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    // A device or a pipe would be read without end, or block (issue 15): named as such.
    const bool other = std::filesystem::exists(path, ec) && !std::filesystem::is_directory(path, ec);
    throw InputError(AtPlace(
        path, 0,
        other ? fmt::format("cannot open the {}: it is not a regular file (a device or a pipe?) — "
                            "give the file itself",
                            kind)
              : fmt::format("cannot open the {} — check the path", kind)));
  }
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  if (!in)
    throw InputError(AtPlace(path, 0, fmt::format("cannot read the {} — check permissions", kind)));
  return text.str();
}

}  // namespace vantage::detail

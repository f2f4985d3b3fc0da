#include "util/words.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>

#include "util/run_files.hpp"
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

namespace {

bool IsControl(char c) {
  const auto byte = static_cast<unsigned char>(c);
  return byte < 0x20 || byte == 0x7F;
}

// The UTF-8 sequence at `i` when it is a C1 control (U+0080 to U+009F: NEL breaks lines in
// terminals) or the line and paragraph separators U+2028, U+2029 (line breaks in editors, and in
// JavaScript before ES2019): its code point, else 0.
uint32_t WideBreakAt(std::string_view text, size_t i) {
  const auto byte = [&](size_t k) { return static_cast<unsigned char>(text[k]); };
  if (i + 1 < text.size() && byte(i) == 0xC2 && byte(i + 1) >= 0x80 && byte(i + 1) <= 0x9F)
    return byte(i + 1);
  if (i + 2 < text.size() && byte(i) == 0xE2 && byte(i + 1) == 0x80 &&
      (byte(i + 2) == 0xA8 || byte(i + 2) == 0xA9))
    return 0x2000u + byte(i + 2) - 0x80u;
  return 0;
}

}  // namespace

size_t FirstControlCharacter(std::string_view text) {
  for (size_t i = 0; i < text.size(); ++i) {
    if (IsControl(text[i])) return i;
  }
  return std::string_view::npos;
}

std::string Escaped(std::string_view text) {
  std::string shown;
  shown.reserve(text.size());
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (const uint32_t code = WideBreakAt(text, i)) {
      shown += fmt::format("\\u{:04X}", code);
      i += code < 0x100 ? 1 : 2;
    } else if (c == '\\') {
      shown += "\\\\";  // so that a backslash in the name cannot pass for an escape
    } else if (!IsControl(c)) {
      shown.push_back(c);
    } else if (c == '\n') {
      shown += "\\n";
    } else if (c == '\t') {
      shown += "\\t";
    } else if (c == '\r') {
      shown += "\\r";
    } else if (c == '\0') {
      shown += "\\0";
    } else {
      shown += fmt::format("\\x{:02X}", static_cast<unsigned char>(c));
    }
  }
  return shown;
}

std::string AsUtf8(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  while (!text.empty()) {
    const size_t bad = FirstNonUtf8Byte(text);
    out += text.substr(0, bad);
    if (bad == std::string_view::npos) break;
    out += "\xEF\xBF\xBD";  // U+FFFD
    text.remove_prefix(bad + 1);
  }
  return out;
}

std::string NameProblem(std::string_view name) {
  const size_t at = FirstControlCharacter(name);
  if (at != std::string_view::npos)
    return fmt::format("has a control character (U+{:04X}) — use printable characters",
                       static_cast<unsigned char>(name[at]));
  for (size_t i = 0; i < name.size(); ++i) {
    if (const uint32_t code = WideBreakAt(name, i))
      return fmt::format("has {} (U+{:04X}) — use printable characters",
                         code < 0x100 ? "a control character" : "a line or paragraph separator",
                         code);
  }
  return "";
}

void CheckUtf8File(std::string_view text, const std::string& path) {
  const auto line_of = [&](size_t at) {
    return 1 + static_cast<int>(std::count(text.begin(), text.begin() + at, '\n'));
  };
  const size_t at = FirstNonUtf8Byte(text);
  if (at != std::string_view::npos) {
    throw InputError(AtPlace(
        path, line_of(at),
        fmt::format("byte 0x{:02X} is not UTF-8 (a name in Latin-1?) — save the file as UTF-8",
                    static_cast<unsigned char>(text[at]))));
  }
  // YAML 1.2 (c-printable) and XML 1.0 (Char) allow no other control character in a file.
  for (size_t i = 0; i < text.size(); ++i) {
    if (!IsControl(text[i]) || text[i] == '\t' || text[i] == '\n' || text[i] == '\r') continue;
    throw InputError(AtPlace(
        path, line_of(i),
        fmt::format("byte 0x{:02X} is a control character (U+{:04X}) — remove it; names take "
                    "printable characters",
                    static_cast<unsigned char>(text[i]), static_cast<unsigned char>(text[i]))));
  }
}

bool ReadWholeFile(const std::string& path, std::string* bytes) {
  std::ifstream in(path, std::ios::binary);
  if (!in.is_open()) return false;
  // In one piece at the size the file has (an ostringstream grew and copied a 137 MB .vis four
  // times; a character at a time was slower still).
  std::error_code ec;
  bytes->assign(static_cast<size_t>(std::filesystem::file_size(path, ec)), '\0');
  if (ec) bytes->clear();
  in.read(bytes->data(), static_cast<std::streamsize>(bytes->size()));
  bytes->resize(static_cast<size_t>(in.gcount()));
  char more[1 << 16];
  while (in.read(more, sizeof more) || in.gcount() > 0)
    bytes->append(more, static_cast<size_t>(in.gcount()));
  return !in.bad();
}

std::string ReadInputFile(const std::string& path, std::string_view kind) {
  NoteInputFile(path, kind);
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
  std::string bytes;
  if (!ReadWholeFile(path, &bytes))
    throw InputError(AtPlace(path, 0, fmt::format("cannot read the {} — check permissions", kind)));
  return bytes;
}

}  // namespace vantage::detail

namespace vantage {

std::string ShownOnOneLine(std::string_view text) { return detail::Escaped(detail::AsUtf8(text)); }

std::string LowerCase(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return text;
}

std::string LowerExtension(const std::string& path) {
  return LowerCase(std::filesystem::path(path).extension().string());
}

}  // namespace vantage

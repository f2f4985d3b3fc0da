#include "scene/ply_body.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <charconv>
#include <cstdint>
#include <fstream>
#include <iterator>
#include <optional>
#include <sstream>
#include <string_view>
#include <vector>

namespace vantage::detail {
namespace {

struct PlyProperty {
  int size = 0;        ///< bytes of the value (binary), or of a list's items
  int count_size = 0;  ///< > 0 for a list: bytes of its count
  bool count_signed = false;
};

struct PlyElement {
  std::string name;
  uint64_t count = 0;
  std::vector<PlyProperty> properties;
};

enum class PlyFormat { kAscii, kLittleEndian, kBigEndian };

struct PlyHeader {
  PlyFormat format = PlyFormat::kAscii;
  std::vector<PlyElement> elements;
  size_t body_offset = 0;
};

/// Bytes of a PLY scalar type; 0 for an unknown one.
int TypeSize(std::string_view type) {
  if (type == "char" || type == "uchar" || type == "int8" || type == "uint8") return 1;
  if (type == "short" || type == "ushort" || type == "int16" || type == "uint16") return 2;
  if (type == "int" || type == "uint" || type == "int32" || type == "uint32" || type == "float" ||
      type == "float32")
    return 4;
  if (type == "double" || type == "float64") return 8;
  return 0;
}

std::vector<std::string> Words(const std::string& line) {
  std::istringstream in(line);
  return {std::istream_iterator<std::string>(in), std::istream_iterator<std::string>()};
}

/// The header, or the words for what is wrong with it. Strict: Assimp's PLY reader segfaulted on
/// an unknown header line and looped forever on a header without end_header (the mesh_file
/// fuzzer, session 9), so no malformed header reaches it.
std::optional<PlyHeader> ReadHeader(const std::string& bytes, std::string* problem) {
  PlyHeader header;
  size_t at = 0;
  int line_number = 0;
  const auto fail = [&](const std::string& what) {
    *problem = fmt::format("header line {}: {}", line_number, what);
    return std::nullopt;
  };
  while (at < bytes.size()) {
    const size_t end = bytes.find('\n', at);
    if (end == std::string::npos) break;
    std::string line = bytes.substr(at, end - at);
    at = end + 1;
    ++line_number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const std::vector<std::string> words = Words(line);
    if (line_number == 1) {
      if (words.size() != 1 || words[0].size() != 3)
        return fail("the first line must be `ply` alone");
      continue;
    }
    if (words.empty() || words[0] == "comment" || words[0] == "obj_info") continue;
    if (words[0] == "end_header") {
      header.body_offset = at;
      return header;
    }
    if (words[0] == "format") {
      if (words.size() != 3)
        return fail("write `format ascii 1.0` (or binary_little_endian, binary_big_endian)");
      if (words[1] == "ascii")
        header.format = PlyFormat::kAscii;
      else if (words[1] == "binary_little_endian")
        header.format = PlyFormat::kLittleEndian;
      else if (words[1] == "binary_big_endian")
        header.format = PlyFormat::kBigEndian;
      else
        return fail(
            fmt::format("format '{}' is not ascii, binary_little_endian or "
                        "binary_big_endian",
                        words[1]));
    } else if (words[0] == "element") {
      PlyElement element;
      if (words.size() != 3) return fail("write `element NAME COUNT`");
      element.name = words[1];
      const auto [ptr, ec] =
          std::from_chars(words[2].data(), words[2].data() + words[2].size(), element.count);
      if (ec != std::errc() || ptr != words[2].data() + words[2].size())
        return fail(fmt::format("element count '{}' is no whole number >= 0", words[2]));
      header.elements.push_back(std::move(element));
    } else if (words[0] == "property") {
      if (header.elements.empty()) return fail("a property before any element");
      PlyProperty property;
      const std::string known =
          "a PLY type (char, uchar, short, ushort, int, uint, float, double, "
          "or int8 ... float64)";
      if (words.size() == 5 && words[1] == "list") {
        property.count_size = TypeSize(words[2]);
        property.count_signed = words[2][0] != 'u';
        property.size = TypeSize(words[3]);
        if (property.count_size == 0 || property.count_size == 8 || words[2].find("float") == 0)
          return fail(fmt::format("list count type '{}' is not a whole-number type", words[2]));
        if (property.size == 0)
          return fail(fmt::format("list item type '{}' is not {}", words[3], known));
      } else if (words.size() == 3) {
        property.size = TypeSize(words[1]);
        if (property.size == 0)
          return fail(fmt::format("property type '{}' is not {}", words[1], known));
      } else {
        return fail("write `property TYPE NAME` or `property list COUNT_TYPE ITEM_TYPE NAME`");
      }
      header.elements.back().properties.push_back(property);
    } else {
      return fail(
          fmt::format("'{}' is no PLY header keyword (format, element, property, comment, "
                      "obj_info, end_header)",
                      words[0].substr(0, 40)));
    }
  }
  *problem = "its header has no end_header line (a file cut short?)";
  return std::nullopt;
}

std::string Missing(const PlyElement& element, uint64_t index) {
  return fmt::format(
      "it ends inside element '{}' {} of {} declared in its header (a file cut "
      "short?)",
      element.name, index + 1, element.count);
}

/// The list count at `bytes[at]` (binary), or nullopt when negative.
std::optional<uint64_t> BinaryCount(const std::string& bytes,
                                    size_t at,
                                    const PlyProperty& p,
                                    bool big_endian) {
  uint64_t value = 0;
  for (int i = 0; i < p.count_size; ++i) {
    const int byte = big_endian ? i : p.count_size - 1 - i;  // most significant first
    value = (value << 8) | static_cast<unsigned char>(bytes[at + static_cast<size_t>(byte)]);
  }
  if (p.count_signed && (value >> (8 * p.count_size - 1)) != 0) return std::nullopt;
  return value;
}

std::string BinaryBodyProblem(const std::string& bytes, const PlyHeader& header) {
  const bool big_endian = header.format == PlyFormat::kBigEndian;
  size_t at = header.body_offset;
  for (const PlyElement& element : header.elements) {
    const bool has_list = std::any_of(element.properties.begin(), element.properties.end(),
                                      [](const PlyProperty& p) { return p.count_size > 0; });
    if (!has_list) {
      // Fixed rows: the size at once (a count of 10^12 must not be walked row by row).
      uint64_t row = 0;
      for (const PlyProperty& p : element.properties) row += static_cast<uint64_t>(p.size);
      const uint64_t left = bytes.size() - at;
      if (row > 0 && element.count > left / row) return Missing(element, left / row);
      at += static_cast<size_t>(row * element.count);
      continue;
    }
    // Every row holds at least one count, so the walk ends within the file's size.
    for (uint64_t i = 0; i < element.count; ++i) {
      for (const PlyProperty& p : element.properties) {
        const size_t need = static_cast<size_t>(p.count_size > 0 ? p.count_size : p.size);
        if (bytes.size() - at < need) return Missing(element, i);
        if (p.count_size == 0) {
          at += need;
          continue;
        }
        const std::optional<uint64_t> items = BinaryCount(bytes, at, p, big_endian);
        if (!items)
          return fmt::format("element '{}' {} has a negative list count", element.name, i + 1);
        at += need;
        if (*items > (bytes.size() - at) / static_cast<uint64_t>(p.size))
          return Missing(element, i);
        at += static_cast<size_t>(*items * static_cast<uint64_t>(p.size));
      }
    }
  }
  return {};
}

std::string AsciiBodyProblem(const std::string& bytes, const PlyHeader& header) {
  size_t at = header.body_offset;
  // The next whitespace-separated word, or an empty view at the end. Whitespace as Words()
  // (istream) splits the header; not std::strchr, which finds a NUL byte in every string.
  const auto space = [](char c) {
    return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\v';
  };
  const auto next = [&]() -> std::string_view {
    while (at < bytes.size() && space(bytes[at])) ++at;
    const size_t start = at;
    while (at < bytes.size() && !space(bytes[at])) ++at;
    return std::string_view(bytes).substr(start, at - start);
  };
  for (const PlyElement& element : header.elements) {
    if (element.properties.empty()) continue;
    // Each row takes at least one word, so the walk ends within the file's size.
    for (uint64_t i = 0; i < element.count; ++i) {
      for (const PlyProperty& p : element.properties) {
        const std::string_view word = next();
        if (word.empty()) return Missing(element, i);
        if (p.count_size == 0) continue;
        uint64_t items = 0;
        const auto [ptr, ec] = std::from_chars(word.data(), word.data() + word.size(), items);
        if (ec != std::errc() || ptr != word.data() + word.size())
          return fmt::format("element '{}' {}: the list count '{}' is no whole number >= 0",
                             element.name, i + 1, word);
        for (uint64_t k = 0; k < items; ++k) {
          if (next().empty()) return Missing(element, i);
        }
      }
    }
  }
  return {};
}

}  // namespace

std::string PlyBodyProblem(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char magic[3] = {};
  // Other formats are not read twice. Assimp takes a file for PLY by its first three bytes,
  // "ply" in any case (it looped on "plY" and on "ply" followed by NULs): so does this check.
  const auto lower = [](char c) { return static_cast<char>(c | 0x20); };
  if (!in.read(magic, 3) || lower(magic[0]) != 'p' || lower(magic[1]) != 'l' ||
      lower(magic[2]) != 'y')
    return {};
  in.seekg(0);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::string problem;
  const std::optional<PlyHeader> header = ReadHeader(bytes, &problem);
  if (!header) return problem;
  return header->format == PlyFormat::kAscii ? AsciiBodyProblem(bytes, *header)
                                             : BinaryBodyProblem(bytes, *header);
}

}  // namespace vantage::detail

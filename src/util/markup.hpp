#pragma once
/// Escaping text for XML and HTML (attribute values and element text alike).
#include <string>
#include <string_view>

namespace vantage::detail {

/// U+FFFE and U+FFFF (UTF-8 EF BF BE/BF) are no XML characters, even escaped (the exporter
/// fuzzer's find, issue 44): written as U+FFFD.
inline bool IsXmlNonCharacterAt(std::string_view text, size_t i) {
  return text.size() >= i + 3 && static_cast<unsigned char>(text[i]) == 0xEF &&
         static_cast<unsigned char>(text[i + 1]) == 0xBF &&
         (static_cast<unsigned char>(text[i + 2]) & 0xFE) == 0xBE;
}

/// Replaces & < > " ' by their entities (&apos; is valid in XML and HTML5).
inline std::string MarkupEscape(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (IsXmlNonCharacterAt(text, i)) {
      out += "\xEF\xBF\xBD";
      i += 2;
      continue;
    }
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&apos;"; break;
      default: out += c;
    }
  }
  return out;
}

/// `text` for the inside of an XML comment, which may not hold "--" (nor end with '-'): the
/// second '-' of each pair, and a last '-', are written \u002d (issue 44: a sensor named
/// `cam--left` made cameras.urdf.xacro malformed). Nothing is unescaped in a comment: this is
/// only for people to read.
inline std::string CommentText(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (size_t i = 0; i < text.size(); ++i) {
    const bool after_dash = !out.empty() && out.back() == '-';
    if (IsXmlNonCharacterAt(text, i)) {
      out += "\xEF\xBF\xBD";
      i += 2;
    } else if (text[i] == '-' && (after_dash || i + 1 == text.size()))
      out += "\\u002d";
    else
      out += text[i];
  }
  return out;
}

}  // namespace vantage::detail

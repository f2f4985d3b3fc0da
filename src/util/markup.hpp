#pragma once
/// Escaping text for XML and HTML (attribute values and element text alike).
#include <string>
#include <string_view>

namespace vantage::detail {

/// Replaces & < > " ' by their entities (&apos; is valid in XML and HTML5).
inline std::string MarkupEscape(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (const char c : text) {
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

}  // namespace vantage::detail

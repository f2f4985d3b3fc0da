// A small XML reader that keeps line numbers and byte offsets (see xml.hpp for why sdformat's
// tree is not used). Covers what SDF files use: declaration, comments, CDATA, processing
// instructions, a DOCTYPE without entity definitions, the five predefined entities and character
// references.
#include "util/xml.hpp"

#include <fmt/format.h>

#include <cstdint>
#include <fstream>
#include <sstream>

#include "util/words.hpp"
#include "vantage/error.hpp"

namespace vantage::detail {
namespace {

/// Deeper nesting than any SDF file has: a guard against stack exhaustion on hostile input.
constexpr int kMaxDepth = 256;

bool IsSpace(char c) { return IsXmlSpace(c); }

bool IsNameStart(char c) {
  const auto u = static_cast<unsigned char>(c);
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_' || c == ':' || u >= 0x80;
}

bool IsNameChar(char c) { return IsNameStart(c) || (c >= '0' && c <= '9') || c == '-' || c == '.'; }

void AppendUtf8(uint32_t code, std::string* out) {
  if (code < 0x80) {
    out->push_back(static_cast<char>(code));
  } else if (code < 0x800) {
    out->push_back(static_cast<char>(0xC0 | (code >> 6)));
    out->push_back(static_cast<char>(0x80 | (code & 0x3F)));
  } else if (code < 0x10000) {
    out->push_back(static_cast<char>(0xE0 | (code >> 12)));
    out->push_back(static_cast<char>(0x80 | ((code >> 6) & 0x3F)));
    out->push_back(static_cast<char>(0x80 | (code & 0x3F)));
  } else {
    out->push_back(static_cast<char>(0xF0 | (code >> 18)));
    out->push_back(static_cast<char>(0x80 | ((code >> 12) & 0x3F)));
    out->push_back(static_cast<char>(0x80 | ((code >> 6) & 0x3F)));
    out->push_back(static_cast<char>(0x80 | (code & 0x3F)));
  }
}

class Parser {
 public:
  Parser(std::string_view text, const std::string& path) : text_(text), path_(path) {}

  XmlDocument Parse() {
    if (text_.substr(0, 3) == "\xEF\xBB\xBF") Advance(3);  // UTF-8 byte order mark
    XmlDocument doc;
    doc.path = path_;
    bool has_root = false;
    while (true) {
      SkipSpace();
      if (AtEnd()) break;
      if (Peek() != '<') Fail("text outside the root element");
      if (StartsWith("<?")) {
        SkipUntil("?>", "processing instruction");
      } else if (StartsWith("<!--")) {
        SkipComment();
      } else if (StartsWith("<!DOCTYPE")) {
        SkipDoctype();
      } else if (StartsWith("<!")) {
        Fail("unexpected '<!' outside the root element");
      } else {
        if (has_root) Fail("a second root element — an XML file has exactly one");
        doc.root = ParseElement(0);
        has_root = true;
      }
    }
    if (!has_root) Fail("no root element (empty file?)");
    return doc;
  }

 private:
  [[noreturn]] void Fail(const std::string& what) const { FailAt(line_, what); }
  [[noreturn]] void FailAt(int line, const std::string& what) const {
    throw InputError(AtPlace(path_, line, "malformed XML: " + what));
  }

  bool AtEnd() const { return pos_ >= text_.size(); }
  char Peek() const { return text_[pos_]; }
  bool StartsWith(std::string_view s) const { return text_.substr(pos_, s.size()) == s; }
  void Advance(size_t n = 1) {
    for (size_t i = 0; i < n && pos_ < text_.size(); ++i, ++pos_) {
      if (text_[pos_] == '\n') ++line_;
    }
  }
  void SkipSpace() {
    while (!AtEnd() && IsSpace(Peek())) Advance();
  }
  void SkipUntil(std::string_view end, const char* what) {
    const int start = line_;
    const size_t found = text_.find(end, pos_);
    if (found == std::string_view::npos) FailAt(start, fmt::format("unterminated {}", what));
    Advance(found + end.size() - pos_);
  }
  void SkipComment() {
    const int start = line_;
    Advance(4);
    const size_t found = text_.find("--", pos_);
    if (found == std::string_view::npos) FailAt(start, "unterminated comment (missing '-->')");
    Advance(found - pos_);
    if (!StartsWith("-->")) Fail("'--' inside a comment");
    Advance(3);
  }
  void SkipDoctype() {
    const int start = line_;
    int bracket = 0;
    while (!AtEnd()) {
      const char c = Peek();
      Advance();
      if (c == '[') ++bracket;
      if (c == ']') --bracket;
      if (c == '>' && bracket <= 0) return;
    }
    FailAt(start, "unterminated DOCTYPE");
  }

  std::string ParseName(const char* what) {
    if (AtEnd() || !IsNameStart(Peek())) Fail(fmt::format("expected {} name", what));
    const size_t start = pos_;
    while (!AtEnd() && IsNameChar(Peek())) Advance();
    return std::string(text_.substr(start, pos_ - start));
  }

  /// Decodes an entity or character reference at '&' and appends it.
  void ParseReference(std::string* out) {
    const size_t end = text_.find(';', pos_);
    if (end == std::string_view::npos || end - pos_ > 12)
      Fail("'&' not followed by an entity such as &amp; — write & as &amp;");
    const std::string_view name = text_.substr(pos_ + 1, end - pos_ - 1);
    if (name == "lt") {
      out->push_back('<');
    } else if (name == "gt") {
      out->push_back('>');
    } else if (name == "amp") {
      out->push_back('&');
    } else if (name == "quot") {
      out->push_back('"');
    } else if (name == "apos") {
      out->push_back('\'');
    } else if (!name.empty() && name[0] == '#') {
      const bool hex = name.size() > 1 && (name[1] == 'x' || name[1] == 'X');
      const std::string_view digits = name.substr(hex ? 2 : 1);
      uint32_t code = 0;
      bool ok = !digits.empty() && digits.size() <= 8;
      for (char c : digits) {
        int v = -1;
        if (c >= '0' && c <= '9') v = c - '0';
        if (hex && c >= 'a' && c <= 'f') v = c - 'a' + 10;
        if (hex && c >= 'A' && c <= 'F') v = c - 'A' + 10;
        if (v < 0) ok = false;
        if (ok) code = code * (hex ? 16 : 10) + static_cast<uint32_t>(v);
      }
      if (!ok || code == 0 || code > 0x10FFFF)
        Fail(fmt::format("bad character reference '&{};'", name));
      AppendUtf8(code, out);
    } else {
      Fail(fmt::format("unknown entity '&{};' — write & as &amp;", name));
    }
    Advance(end + 1 - pos_);
  }

  XmlElement ParseElement(int depth) {
    if (depth >= kMaxDepth) Fail(fmt::format("elements nested deeper than {} levels", kMaxDepth));
    XmlElement element;
    element.line = line_;
    element.begin = pos_;
    Advance();  // '<'
    element.name = ParseName("element");
    // Attributes.
    while (true) {
      const bool had_space = !AtEnd() && IsSpace(Peek());
      SkipSpace();
      if (AtEnd()) FailAt(element.line, fmt::format("unterminated tag <{}>", element.name));
      if (Peek() == '>' || StartsWith("/>")) break;
      if (!had_space) Fail(fmt::format("expected white space, '>' or '/>' in <{}>", element.name));
      std::string key = ParseName("attribute");
      SkipSpace();
      if (AtEnd() || Peek() != '=')
        Fail(fmt::format("attribute '{}' of <{}> has no value — write {}=\"...\"", key,
                         element.name, key));
      Advance();
      SkipSpace();
      if (AtEnd() || (Peek() != '"' && Peek() != '\''))
        Fail(fmt::format("value of attribute '{}' must be quoted", key));
      const char quote = Peek();
      Advance();
      std::string value;
      while (true) {
        if (AtEnd()) Fail(fmt::format("unterminated value of attribute '{}'", key));
        const char c = Peek();
        if (c == quote) break;
        if (c == '<') Fail(fmt::format("'<' inside the value of attribute '{}'", key));
        if (c == '&') {
          ParseReference(&value);
        } else {
          value.push_back(c);
          Advance();
        }
      }
      Advance();  // closing quote
      // Names enter here (SDF, URDF): "&#10;" or "&#1;" in one would break the CSV and XML
      // outputs (issue 15). No attribute of these formats takes a control character.
      if (const std::string problem = NameProblem(value); !problem.empty())
        throw InputError(AtPlace(path_, line_,
                                 fmt::format("<{}> {} '{}' {}", element.name, key,
                                             Escaped(value), problem)));
      for (const auto& [k, v] : element.attributes) {
        if (k == key) Fail(fmt::format("attribute '{}' given twice in <{}>", key, element.name));
      }
      element.attributes.emplace_back(std::move(key), std::move(value));
    }
    if (StartsWith("/>")) {
      Advance(2);
      element.content_begin = element.end = pos_;
      return element;
    }
    Advance();  // '>'
    element.content_begin = pos_;
    // Content.
    while (true) {
      if (AtEnd())
        FailAt(element.line,
               fmt::format("<{}> is never closed — add </{}>", element.name, element.name));
      const char c = Peek();
      if (c == '&') {
        ParseReference(&element.text);
      } else if (c != '<') {
        element.text.push_back(c);
        Advance();
      } else if (StartsWith("</")) {
        const int close_line = line_;
        Advance(2);
        const std::string name = ParseName("closing tag");
        SkipSpace();
        if (AtEnd() || Peek() != '>') Fail(fmt::format("expected '>' after </{}", name));
        Advance();
        if (name != element.name) {
          FailAt(close_line,
                 fmt::format("</{}> closes <{}> opened at line {} — the tags must match", name,
                             element.name, element.line));
        }
        element.end = pos_;
        return element;
      } else if (StartsWith("<!--")) {
        SkipComment();
      } else if (StartsWith("<![CDATA[")) {
        const int start = line_;
        Advance(9);
        const size_t end = text_.find("]]>", pos_);
        if (end == std::string_view::npos) FailAt(start, "unterminated CDATA section");
        element.text.append(text_.substr(pos_, end - pos_));
        Advance(end + 3 - pos_);
      } else if (StartsWith("<?")) {
        SkipUntil("?>", "processing instruction");
      } else if (StartsWith("<!")) {
        Fail("unexpected '<!' inside an element");
      } else {
        element.children.push_back(ParseElement(depth + 1));
      }
    }
  }

  std::string_view text_;
  const std::string& path_;
  size_t pos_ = 0;
  int line_ = 1;
};

}  // namespace

const XmlElement* XmlElement::Child(std::string_view child_name) const {
  for (const XmlElement& child : children) {
    if (child.name == child_name) return &child;
  }
  return nullptr;
}

std::vector<const XmlElement*> XmlElement::Children(std::string_view child_name) const {
  std::vector<const XmlElement*> found;
  for (const XmlElement& child : children) {
    if (child.name == child_name) found.push_back(&child);
  }
  return found;
}

const std::string* XmlElement::Attribute(std::string_view key) const {
  for (const auto& [k, v] : attributes) {
    if (k == key) return &v;
  }
  return nullptr;
}

std::string XmlElement::Trimmed() const { return TrimXmlSpace(text); }

bool IsXmlSpace(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }

std::string TrimXmlSpace(std::string_view text) {
  size_t begin = 0;
  size_t end = text.size();
  while (begin < end && IsXmlSpace(text[begin])) ++begin;
  while (end > begin && IsXmlSpace(text[end - 1])) --end;
  return std::string(text.substr(begin, end - begin));
}

XmlDocument ParseXml(std::string_view text, const std::string& path) {
  return Parser(text, path).Parse();
}

XmlDocument ReadXmlFile(const std::string& path) {
  // A device or a pipe is refused before it is read (issue 15: /dev/zero ran out of memory).
  const std::string text = ReadInputFile(path, "file");
  CheckUtf8File(text, path);  // names and paths go into report.json, which is UTF-8
  return ParseXml(text, path);
}

}  // namespace vantage::detail

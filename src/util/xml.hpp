#pragma once
/// A small non-validating XML reader for SDF worlds, model files and model.config files.
///
/// Why vantage keeps its own XML reader instead of libsdformat's element tree:
/// - constellation.world (report/gazebo_export.cpp) is the input world edited as text, so that
///   everything vantage does not change keeps its exact bytes (comments, plugins, physics, GUI).
///   The edit cuts and copies elements by their source byte offsets (`begin`, `content_begin`,
///   `end` below) and finds the sensors' elements by their lines; sdformat's elements carry no
///   byte offsets, and writing its tree back out reformats the whole file.
/// - Errors point at the offending line (GAZEBO.md, STYLE.md "Errors"): once sdformat has
///   expanded an `<include>`, the include element itself, every child of a `<plugin>` and the
///   include's overriding `<pose>` carry no line number (or the model file's), and malformed XML
///   is only printed to the console, without an Errors entry.
/// It lives in util/ because the scene reader (scene/sdf/) and the world writer (report/) both
/// use it.
#include <cstddef>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace vantage::detail {

/// One XML element: its name, attributes, directly contained character data and children.
struct XmlElement {
  std::string name;
  std::vector<std::pair<std::string, std::string>> attributes;  ///< in document order
  std::string text;  ///< character data directly inside (entities decoded, CDATA included)
  std::vector<XmlElement> children;
  int line = 0;  ///< 1-based line of the element's '<'
  /// Byte offsets in the parsed text: `begin` at the '<' of the start tag, `content_begin` just
  /// after the start tag's '>' (== `end` for an empty element `<a/>`), `end` just after the
  /// element's last '>'. They let a writer copy or cut the element's exact text.
  size_t begin = 0;
  size_t content_begin = 0;
  size_t end = 0;

  /// First child named `child_name`, or nullptr.
  const XmlElement* Child(std::string_view child_name) const;
  /// Every child named `child_name`, in document order.
  std::vector<const XmlElement*> Children(std::string_view child_name) const;
  /// Value of an attribute, or nullptr when absent.
  const std::string* Attribute(std::string_view key) const;
  /// `text` without leading and trailing white space.
  std::string Trimmed() const;
};

/// XML's white space (the S production): space, tab, line feed, carriage return.
bool IsXmlSpace(char c);
/// `text` without leading and trailing XML white space.
std::string TrimXmlSpace(std::string_view text);

/// A parsed file: its path (as given) and its root element.
struct XmlDocument {
  std::string path;
  XmlElement root;
};

/// Parses XML text. Throws InputError "path:line: malformed XML: ..." on the first
/// well-formedness error (unclosed or mismatched tags, bad attributes, unknown entities, text
/// outside the root, nesting deeper than 256 levels).
XmlDocument ParseXml(std::string_view text, const std::string& path);

/// Reads and parses a file. Throws InputError naming the file when it cannot be read.
XmlDocument ReadXmlFile(const std::string& path);

}  // namespace vantage::detail

// Ogre material scripts, read as far as the colour of the first pass (GAZEBO.md, "Targets"): the
// plugin found its targets by the colour Gazebo rendered, so the colour a script gives a visual
// decides whether it is a target (roles.cpp).
#include "scene/sdf/materials.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>

#include "util/run_files.hpp"
#include "util/words.hpp"

namespace vantage::detail {
namespace {

struct Token {
  std::string text;
  int line = 0;
  bool is_quoted = false;
};

/// Splits a script into words, quoted strings and braces, dropping comments.
std::vector<Token> Tokenize(std::string_view text) {
  std::vector<Token> tokens;
  int line = 1;
  size_t i = 0;
  while (i < text.size()) {
    const char c = text[i];
    if (c == '\n') {
      ++line;
      ++i;
    } else if (c == ' ' || c == '\t' || c == '\r') {
      ++i;
    } else if (text.substr(i, 2) == "//") {
      while (i < text.size() && text[i] != '\n') ++i;
    } else if (text.substr(i, 2) == "/*") {
      const size_t end = text.find("*/", i + 2);
      const size_t stop = end == std::string_view::npos ? text.size() : end + 2;
      line += static_cast<int>(std::count(text.begin() + i, text.begin() + stop, '\n'));
      i = stop;
    } else if (c == '{' || c == '}') {
      tokens.push_back(Token{std::string(1, c), line, false});
      ++i;
    } else if (c == '"') {
      const size_t end = text.find('"', i + 1);
      const size_t stop = end == std::string_view::npos ? text.size() : end;
      tokens.push_back(Token{std::string(text.substr(i + 1, stop - i - 1)), line, true});
      line += static_cast<int>(std::count(text.begin() + i, text.begin() + stop, '\n'));
      i = std::min(text.size(), stop + 1);
    } else {
      const size_t start = i;
      while (i < text.size() && text[i] != ' ' && text[i] != '\t' && text[i] != '\r' &&
             text[i] != '\n' && text[i] != '{' && text[i] != '}' && text.substr(i, 2) != "//" &&
             text.substr(i, 2) != "/*") {
        ++i;
      }
      tokens.push_back(Token{std::string(text.substr(start, i - start)), line, false});
    }
  }
  return tokens;
}

/// A statement (the words of one line) and, when a `{ }` block follows it, the block's content.
struct Node {
  std::vector<Token> words;
  std::vector<Node> children;
  bool is_block = false;
  int line = 0;
};

class TreeBuilder {
 public:
  explicit TreeBuilder(const std::vector<Token>& tokens) : tokens_(tokens) {}

  /// Reads statements until a '}' (consumed) or the end.
  std::vector<Node> Block(int depth, bool* is_closed) {
    std::vector<Node> nodes;
    Node pending;
    const auto flush = [&] {
      if (!pending.words.empty()) nodes.push_back(std::move(pending));
      pending = Node{};
    };
    while (pos_ < tokens_.size()) {
      const Token& token = tokens_[pos_];
      if (!token.is_quoted && token.text == "}") {
        ++pos_;
        flush();
        *is_closed = true;
        return nodes;
      }
      if (!token.is_quoted && token.text == "{") {
        ++pos_;
        // The block belongs to the statement on its line or, with '{' on a line of its own, to
        // the statement just before.
        Node header;
        if (!pending.words.empty()) {
          header = std::move(pending);
          pending = Node{};
        } else if (!nodes.empty() && !nodes.back().is_block) {
          header = std::move(nodes.back());
          nodes.pop_back();
        } else {
          header.line = token.line;
        }
        bool closed = false;
        if (depth < 64) {
          header.children = Block(depth + 1, &closed);
        } else {
          closed = SkipBlock();
        }
        header.is_block = true;
        // Unwinding from the innermost block out, the last one set is the outermost.
        if (!closed) unclosed_line_ = header.line;
        nodes.push_back(std::move(header));
        if (!closed) break;
        continue;
      }
      if (!pending.words.empty() && token.line != pending.line) flush();
      if (pending.words.empty()) pending.line = token.line;
      pending.words.push_back(token);
      ++pos_;
    }
    flush();
    *is_closed = false;
    return nodes;
  }

  /// The line of the outermost statement whose `{` the script never closes; 0 when all are.
  int unclosed_line() const { return unclosed_line_; }

 private:
  bool SkipBlock() {
    int level = 1;
    while (pos_ < tokens_.size()) {
      const Token& token = tokens_[pos_++];
      if (token.is_quoted) continue;
      if (token.text == "{") ++level;
      if (token.text == "}" && --level == 0) return true;
    }
    return false;
  }

  const std::vector<Token>& tokens_;
  size_t pos_ = 0;
  int unclosed_line_ = 0;
};

std::optional<double> ParseNumber(const std::string& s) {
  double value = 0;
  const char* begin = s.data();
  const char* end = s.data() + s.size();
  if (begin != end && *begin == '+') ++begin;
  const auto [ptr, ec] = std::from_chars(begin, end, value);
  if (ec != std::errc() || ptr != end || !std::isfinite(value)) return std::nullopt;
  return value;
}

const Node* FirstBlock(const std::vector<Node>& nodes, std::string_view keyword) {
  for (const Node& node : nodes) {
    if (node.is_block && !node.words.empty() && node.words[0].text == keyword) return &node;
  }
  return nullptr;
}

}  // namespace

std::optional<Rgb> MaterialColours::SegmentationColour() const {
  if (emissive) return emissive;
  return diffuse;
}

void MaterialColours::Override(const MaterialColours& over) {
  if (over.ambient) ambient = over.ambient;
  if (over.diffuse) diffuse = over.diffuse;
  if (over.emissive) emissive = over.emissive;
}

void MaterialLibrary::ParseScript(std::string_view text, const std::string& path) {
  const std::vector<Token> tokens = Tokenize(text);
  TreeBuilder builder(tokens);
  bool closed = false;
  std::vector<Node> top = builder.Block(0, &closed);
  if (closed) problems.push_back(fmt::format("{}: unbalanced '}}' in the material script", path));
  // Session 9: a script cut short was read as far as it went, without a word.
  if (builder.unclosed_line() > 0)
    problems.push_back(fmt::format("{}:{}: the '{{' of this block is never closed: the material "
                                   "script ends inside it (cut short?)",
                                   path, builder.unclosed_line()));
  for (const Node& node : top) {
    if (!node.is_block || node.words.empty() || node.words[0].text != "material") continue;
    if (node.words.size() < 2) {
      problems.push_back(fmt::format("{}:{}: material without a name", path, node.line));
      continue;
    }
    const std::string& name = node.words[1].text;
    MaterialColours colours;
    if (node.words.size() >= 4 && node.words[2].text == ":") {
      const MaterialColours* parent = Find(node.words[3].text);
      if (parent) {
        colours = *parent;
      } else {
        problems.push_back(fmt::format("{}:{}: material '{}' inherits unknown material '{}'", path,
                                       node.line, name, node.words[3].text));
      }
    }
    const Node* technique = FirstBlock(node.children, "technique");
    const Node* pass = technique ? FirstBlock(technique->children, "pass") : nullptr;
    if (pass) {
      MaterialColours own;
      for (const Node& entry : pass->children) {
        if (entry.is_block || entry.words.empty()) continue;
        const std::string& key = entry.words[0].text;
        std::optional<Rgb>* slot = key == "ambient"    ? &own.ambient
                                   : key == "diffuse"  ? &own.diffuse
                                   : key == "emissive" ? &own.emissive
                                                       : nullptr;
        if (!slot) continue;
        // `vertexcolour` takes the colour from the mesh: no fixed colour to segment on.
        if (entry.words.size() == 2 && entry.words[1].text == "vertexcolour") continue;
        Rgb rgb{};
        bool ok = entry.words.size() == 4 || entry.words.size() == 5;
        for (size_t i = 0; ok && i < 3; ++i) {
          const std::optional<double> v = ParseNumber(entry.words[i + 1].text);
          ok = v.has_value();
          if (ok) rgb[i] = *v;
        }
        if (!ok) {
          std::vector<std::string> values;
          for (size_t i = 1; i < entry.words.size(); ++i) values.push_back(entry.words[i].text);
          problems.push_back(fmt::format("{}:{}: '{} {}' of material '{}' is not 3 or 4 finite "
                                         "numbers: skipped, as Ogre skips it (the material has no "
                                         "{} colour of its own)",
                                         path, entry.line, key, fmt::join(values, " "), name, key));
          continue;
        }
        *slot = rgb;
      }
      colours.Override(own);
    }
    materials.emplace(name, colours);
  }
}

bool MaterialLibrary::LoadFile(const std::string& path) {
  // A folder, a device or a pipe is no script (issue 15: file:///dev/zero ran out of memory).
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return false;
  detail::NoteInputFile(path, "material script");
  std::string text;
  if (!ReadWholeFile(path, &text)) return false;
  ParseScript(text, path);
  return true;
}

const MaterialColours* MaterialLibrary::Find(const std::string& name) const {
  const auto it = materials.find(name);
  return it == materials.end() ? nullptr : &it->second;
}

std::array<int, 3> ToRgb255(const Rgb& colour) {
  std::array<int, 3> out{};
  for (size_t i = 0; i < 3; ++i)
    out[i] = static_cast<int>(std::lround(255.0 * std::clamp(colour[i], 0.0, 1.0)));
  return out;
}

}  // namespace vantage::detail

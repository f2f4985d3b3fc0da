#pragma once
/// Colours of Ogre material scripts (`.material`) as Gazebo classic applies them to visuals, and
/// the plugin's colour segmentation rule (GAZEBO.md, "Targets").
#include <array>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace vantage::detail {

/// An RGB colour with components in [0, 1] as written (alpha dropped).
using Rgb = std::array<double, 3>;

/// The colours a material sets; each is absent when the script/element does not set it.
struct MaterialColours {
  std::optional<Rgb> ambient;
  std::optional<Rgb> diffuse;
  std::optional<Rgb> emissive;

  /// The colour the plugin segments on: the emissive colour where set, else the diffuse one;
  /// nullopt when neither is set.
  std::optional<Rgb> SegmentationColour() const;
  /// Channels set in `over` replace those here (Gazebo applies inline colours after a script).
  void Override(const MaterialColours& over);
};

/// Materials of one or more Ogre scripts, by name.
struct MaterialLibrary {
  std::map<std::string, MaterialColours> materials;
  std::vector<std::string> problems;  ///< "file:line: ..." lines that were skipped

  /// Parses a script and adds its materials; an already known name keeps its first definition
  /// (Ogre refuses duplicates). Reads `material NAME [: PARENT] { technique { pass { ... } } }`:
  /// only the first pass of the first technique counts (what Ogre renders on a plain scene);
  /// `ambient`, `diffuse`, `emissive` take 3 or 4 numbers; comments (`//`, `/* */`), quoted
  /// names, other objects (programs, compositors), other keys and nested blocks are skipped.
  void ParseScript(std::string_view text, const std::string& path);
  /// Reads and parses a script file; false when it cannot be read.
  bool LoadFile(const std::string& path);
  const MaterialColours* Find(const std::string& name) const;
};

/// 0–255 integer colour of a [0, 1] colour as the renderer writes it: round(255·clamp(v, 0, 1)).
std::array<int, 3> ToRgb255(const Rgb& colour);

}  // namespace vantage::detail

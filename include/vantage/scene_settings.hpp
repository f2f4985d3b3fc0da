#pragma once
/// The selection settings a scene may declare, one row each (issue 42), in the util layer beside
/// SelectionSettings so that the scene readers see it: a YAML scene's `settings:` keys and the
/// Gazebo plugin's parameters, their ranges and messages, are read from the rows, and the
/// pipeline takes a scene's setting where the request gives no value of the same SelectOptions
/// field (RequestOverScene, selection_options.hpp).
#include <array>
#include <limits>
#include <optional>
#include <string_view>
#include <variant>

#include "vantage/settings.hpp"

namespace vantage {

/// One setting of SelectionSettings. Its member's type says how a scene writes it: a whole
/// number (at least `low`), a method's name, or a number within [low, high] (low excluded where
/// low_open).
struct SceneSelectionSetting {
  /// The SelectOptions field it sets: also the field of its selection option (kSelectionOptions)
  /// and its key in SelectionSettings::lines.
  std::string_view field;
  std::variant<int SelectionSettings::*, double SelectionSettings::*,
               std::optional<double> SelectionSettings::*,
               std::optional<Method> SelectionSettings::*>
      member;
  /// Its key under a YAML scene's `settings:`; "ransac.iterations" is `iterations` in the map
  /// `settings.ransac`.
  std::string_view yaml_key;
  /// The original Gazebo plugin's parameter (docs/GAZEBO.md), empty where it has none.
  std::string_view plugin_parameter = {};
  double low = 0;
  bool low_open = false;
  double high = std::numeric_limits<double>::infinity();
  /// A YAML scene's error for a number out of range, after "settings.KEY = VALUE ".
  std::string_view out_of_range = {};
  /// The plugin gives the number in percent; `plugin_example` is a valid value for its errors.
  bool plugin_percent = false;
  std::string_view plugin_example = {};
  /// An objective beyond coverage (a whole number from 2 on): a scene gives at most one.
  bool objective = false;

  /// Whether a number lies outside its range; `scale` units to the setting's one (100: percent).
  constexpr bool OutOfRange(double value, double scale = 1) const {
    return value < low * scale || (low_open && value == low * scale) || value > high * scale;
  }
};

inline constexpr std::array<SceneSelectionSetting, 7> kSceneSelectionSettings = {{
    {.field = "n",
     .member = &SelectionSettings::n,
     .yaml_key = "n",
     .plugin_parameter = "numberOfIntendedSensors",
     .low = 1},
    {.field = "method", .member = &SelectionSettings::method, .yaml_key = "method"},
    {.field = "ransac_iterations",
     .member = &SelectionSettings::ransac_iterations,
     .yaml_key = "ransac.iterations",
     .plugin_parameter = "ransacNumberOfIterations",
     .low = 1},
    {.field = "ransac_stop_coverage",
     .member = &SelectionSettings::ransac_stop_coverage,
     .yaml_key = "ransac.stop_coverage",
     .plugin_parameter = "ransacSurfacePercentageStopThreshold",
     .high = 1,
     .out_of_range = "is a fraction — give a value in [0, 1] (e.g. 0.8 for 80 %)",
     .plugin_percent = true,
     .plugin_example = "90"},
    {.field = "goal",
     .member = &SelectionSettings::goal,
     .yaml_key = "goal",
     .low_open = true,
     .high = 1,
     .out_of_range = "is a coverage fraction — give a value in (0, 1], e.g. 0.9 for 90 %",
     .objective = true},
    {.field = "k", .member = &SelectionSettings::k, .yaml_key = "k", .low = 1, .objective = true},
    {.field = "budget",
     .member = &SelectionSettings::budget,
     .yaml_key = "budget",
     .out_of_range = "must be >= 0 — the most the sensors may cost together",
     .objective = true},
}};

}  // namespace vantage

#pragma once
/// The selection settings a scene may declare, one row each (issue 42), in the util layer beside
/// SelectionSettings: the pipeline takes a scene's setting where the request gives no value of
/// the same SelectOptions field (RequestOverScene, selection_options.hpp).
#include <array>
#include <optional>
#include <string_view>
#include <variant>

#include "vantage/settings.hpp"

namespace vantage {

/// One setting of SelectionSettings.
struct SceneSelectionSetting {
  /// The SelectOptions field it sets: also the field of its selection option (kSelectionOptions)
  /// and its key in SelectionSettings::lines.
  std::string_view field;
  std::variant<int SelectionSettings::*, double SelectionSettings::*,
               std::optional<double> SelectionSettings::*,
               std::optional<Method> SelectionSettings::*>
      member;
};

inline constexpr std::array<SceneSelectionSetting, 7> kSceneSelectionSettings = {{
    {"n", &SelectionSettings::n},
    {"method", &SelectionSettings::method},
    {"ransac_iterations", &SelectionSettings::ransac_iterations},
    {"ransac_stop_coverage", &SelectionSettings::ransac_stop_coverage},
    {"goal", &SelectionSettings::goal},
    {"k", &SelectionSettings::k},
    {"budget", &SelectionSettings::budget},
}};

}  // namespace vantage

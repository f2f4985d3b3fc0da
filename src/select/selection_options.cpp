// The selection options' table (selection_options.hpp): whether an option is given, its value
// into SelectOptions, the scene's settings under a request, a row by its keyword.
#include "vantage/selection_options.hpp"

#include <type_traits>

#include "vantage/error.hpp"
#include "vantage/scene_settings.hpp"

namespace vantage {

bool SelectionOption::GivenIn(const SelectionRequest& request) const {
  return std::visit(
      [&](auto pointer) -> bool {
        const auto& value = request.*pointer;
        if constexpr (std::is_same_v<std::decay_t<decltype(value)>, bool>)
          return value;
        else
          return value.has_value();
      },
      member);
}

namespace {

// Whether Given is std::optional<Field>.
template <typename Given, typename Field>
constexpr bool kOptionalOf = false;
template <typename Field>
constexpr bool kOptionalOf<std::optional<Field>, Field> = true;

}  // namespace

void SelectionOption::ApplyTo(const SelectionRequest& request, SelectOptions* options) const {
  std::visit(
      [&](auto from, auto to) {
        if constexpr (!std::is_same_v<decltype(to), std::monostate>) {
          using Given = std::decay_t<decltype(request.*from)>;
          using Field = std::decay_t<decltype(options->*to)>;
          const Given& value = request.*from;
          if constexpr (std::is_same_v<Given, Field>) {  // bool, or an optional kept optional
            options->*to = value;
          } else if constexpr (kOptionalOf<Given, Field>) {
            if (value) options->*to = *value;
          } else {
            throw InternalError("selection option " + std::string(flag) +
                                ": its SelectOptions field has another type");
          }
        }
      },
      member, target);
}

SelectionRequest RequestOverScene(const SelectionRequest& request,
                                  const SelectionSettings& scene) {
  bool gives_objective = false;
  for (const SelectionOption& option : kSelectionOptions)
    gives_objective = gives_objective || (option.objective && option.GivenIn(request));
  SelectionRequest merged = request;
  for (const SelectionOption& option : kSelectionOptions) {
    if (option.GivenIn(request) || (gives_objective && option.objective)) continue;
    for (const SceneSelectionSetting& setting : kSceneSelectionSettings) {
      if (setting.field != option.field) continue;
      std::visit(
          [&](auto to, auto from) {
            using Given = std::decay_t<decltype(merged.*to)>;
            using Declared = std::decay_t<decltype(scene.*from)>;
            // Both optional, or the scene's a plain value the request holds as optional.
            if constexpr (std::is_same_v<Given, Declared> || kOptionalOf<Given, Declared>) {
              merged.*to = scene.*from;
            } else {
              throw InternalError("scene setting " + std::string(setting.field) +
                                  ": its selection option has another type");
            }
          },
          option.member, setting.member);
    }
  }
  return merged;
}

std::span<const SelectionOption> SelectionOptionTable() { return kSelectionOptions; }

const SelectionOption& SelectionOptionOfKeyword(std::string_view keyword) {
  for (const SelectionOption& option : kSelectionOptions)
    if (option.keyword == keyword) return option;
  throw InternalError("no selection option has the keyword " + std::string(keyword));
}

}  // namespace vantage

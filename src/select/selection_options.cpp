// The selection options' table (selection_options.hpp): whether an option is given, a row by its
// keyword.
#include "vantage/selection_options.hpp"

#include "vantage/error.hpp"

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

std::span<const SelectionOption> SelectionOptionTable() { return kSelectionOptions; }

const SelectionOption& SelectionOptionOfKeyword(std::string_view keyword) {
  for (const SelectionOption& option : kSelectionOptions)
    if (option.keyword == keyword) return option;
  throw InternalError("no selection option has the keyword " + std::string(keyword));
}

}  // namespace vantage

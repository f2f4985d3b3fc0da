#pragma once
/// report.json's `inputs` block (docs/outputs.md): written by ReportJson, read back by
/// LoadConstellation so that `render` and `evaluate` reproduce a run from its folder.
#include <nlohmann/json.hpp>
#include <string>

#include "vantage/report.hpp"

namespace vantage::detail {

nlohmann::ordered_json RunInputsJson(const RunInputs& inputs);

/// Reads the block back; InputError "`where`: inputs.<key> must be ..." for a value of the wrong
/// type. Ranges are checked where the values are used, as for the command line's.
RunInputs ParseRunInputs(const nlohmann::json& j, const std::string& where);

}  // namespace vantage::detail

#pragma once
/// report.json's installation constraints (docs/outputs.md, docs/constraints.md): the run's
/// `constraints` block and each result's check.
#include <nlohmann/json.hpp>

#include "vantage/report.hpp"

namespace vantage::detail {

/// The run's block: interference (overlap, projecting candidates, conflicting pairs),
/// calibration rule, minimum separation, whether selection obeyed them.
nlohmann::ordered_json ConstraintsJson(const ConstraintsInfo& info);

/// A keep-out box as report.json and report.html give it: `name`, `center` (world frame [m]),
/// `size` (edges along the box's own axes [m]) and `quaternion` (world_from_box's rotation,
/// [w, x, y, z]).
nlohmann::ordered_json KeepOutBoxJson(const KeepOutBox& box);

/// One result's check: the conflicts it breaks, those it avoided, its overlap graph (edges with
/// their common cells) and whether that graph is connected.
nlohmann::ordered_json ResultConstraintsJson(const Selection& selection,
                                             const ConstraintsInfo& info,
                                             const VisibilityFile& data);

}  // namespace vantage::detail

#pragma once
/// report.json's and report.html's `by_type` (optimize --by-type, issue 43; docs/outputs.md).
#include <nlohmann/json.hpp>

#include "vantage/report.hpp"

namespace vantage::detail {

/// Per type its best answer at each n (`types`), and the run's own best per n (`mix`) with the
/// types it uses, the best single type at that n and what mixing gains over it.
nlohmann::ordered_json ByTypeJson(const TypeComparisonTable& table, const VisibilityFile& data);

}  // namespace vantage::detail

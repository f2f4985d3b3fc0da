// report.json's and report.html's `by_type` (optimize --by-type, issue 43).
#include "report/by_type_json.hpp"

#include <algorithm>

namespace vantage::detail {

using nlohmann::ordered_json;

// report.json's `by_type` (optimize --by-type, issue 43): per type its best answer at each n,
// and the run's own best per n with what it gains over the best single type.
ordered_json ByTypeJson(const TypeComparisonTable& table, const VisibilityFile& data) {
  const auto answer = [&](const Selection& s) {
    ordered_json r = {{"n", s.n}, {"method", s.method}};
    ordered_json names = ordered_json::array();
    for (uint32_t index : s.chosen) names.push_back(data.candidates.at(index).name);
    r["sensors"] = std::move(names);
    r["coverage"] = s.coverage;
    if (s.upper_bound) r["upper_bound"] = *s.upper_bound;
    r["optimal"] = s.proven_optimal;
    // null: a chosen sensor's vendor publishes no price (issue 43).
    r["total_cost"] = s.cost ? ordered_json(*s.cost) : ordered_json();
    return r;
  };
  ordered_json types = ordered_json::array();
  for (const TypeComparison& type : table.types) {
    ordered_json best = ordered_json::array();
    for (const Selection& s : type.best) best.push_back(answer(s));
    ordered_json row = {{"type", type.type_id}, {"name", type.name},
                        {"candidates", type.candidates},
                        {"unit_cost", type.unit_cost_given ? ordered_json(type.unit_cost)
                                                           : ordered_json()}};
    // Under the physical model, a type it cannot judge says so (issue 43).
    if (table.physical && !type.physical_gap.empty()) row["physical_model"] = type.physical_gap;
    row["best"] = std::move(best);
    types.push_back(std::move(row));
  }
  ordered_json mix = ordered_json::array();
  for (const Selection& s : table.mix) {
    ordered_json r = answer(s);
    // The best single type at this n (ties: the first) and what mixing gains over it.
    const TypeComparison* top = nullptr;
    const Selection* top_answer = nullptr;
    for (const TypeComparison& type : table.types) {
      for (const Selection& t : type.best) {
        if (t.n == s.n && (!top_answer || t.coverage > top_answer->coverage)) {
          top = &type;
          top_answer = &t;
        }
      }
    }
    ordered_json types_used = ordered_json::array();  // in the order of `types`
    for (const TypeComparison& type : table.types) {
      const bool used = std::any_of(s.chosen.begin(), s.chosen.end(), [&](uint32_t index) {
        return data.candidates.at(index).type_id == type.type_id;
      });
      if (used) types_used.push_back(type.type_id);
    }
    r["types"] = std::move(types_used);
    if (top) {
      r["best_single_type"] = top->type_id;
      r["best_single_coverage"] = top_answer->coverage;
      r["gain"] = s.coverage - top_answer->coverage;
    }
    mix.push_back(std::move(r));
  }
  return {{"types", std::move(types)}, {"mix", std::move(mix)}};
}

}  // namespace vantage::detail

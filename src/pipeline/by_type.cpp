// `optimize --by-type` (issue 43, "which sensor to buy"): the run's own selection over each
// sensor type's candidates alone, beside the run's best over all of them. No new solver: each
// type's table is what `optimize` would answer for a scene holding only that type's candidates.
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <map>

#include "pipeline/common.hpp"

namespace vantage::detail {
namespace {

// The best of `answers` at each n from first_n to last_n (highest coverage; ties: the first), its
// bound the least any answer of that n proved, optimal when an answer of that n was proven optimal
// with no more coverage than it. Answers of other objectives (k) than `k` are ignored.
std::vector<Selection> BestPerN(const std::vector<Selection>& answers, int first_n, int last_n,
                                int k) {
  std::vector<Selection> best;
  for (int n = first_n; n <= last_n; ++n) {
    const Selection* top = nullptr;
    std::optional<double> bound;
    for (const Selection& s : answers) {
      if (s.n != n || s.k != k) continue;
      if (!top || s.coverage > top->coverage) top = &s;
      if (s.upper_bound) bound = std::min(bound.value_or(*s.upper_bound), *s.upper_bound);
    }
    if (!top) continue;
    Selection chosen = *top;
    chosen.upper_bound = bound;
    chosen.proven_optimal = std::any_of(answers.begin(), answers.end(), [&](const Selection& s) {
      return s.n == n && s.k == k && s.proven_optimal && s.coverage <= chosen.coverage;
    });
    best.push_back(std::move(chosen));
  }
  return best;
}

// The chosen sensors' summed unit cost; none when one of them has no price (issue 43).
std::optional<double> TotalCost(const Selection& s, std::span<const Candidate> candidates) {
  double cost = 0;
  for (uint32_t i : s.chosen) {
    if (!UnitCostGiven(candidates[i].sensor, candidates[i].type_id)) return std::nullopt;
    cost += candidates[i].sensor.cost;
  }
  return cost;
}

}  // namespace

TypeComparisonTable CompareTypes(const VisibilityFile& data, const SelectOptions& options,
                                 const std::vector<Selection>& results,
                                 const std::vector<Selection>& curve) {
  const std::span<const Candidate> candidates = data.candidates;
  const int first_n = options.objective() == Objective::kKCoverage ? options.k : 1;
  const int k = options.objective() == Objective::kKCoverage ? options.k : 1;
  // Types in the order of their first candidates.
  std::vector<std::string> order;
  std::map<std::string, std::vector<uint32_t>> members;
  for (uint32_t i = 0; i < candidates.size(); ++i) {
    std::vector<uint32_t>& list = members[candidates[i].type_id];
    if (list.empty()) order.push_back(candidates[i].type_id);
    list.push_back(i);
  }
  TypeComparisonTable table;
  table.physical = data.physical;
  for (const std::string& type_id : order) {
    const std::vector<uint32_t>& of_type = members[type_id];
    TypeComparison type;
    type.type_id = type_id;
    const SensorType& sensor = candidates[of_type.front()].sensor;
    type.name = sensor.name.empty() ? type_id : sensor.name;
    type.candidates = of_type.size();
    type.unit_cost = sensor.cost;
    type.unit_cost_given = UnitCostGiven(sensor, type_id);
    type.physical_gap = PhysicalModelGap(sensor, type_id);
    const int last_n = std::min(options.n, static_cast<int>(of_type.size()));
    if (last_n < first_n) {  // fewer candidates than k-coverage needs
      table.types.push_back(std::move(type));
      continue;
    }
    // The type's own problem: its observations, its conflicts renumbered, the same options.
    std::vector<Observation> observations;
    std::vector<int64_t> local(candidates.size(), -1);
    for (uint32_t i : of_type) {
      local[i] = static_cast<int64_t>(observations.size());
      observations.push_back(data.observations[i]);
    }
    SelectOptions own = options;
    own.constraints.conflicts.clear();
    for (const Conflict& c : options.constraints.conflicts) {
      if (local[c.a] < 0 || local[c.b] < 0) continue;
      Conflict renumbered = c;
      renumbered.a = static_cast<uint32_t>(local[c.a]);
      renumbered.b = static_cast<uint32_t>(local[c.b]);
      own.constraints.conflicts.push_back(renumbered);
    }
    std::vector<Selection> answers;
    // --method all answers every n up to its n in one call; a single method answers one n.
    const bool every_n = options.method == Method::kAll;
    for (int n = every_n ? last_n : first_n; n <= last_n; ++n) {
      own.n = n;
      for (Selection& s : SelectExplained(observations, data.reference, own))
        answers.push_back(std::move(s));
    }
    for (Selection& s : answers)
      for (uint32_t& i : s.chosen) i = of_type[i];  // back to the run's candidate indices
    type.best = BestPerN(answers, first_n, last_n, k);
    for (Selection& s : type.best) s.cost = TotalCost(s, candidates);
    table.types.push_back(std::move(type));
  }
  std::vector<Selection> all = results;
  all.insert(all.end(), curve.begin(), curve.end());
  table.mix = BestPerN(all, first_n, options.n, k);
  for (Selection& s : table.mix) s.cost = TotalCost(s, candidates);
  spdlog::info("by type: {} types compared at n = {}..{}", table.types.size(), first_n, options.n);
  return table;
}

}  // namespace vantage::detail

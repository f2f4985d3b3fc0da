// Robustness read-outs (issue 9): failures, near-optimal alternatives, shrunk fields of view.
#include "vantage/robustness.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "vantage/error.hpp"

namespace vantage {

std::vector<SensorFailure> SensorFailures(const CoverageEvaluator& evaluator,
                                          std::span<const uint32_t> chosen, int k,
                                          std::optional<uint32_t> min_points) {
  std::vector<SensorFailure> failures;
  std::vector<uint32_t> others;
  for (size_t i = 0; i < chosen.size(); ++i) {
    others.assign(chosen.begin(), chosen.end());
    others.erase(others.begin() + static_cast<std::ptrdiff_t>(i));
    failures.push_back({chosen[i], evaluator.CoverageUnder(others, k, min_points)});
  }
  return failures;
}

namespace {

// CoverageUnder(others + {j}) for every j in turn, counted incrementally: the others' counts once,
// then each j's list added and taken back. The same integer count as from scratch (a cell counts
// once its final tally reaches the threshold, whatever the order), in a pass over j's list
// instead of over R and every chosen list (the alternatives of 10 sensors among 1,000 candidates
// were 10,000 such passes).
class CoverageWithOneMore {
 public:
  CoverageWithOneMore(const CoverageEvaluator& evaluator, int k,
                      std::optional<uint32_t> min_points)
      : observations_(evaluator.observations()),
        threshold_(min_points ? *min_points : static_cast<uint64_t>(k)),
        points_(min_points.has_value()),
        tally_(evaluator.reference_size(), 0) {
    VANTAGE_CHECK(threshold_ >= 1);
  }

  void SetOthers(std::span<const uint32_t> others) {
    std::fill(tally_.begin(), tally_.end(), 0);
    base_ = 0;
    for (const uint32_t c : others) base_ += Add(c);
  }

  double With(uint32_t j) {
    if (tally_.empty()) return 0.0;
    const size_t gained = Add(j);
    Remove(j);
    return static_cast<double>(base_ + gained) / static_cast<double>(tally_.size());
  }

 private:
  uint64_t Weight(const Observation& o, size_t i) const { return points_ ? o.reference_hits[i] : 1; }

  // Adds c's tallies; returns the cells that reach the threshold.
  size_t Add(uint32_t c) {
    VANTAGE_CHECK(c < observations_.size());
    const Observation& o = observations_[c];
    VANTAGE_CHECK(!points_ || o.has_point_counts());
    size_t reached = 0;
    for (size_t i = 0; i < o.reference_indices.size(); ++i) {
      const uint32_t cell = o.reference_indices[i];
      VANTAGE_CHECK(cell < tally_.size());
      const uint64_t before = tally_[cell];
      tally_[cell] += Weight(o, i);
      if (before < threshold_ && tally_[cell] >= threshold_) ++reached;
    }
    return reached;
  }

  void Remove(uint32_t c) {
    const Observation& o = observations_[c];
    for (size_t i = 0; i < o.reference_indices.size(); ++i)
      tally_[o.reference_indices[i]] -= Weight(o, i);
  }

  std::span<const Observation> observations_;
  uint64_t threshold_;
  bool points_;
  std::vector<uint64_t> tally_;
  size_t base_ = 0;
};


double TotalCostOf(std::span<const double> costs, std::span<const uint32_t> chosen) {
  double total = 0;
  for (const uint32_t i : chosen) total += costs[i];
  return total;
}

}  // namespace

std::vector<Alternative> NearOptimalAlternatives(const CoverageEvaluator& evaluator,
                                                 std::span<const uint32_t> chosen,
                                                 const AlternativeRules& rules) {
  const auto candidate_count = static_cast<uint32_t>(evaluator.observations().size());
  const bool priced = !rules.costs.empty();
  VANTAGE_CHECK(!priced || rules.costs.size() == candidate_count);
  const double best = evaluator.CoverageUnder(chosen, rules.k, rules.min_points);
  const double chosen_cost = priced ? TotalCostOf(rules.costs, chosen) : 0.0;
  // A small tolerance keeps ties at exactly `within`, the goal or the budget from depending on
  // float rounding.
  const auto keeps_rules = [&](const Alternative& a) {
    if (a.coverage < best - rules.within - 1e-12) return false;
    if (rules.at_least && a.coverage < *rules.at_least) return false;
    return !(rules.budget && a.cost && *a.cost > *rules.budget * (1 + 1e-12));
  };
  // Strictly better replacements first; ties keep the lower candidate index.
  const auto better = [&](const Alternative& a, const Alternative& b) {
    if (rules.cheapest && *a.cost != *b.cost) return *a.cost < *b.cost;
    return a.coverage > b.coverage;
  };
  std::vector<Alternative> alternatives;
  std::vector<uint32_t> swapped(chosen.begin(), chosen.end());
  std::vector<uint32_t> others;
  CoverageWithOneMore counter(evaluator, rules.k, rules.min_points);
  for (size_t slot = 0; slot < chosen.size(); ++slot) {
    if (std::find(rules.kept.begin(), rules.kept.end(), chosen[slot]) != rules.kept.end())
      continue;  // installed
    others.assign(chosen.begin(), chosen.end());
    others.erase(others.begin() + static_cast<std::ptrdiff_t>(slot));
    counter.SetOthers(others);
    std::optional<Alternative> best_for_slot;
    for (uint32_t j = 0; j < candidate_count; ++j) {
      if (std::find(chosen.begin(), chosen.end(), j) != chosen.end()) continue;
      swapped[slot] = j;
      Alternative a{swapped, chosen[slot], j, counter.With(j), std::nullopt};
      if (priced) a.cost = chosen_cost - rules.costs[chosen[slot]] + rules.costs[j];
      // Unpriced, the rules are checked on the slot's best only (the same answer: its coverage
      // is the most any replacement keeps); priced, the best must be among those keeping them.
      if (priced && !keeps_rules(a)) continue;
      if (!best_for_slot || better(a, *best_for_slot)) best_for_slot = std::move(a);
    }
    swapped[slot] = chosen[slot];
    if (!best_for_slot || !keeps_rules(*best_for_slot)) continue;
    alternatives.push_back(std::move(*best_for_slot));
  }
  std::stable_sort(alternatives.begin(), alternatives.end(), better);
  return alternatives;
}

std::vector<Candidate> ShrinkFov(std::span<const Candidate> candidates, double tolerance_deg) {
  std::vector<Candidate> shrunk;
  const double delta = tolerance_deg * std::numbers::pi / 180.0;
  for (const Candidate& c : candidates) {
    const SensorType& s = c.sensor;
    const double hfov = s.HorizontalFov(), vfov = s.VerticalFov();
    if (!(delta >= 0) || delta >= std::min(hfov, vfov))
      throw InputError(fmt::format(
          "--fov-tolerance {} deg must be at least 0 and below the smallest field of view ({:.2f} deg "
          "of {})",
          tolerance_deg, std::min(hfov, vfov) * 180.0 / std::numbers::pi, c.name));
    Candidate narrowed = c;
    narrowed.sensor.fx = s.width / (2.0 * std::tan((hfov - delta) / 2.0));
    narrowed.sensor.fy = s.height / (2.0 * std::tan((vfov - delta) / 2.0));
    shrunk.push_back(std::move(narrowed));
  }
  return shrunk;
}

void RobustnessOptions::Validate() const {
  if (!(fov_tolerance_deg >= 0) || !std::isfinite(fov_tolerance_deg))
    throw InputError(fmt::format("--fov-tolerance {} must be a number of degrees >= 0 — e.g. 3",
                                 fov_tolerance_deg));
  if (!(within >= 0 && within <= 1))
    throw InputError(fmt::format("--alternatives-within {} must lie in [0, 100] coverage points",
                                 100.0 * within));
}

Robustness AssessRobustness(const VisibilityFile& data, const std::vector<Selection>& results,
                            int index, const RayScene* rays, const ObserveOptions& observe,
                            const RobustnessOptions& options) {
  VANTAGE_CHECK(index >= 0 && static_cast<size_t>(index) < results.size());
  const Selection& result = results[static_cast<size_t>(index)];
  const CoverageEvaluator evaluator(data.observations, data.reference.size());
  Robustness r;
  r.result = index;
  r.failures = SensorFailures(evaluator, result.chosen, result.k, result.min_points);
  for (const SensorFailure& f : r.failures) {
    if (!r.worst || f.coverage < r.worst->coverage) r.worst = f;
  }
  r.alternatives_within = options.within;
  // A priced result (a budget, --cheapest) keeps its budget and ranks by cost with the prices it
  // was selected with; without them (a caller that has none) a budget result lists none.
  const bool priced = result.cost.has_value() && !options.costs.empty();
  if (priced || !result.budget) {
    AlternativeRules rules{.k = result.k,
                           .min_points = result.min_points,
                           .within = options.within,
                           .at_least = result.goal,
                           .kept = options.kept};
    if (priced) {
      rules.costs = options.costs;
      rules.budget = result.budget;
      rules.cheapest = !result.budget;
    }
    r.alternatives = NearOptimalAlternatives(evaluator, result.chosen, rules);
  }
  if (rays && !result.chosen.empty()) {
    std::vector<Candidate> chosen;
    for (uint32_t i : result.chosen) chosen.push_back(data.candidates.at(i));
    // Issue 15: a legal 2.5 deg camera failed the whole run here, after the ray cast, on the
    // default tolerance of 3 deg. The read-out is skipped instead, saying why.
    const auto narrowest = std::min_element(
        chosen.begin(), chosen.end(), [](const Candidate& a, const Candidate& b) {
          return std::min(a.sensor.HorizontalFov(), a.sensor.VerticalFov()) <
                 std::min(b.sensor.HorizontalFov(), b.sensor.VerticalFov());
        });
    const double narrowest_deg =
        std::min(narrowest->sensor.HorizontalFov(), narrowest->sensor.VerticalFov()) * 180.0 /
        std::numbers::pi;
    if (options.fov_tolerance_deg * std::numbers::pi / 180.0 >=
        std::min(narrowest->sensor.HorizontalFov(), narrowest->sensor.VerticalFov())) {
      r.fov_note = fmt::format(
          "fields of view -{:g} deg: skipped — chosen sensor {} has a field of view of {:.2f} "
          "deg, not wider than the tolerance (give a smaller --fov-tolerance for this read-out)",
          options.fov_tolerance_deg, narrowest->name, narrowest_deg);
      return r;
    }
    ObserveOptions shrunk_options = observe;
    shrunk_options.quality = data.quality;
    shrunk_options.physical = data.physical;
    shrunk_options.progress = nullptr;
    const std::vector<Observation> shrunk = Observe(
        *rays, data.reference, ShrinkFov(chosen, options.fov_tolerance_deg), shrunk_options);
    std::vector<uint32_t> all(shrunk.size());
    for (size_t i = 0; i < all.size(); ++i) all[i] = static_cast<uint32_t>(i);
    r.fov_tolerance_deg = options.fov_tolerance_deg;
    r.fov_shrunk_coverage = CoverageEvaluator(shrunk, data.reference.size())
                                .CoverageUnder(all, result.k, result.min_points);
  }
  return r;
}

}  // namespace vantage
